"""How a grid is drawn: every figure, on the grid's typed face (``acoustics.grid.face``)."""
