"""tmakit's version, as grid files and study files record it (a module of its own: the builders
read it while planning, before anything needs xarray)."""

TMAKIT_VERSION = "0.1.0"
