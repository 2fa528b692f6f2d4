"""The experiments ``tmakit experiment`` runs: the papers' Monte Carlo studies, their scenarios and
plots, and the studies on the built-in areas. They build tables and run the trackers, so they stand
above both ``acoustics`` and ``tracker`` (tests/test_imports.py).

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
  by ``python -m tools.studies.schmidt``.
- `shelf`: tracking in the shelf-break area with its bearing-dependent grid and with the
  origin's column over a flat bottom (``tmakit experiment shelf``); `shelf_plot` draws it.
- `depth`: a submarine off its class's table depth, tracked with the class's depth, the true
  depth and the depth unknown (``tmakit experiment depth``); `depth_plot` draws it.
- `follow`: tracking with an atlas that follows the observer against one grid
  (``tmakit experiment follow``).
- `kerror`: tracking with the K error a sensitivity study measured, per bearing and range or as
  one number (``tmakit experiment kerror``).

Data flows one way: the plots import the data definitions (scenarios, columns), never the
experiments; an experiment imports its plot module only where it draws.
"""
