"""KRAKEN's TL for a case, run through pelagic in the .venv-kraken environment (not tmakit's).

``python kraken_tl.py CASE.json OUT.json``: CASE holds the KRAKEN ``env`` and FIELD ``flp``
texts (the Acoustics Toolbox's formats); OUT gets ``tl_db`` (receiver depth x range, dB re 1 m),
the receiver axes, the number of modes and pelagic's version. This script is the only place
pelagic is imported; it runs as its own process.
"""

import json
import sys
import tempfile
from pathlib import Path

import numpy as np
import pelagic


def main(case_path: str, out_path: str) -> int:
    case = json.loads(Path(case_path).read_text())
    with tempfile.TemporaryDirectory() as tmp:
        env, flp = Path(tmp) / "case.env", Path(tmp) / "case.flp"
        env.write_text(case["env"])
        flp.write_text(case["flp"])
        result = pelagic.kraken.load(str(env), flp=str(flp)).run()
    freq = result.frequencies[0]
    field = freq.field
    magnitude = np.abs(np.asarray(field.pressure)[0])  # (receiver depth, range) of the one source
    with np.errstate(divide="ignore"):
        tl = -20.0 * np.log10(magnitude)
    tl = np.where(np.isfinite(tl), tl, 999.0)
    Path(out_path).write_text(json.dumps({
        "tl_db": tl.tolist(), "receiver_depth_m": np.asarray(field.depths_m).tolist(),
        "receiver_range_m": np.asarray(field.ranges_m).tolist(),
        "modes": int(sum(np.asarray(p.modes.wavenumbers).size for p in freq.profiles)),
        "pelagic": pelagic.__version__}))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
