"""Run `arlpy_tl.py` in the cross-check environment and read back arlpy's TL.

The environment is .venv-arlpy (arlpy 1.9.3 with its numpy<2, scipy<1.14), made by
``make test``, which gives its interpreter in ``ARLPY_PYTHON``. tmakit's own environment does
not hold arlpy.
"""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import numpy as np

from acoustics.bellhop.exe import find_bellhop
from bench.crosscheck.sidevenv import CrosscheckError, side_python

SCRIPT = Path(__file__).with_name("arlpy_tl.py")


def arlpy_python() -> str:
    """The cross-check environment's interpreter; a failure (not a skip) when there is none."""
    return side_python("ARLPY_PYTHON", ".venv-arlpy", "arlpy 1.9.3")


def arlpy_tl_db(case: dict, tmp_path: Path, *, timeout_s: float = 600.0) -> dict:
    """TL of ``case`` (see `arlpy_tl.py`) from arlpy driving tmakit's BELLHOP executable.

    Returns the script's output with ``tl_db`` (receiver depth x range, dB) and the receiver
    axes as arrays. A failure of the script raises `CrosscheckError` with its message.
    """
    case_path, out_path = tmp_path / "arlpy-case.json", tmp_path / "arlpy-tl.json"
    case_path.write_text(json.dumps(case))
    command = [arlpy_python(), str(SCRIPT), str(case_path), str(out_path),
               "--bellhop", str(find_bellhop().path)]
    proc = subprocess.run(command, capture_output=True, text=True, timeout=timeout_s)
    if proc.returncode != 0:
        raise CrosscheckError(f"{' '.join(command)} exited with {proc.returncode}:\n{proc.stderr[-4000:]}"
                              f"\narlpy printed:\n{proc.stdout[-2000:]}")
    out = json.loads(out_path.read_text())
    for key in ("tl_db", "receiver_depth_m", "receiver_range_m"):
        out[key] = np.asarray(out[key], dtype=float)
    return out
