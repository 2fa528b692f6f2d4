"""What determines a sensitivity study's numbers, checked before anything runs, and its hash."""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass

import numpy as np

from acoustics.builder.plan import RECIPROCITY_MIN_DEPTH_M
from acoustics.sensitivity.perturb import check_perturbations
from acoustics.sensitivity.perturbspec import Perturbation
from acoustics.version import TMAKIT_VERSION
from envdata.area import Area
from envdata.datafiles import input_file_digests
from envdata.errors import InputError

STUDY_FORMAT_VERSION = 1


@dataclass(frozen=True, slots=True, kw_only=True)
class StudySpec:
    """Everything that determines a study's numbers.

    Parameters
    ----------
    area : Area
        The nominal area.
    perturbations : tuple of Perturbation
        What is uncertain; checked at +-4 sd on the nominal area.
    members : int
        Ensemble size, in [1, 100000].
    seed : int
        Member m draws from ``np.random.default_rng([seed, m])``; in [0, 2^63).
    tl : bool
        Full grid per member, keeping TL over depth and range.
    reciprocity_min_depth_m : float
        Classes at least this deep get K by reciprocity, m.
    """

    area: Area
    perturbations: tuple[Perturbation, ...]
    members: int
    seed: int = 0
    tl: bool = False
    reciprocity_min_depth_m: float = RECIPROCITY_MIN_DEPTH_M

    def __post_init__(self) -> None:
        if not 1 <= self.members <= 100_000:
            raise InputError(f"members: must be in [1, 100000], got {self.members}")
        if not 0 <= self.seed < 2 ** 63:
            raise InputError(f"seed: must be in [0, 2^63), got {self.seed}")
        if not (np.isfinite(self.reciprocity_min_depth_m) and self.reciprocity_min_depth_m >= 0):
            raise InputError(f"reciprocity_min_depth_m: must be >= 0 m, got {self.reciprocity_min_depth_m}")
        check_perturbations(self.area, list(self.perturbations))

    def digest(self, bellhop_sha256: str | None) -> str:
        """sha256 of the spec, the study format, tmakit's version and the BELLHOP binary."""
        payload = {"area": self.area.to_dict(), "perturbations": [p.to_dict() for p in self.perturbations],
                   "seed": self.seed, "tl": self.tl, "reciprocity_min_depth_m": self.reciprocity_min_depth_m,
                   "format": STUDY_FORMAT_VERSION, "tmakit": TMAKIT_VERSION, "bellhop_sha256": bellhop_sha256,
                   "input_files": input_file_digests(self.area.water)}
        return hashlib.sha256(json.dumps(payload, sort_keys=True).encode()).hexdigest()
