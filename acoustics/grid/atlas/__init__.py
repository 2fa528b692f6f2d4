"""An atlas: the bearing-dependent tables of many observer positions and months, in one Zarr store.

``format`` (what the store is on disk: layout, template, table writes, checks), ``store`` (an
open store, `AtlasStore`: it holds the tables and reads them), ``weights`` (the positions around
an observer and their weights), ``sample`` (values where asked, ``tmakit atlas sample``) and
``follow`` (the face the trackers take: the tables around the observer at every cycle). The
way in for tables is ``acoustics.open_tables``; the store itself is opened by ``open_store``
for what only a store answers (its positions, months and coverage).
"""
