"""RAM, the split-step Pade parabolic equation (easypyram), beside BELLHOP: coherent TL of one
2-D environment on a receiver grid."""

from acoustics.ram.environment import RamEnvironment
from acoustics.ram.errors import RamInputError, RamRunError
from acoustics.ram.run import ram_run_bytes, ram_tl_db
from acoustics.ram.settings import RamSettings

__all__ = ["RamEnvironment", "RamInputError", "RamRunError", "RamSettings", "ram_run_bytes", "ram_tl_db"]
