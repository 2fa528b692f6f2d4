"""The one plan for BELLHOP work: every run's settings filled from the area in one place.

``run_spec`` takes the area's ``[propagation]`` settings (mode, beams, fan, absorption) into a
run; the flat builder (``plan_runs``: one run per source depth and run frequency, the beam fan
cut in two where that balances two workers), the radial builder, the sensitivity members and
``acoustics.builder.kobserver`` (K at the observer, with or without reciprocity:
``plan_k_runs``) all make their runs through it.
"""

from __future__ import annotations

import numpy as np

from acoustics.bellhop.envfile import RunSpec, env_text
from acoustics.builder.bandruns import freq_key, run_frequencies_hz, run_timeout_s
from acoustics.builder.runs import Run
from envdata.area import Area

#: Classes at least this deep get K at the observer by reciprocity (one source at the observer
#: serves them all); shallower ones directly. Measured on ocean-deep: reciprocity is within 0.1 dB
#: (median) for the 200 m class, 2.3-2.4 dB off for the 6-8 m classes: BELLHOP's incoherent
#: beams are not reciprocal next to the pressure-release surface (docs/sensitivity.md,
#: bench/bench_sensitivity.py).
RECIPROCITY_MIN_DEPTH_M = 50.0


def run_spec(area: Area, *, title: str, freq_hz: float, source_depths_m, receiver_depths_m, ranges_m,
             fan: tuple[int, float, float] | None = None) -> RunSpec:
    """One run at the area's ``[propagation]`` settings; ``fan`` = (beams, first, last angle in
    deg) for a slice of the area's fan (default the whole fan)."""
    prop = area.propagation
    n_beams, a1, a2 = fan if fan is not None else (prop.n_beams, prop.angle_min_deg, prop.angle_max_deg)
    return RunSpec(title=title, freq_hz=float(freq_hz),
                   source_depth_m=tuple(float(z) for z in source_depths_m),
                   receiver_depth_m=tuple(float(z) for z in receiver_depths_m),
                   range_m=tuple(float(r) for r in ranges_m), mode=prop.mode,
                   beam_type=prop.beam_type, n_beams=n_beams, angle_min_deg=a1, angle_max_deg=a2,
                   absorption=prop.absorption)


def receiver_depths_m(area: Area) -> np.ndarray:
    """Grid depths plus the observer depth (so that K(r) needs no depth interpolation)."""
    return np.unique(np.append(area.depth_m(), area.observer.depth_m))


def fan_slices(n_beams: int, angle_min_deg: float, angle_max_deg: float,
               pieces: int) -> list[tuple[int, float, float]]:
    """A beam fan cut into ``pieces`` slices: (beams, first angle, last angle) of each.

    The slices keep the fan's angular spacing, and BELLHOP's beam amplitudes depend on the fan
    only through that spacing, so the slices' intensities (incoherent, semicoherent) or
    pressures (coherent) add up to the whole fan's. BELLHOP's automatic count (0) is not cut.
    """
    if pieces == 1 or n_beams < 2 * pieces:
        return [(n_beams, angle_min_deg, angle_max_deg)]
    step = (angle_max_deg - angle_min_deg) / (n_beams - 1)
    cuts = [round(j * n_beams / pieces) for j in range(pieces + 1)]
    return [(hi - lo, angle_min_deg + lo * step, angle_min_deg + (hi - 1) * step)
            for lo, hi in zip(cuts[:-1], cuts[1:])]


def plan_runs(area: Area, source_depths_m=None, receiver_depths=None, *, balance: bool = True,
              pieces: int | None = None, freqs_hz=None) -> list[Run]:
    """The BELLHOP runs for ``area``: one per (source depth, run frequency).

    With ``balance``, an odd number of runs has its last run cut into two halves of the beam
    fan (see ``fan_slices``), so that two workers finish together; the choice depends only on
    the area, never on the number of workers, so the numbers do not either. ``pieces`` cuts
    every run into that many slices instead. ``freqs_hz`` runs these frequencies in place of the
    bands' run frequencies (``--model auto``: BELLHOP's share, ``acoustics.builder.modelchoice``).
    """
    prop = area.propagation
    if source_depths_m is None:
        source_depths_m = sorted({cls.depth_m for cls in area.classes})
    if receiver_depths is None:
        receiver_depths = receiver_depths_m(area)
    ranges = tuple(float(r) for r in area.grid.range_m())
    # a frequency shared by two bands (an edge) is one run
    if freqs_hz is None:
        freqs_hz = [f for band in area.bands for f in run_frequencies_hz(area, band)]
    groups = list(dict.fromkeys((float(sd), freq_key(f)) for sd in source_depths_m for f in freqs_hz))
    n_pieces = [pieces or 1] * len(groups)
    if pieces is None and balance and len(groups) % 2 == 1:
        n_pieces[-1] = 2
    runs = []
    for (sd, f), n in zip(groups, n_pieces):
        slices = fan_slices(prop.n_beams, prop.angle_min_deg, prop.angle_max_deg, n)
        for part, (n_beams, a1, a2) in enumerate(slices):
            spec = run_spec(area, title=f"tmakit {area.name} sd={sd:g} m f={f:.3f} Hz part {part + 1}/{len(slices)}",
                            freq_hz=f, source_depths_m=(sd,), receiver_depths_m=receiver_depths,
                            ranges_m=ranges, fan=(n_beams, a1, a2))
            runs.append(Run(env=env_text(area, spec), freq_hz=f, source_depth_m=sd, part=part,
                            n_parts=len(slices), n_beams=n_beams,
                            timeout_s=run_timeout_s(area, n_beams, len(spec.receiver_depth_m) * len(ranges))))
    return runs


def k_runs(area: Area, reciprocity_min_depth_m: float = RECIPROCITY_MIN_DEPTH_M
           ) -> tuple[list[float], list[float], dict[str, tuple[int, int]]]:
    """Source depths, receiver depths and, per class, the (source, receiver) index of its TL for
    K at the observer: classes at or below ``reciprocity_min_depth_m`` by reciprocity (source at
    the observer, receiver at the class depth), the others directly (source at the class depth).
    ``0`` puts every class on reciprocity, ``math.inf`` none."""
    obs = area.observer.depth_m
    deep = sorted({c.depth_m for c in area.classes if c.depth_m >= reciprocity_min_depth_m})
    shallow = sorted({c.depth_m for c in area.classes if c.depth_m < reciprocity_min_depth_m})
    sources = sorted(set(shallow) | ({obs} if deep else set()))
    receivers = sorted({obs} | set(deep))
    where = {}
    for cls in area.classes:
        if cls.depth_m >= reciprocity_min_depth_m:
            where[cls.name] = (sources.index(obs), receivers.index(cls.depth_m))  # reciprocity
        else:
            where[cls.name] = (sources.index(cls.depth_m), receivers.index(obs))  # direct
    return sources, receivers, where


def plan_k_runs(area: Area, reciprocity_min_depth_m: float = RECIPROCITY_MIN_DEPTH_M) -> list[Run]:
    """The runs of K at the observer: one per run frequency, every source of ``k_runs`` in it
    (BELLHOP traces each source on its own; one run spares the start-up of several)."""
    sources, receivers, _ = k_runs(area, reciprocity_min_depth_m)
    ranges = area.grid.range_m()
    prop = area.propagation
    runs = []
    freqs = dict.fromkeys(freq_key(f) for band in area.bands for f in run_frequencies_hz(area, band))
    for f in freqs:
        spec = run_spec(area, title=f"tmakit sensitivity {area.name} f={f:.3f} Hz", freq_hz=f,
                        source_depths_m=sources, receiver_depths_m=receivers, ranges_m=ranges)
        runs.append(Run(env=env_text(area, spec), freq_hz=f, source_depth_m=float(sources[0]),
                        all_sources=True, n_beams=prop.n_beams,
                        timeout_s=run_timeout_s(area, spec.n_beams,
                                                len(sources) * len(receivers) * len(ranges))))
    return runs
