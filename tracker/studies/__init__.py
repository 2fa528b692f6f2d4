"""The papers' Monte Carlo studies, their scenarios and their plots, on top of the trackers.

Modules (import them directly; nothing is imported here, so importing the package loads
neither the trackers nor matplotlib):

- `gm`: the Grinenkov & Mashoshin section 4 study, the n x n x n design of eqs. 32-34 over the
  ML tracker (``tmakit experiment gm``); `gm_plot` draws its RMS and one-run figures.
- `idm`: the Iglesis & de Montella section 5 study, RMSE of the particle filters against the
  Cramér-Rao bounds (``tmakit experiment idm``); `idm_scenarios` holds its scenarios,
  `idm_columns` the filter names of its CSV and JSON columns, and `idm_plot` draws its RMSE
  figure.
- `schmidt`: the Schmidt et al. worked example of a stationary target located from bearings
  (first leg, error quadrilateral, Monte Carlo mean), written to ``docs/results/locate.json``
  by ``python -m tracker.studies.schmidt``.
- `shelf`: tracking in the shelf-break area with its bearing-dependent grid and with the
  origin's column over a flat bottom (``tmakit experiment shelf``); `shelf_plot` draws it.

Data flows one way: the plots import the data definitions (scenarios, columns), never the
experiments; an experiment imports its plot module only where it draws.
"""
