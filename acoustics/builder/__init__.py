"""How a grid is built: the run plan, the BELLHOP runs on threads or a Dask cluster (``executor``,
``runs``), what flat and radial builders share (``bandruns``), the builders (``flat``,
``radial``) and the grid file built once and resumed (``gridfile``)."""
