"""tmakit's tables inside Stone Soup (``pip install tmakit[stonesoup]``): a measurement model for
bearing and band levels whose level function is tmakit's (``model``), the probability of
detection from the same tables and the sonar with a Bernoulli particle updater that uses it
(``detection``), and converters between tmakit's measurement and track CSVs and Stone Soup's
detections and tracks (``convert``); ``example`` runs Stone Soup's particle filter beside
``tmakit track --method rpf`` (docs/stonesoup.md). Nothing else of tmakit imports this package.
"""
