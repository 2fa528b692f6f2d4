"""RAM, the split-step Pade parabolic equation (easypyram), beside BELLHOP: coherent TL of one
2-D environment on a receiver grid."""

from envdata.lazyexports import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(__name__, {
    "acoustics.ram.environment": ["RamEnvironment"],
    "acoustics.ram.errors": ["RamInputError", "RamRunError"],
    "acoustics.ram.run": ["ram_run_bytes", "ram_tl_db"],
    "acoustics.ram.settings": ["RamSettings"],
})
