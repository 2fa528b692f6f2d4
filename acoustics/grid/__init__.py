"""What a grid is: the dataset and its contract, its files, and the one typed face the trackers,
the simulator, the figures and the commands read it through (``tables``), with its lookup rules
(``depthinterp``, ``radialinterp``) and detection maps (``detectionmap``)."""
