"""pelagic's BELLHOP on tmakit's own runs, in the .venv-kraken environment (not tmakit's).

``python pelagic_bellhop.py FOLDER OUT.json``: FOLDER holds one folder per run, each with the
run's ``run.env`` and the files beside it (``run.bty``, ``run.ssp``, ``run.sbp``), as tmakit
writes them for ``bellhop.exe``. Each run is loaded and run by pelagic in this process; its
result is written beside its inputs as ``pelagic.npz``: a TL run's pressure (receiver depth x
range of the first source), an arrivals run's arrivals (per receiver, in pelagic's order: its
range and depth, its count; per arrival the amplitude, the delay's imaginary part, the angle at
the receiver and the surface reflections). OUT gets, per run, the wall and CPU time of the run
(loading and solving, not writing) and pelagic's version. This script is the only place that
imports pelagic (GPL-3.0); it runs as its own process, as ``kraken_tl.py`` does.
"""

import json
import resource
import sys
import time
from pathlib import Path

import numpy as np
import pelagic


def cpu_seconds() -> float:
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def main(folder: str, out_path: str) -> int:
    runs = {}
    for run_dir in sorted(p for p in Path(folder).iterdir() if p.is_dir()):
        start, cpu = time.perf_counter(), cpu_seconds()
        result = pelagic.bellhop.load(str(run_dir / "run.env")).run()
        runs[run_dir.name] = {"seconds": time.perf_counter() - start, "cpu_seconds": cpu_seconds() - cpu}
        if result.field is not None:
            np.savez(run_dir / "pelagic.npz", pressure=np.asarray(result.field.pressure)[0])
        else:
            arr = result.arrivals
            np.savez(run_dir / "pelagic.npz", range_m=np.asarray(arr.ranges_m), depth_m=np.asarray(arr.depths_m),
                     count=np.diff(np.asarray(arr.arrival_offset)), amplitude=np.asarray(arr.amplitude),
                     delay_imag_s=np.asarray(arr.attenuation_time_s),
                     receiver_angle_deg=np.asarray(arr.receiver_angle_degrees),
                     surface_bounces=np.asarray(arr.top_bounces))
    Path(out_path).write_text(json.dumps({"pelagic": pelagic.__version__, "runs": runs}))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
