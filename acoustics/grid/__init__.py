"""What tables are: the grid dataset and its contract (``dataset``, ``schema``, ``formats``), its
files (``io``), the one way in (``opentables``: a grid file, an atlas store or a dataset, checked
by ``checked``), the face every reader asks (``face``: ``Tables``) and its implementations
(``flattables``, ``radialtables``, an atlas's ``atlas/follow``), the filters' level model
(``levelprofile``), K at another target depth (``targetdepth``), the lookup kernels (``lookup``),
and what is drawn or summarised from a face (``detectionmap``, ``summary``, ``compare``).
``atlas/`` is an atlas's store: its format, reading, weights, sampling and following."""
