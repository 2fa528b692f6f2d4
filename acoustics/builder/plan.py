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
from acoustics.builder.bandruns import (
    SourcePattern,
    freq_key,
    run_frequencies_hz,
    run_pattern,
    run_timeout_s,
    surface_acts,
)
from acoustics.builder.runs import Run
from envdata.area import Area, TlMode

#: Classes at least this deep get K at the observer by reciprocity (one source at the observer
#: serves them all); shallower ones directly. Measured on ocean-deep: reciprocity is within 0.1 dB
#: (median) for the 200 m class, 2.3-2.4 dB off for the 6-8 m classes: BELLHOP's incoherent
#: beams are not reciprocal next to the pressure-release surface (docs/sensitivity.md,
#: bench/bench_sensitivity.py).
RECIPROCITY_MIN_DEPTH_M = 50.0


def run_spec(area: Area, *, title: str, freq_hz: float, source_depths_m, receiver_depths_m, ranges_m,
             fan: tuple[int, float, float] | None = None, pattern: SourcePattern | None = None,
             arrivals: bool = False, mirror_surface: bool = False) -> RunSpec:
    """One run at the area's ``[propagation]`` settings; ``fan`` = (beams, first, last angle in
    deg) for a slice of the area's fan (default the whole fan); ``pattern`` the source's beam
    pattern (the surface at a target that is the source, ``bandruns.run_pattern``);
    ``arrivals`` for an arrivals run and ``mirror_surface`` for its water mirrored above the
    surface (the surface at a target that is the receiver, ``acoustics.builder.surfaceimage``).

    The semicoherent mode runs as incoherent beams: its Lloyd factor is the pattern, band-averaged
    and only at a target's end (BELLHOP's own 'S' would apply it at every source, the observer
    included, at one frequency).
    """
    prop = area.propagation
    n_beams, a1, a2 = fan if fan is not None else (prop.n_beams, prop.angle_min_deg, prop.angle_max_deg)
    mode = TlMode.INCOHERENT if prop.mode is TlMode.SEMICOHERENT else prop.mode
    return RunSpec(title=title, freq_hz=float(freq_hz),
                   source_depth_m=tuple(float(z) for z in source_depths_m),
                   receiver_depth_m=tuple(float(z) for z in receiver_depths_m),
                   range_m=tuple(float(r) for r in ranges_m), mode=mode,
                   beam_type=prop.beam_type, n_beams=n_beams, angle_min_deg=a1, angle_max_deg=a2,
                   absorption=prop.absorption, source_pattern=pattern.pairs if pattern is not None else None,
                   arrivals=arrivals, mirror_surface=mirror_surface)


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


def source_speed_mps(area: Area, depth_m: float) -> float:
    """Sound speed at ``depth_m`` in a flat area's one profile, m/s."""
    return float(area.water.ssp.speed_at(depth_m))


def source_runs(area: Area, source_depths_m, freqs_hz=None) -> list[tuple[float, float, SourcePattern | None]]:
    """(source depth, run frequency, source pattern) of every run from ``source_depths_m``: a
    class's depth runs each of its bands' frequencies with that class's pattern in the band
    (``bandruns.run_pattern``; classes at one depth with one spectrum share it), any other depth
    (the observer's) without one. ``freqs_hz`` restricts the runs to these frequencies."""
    keep = None if freqs_hz is None else {freq_key(f) for f in freqs_hz}
    out: dict[tuple[float, float, str], tuple[float, float, SourcePattern | None]] = {}
    for sd in source_depths_m:
        sd = float(sd)
        classes = [c for c in area.classes if c.depth_m == sd]
        for band in area.bands:
            for f in run_frequencies_hz(area, band):
                f = freq_key(f)
                if keep is not None and f not in keep:
                    continue
                patterns = [run_pattern(area, c, band, f, sd, source_speed_mps(area, sd)) for c in classes] or [None]
                for pattern in patterns:
                    out.setdefault((sd, f, pattern.key if pattern is not None else ""), (sd, f, pattern))
    return list(out.values())


def plan_runs(area: Area, source_depths_m=None, receiver_depths=None, *, balance: bool = True,
              pieces: int | None = None, freqs_hz=None) -> list[Run]:
    """The BELLHOP runs for ``area``: one per (source depth, run frequency, source pattern).

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
    # a frequency shared by two bands (an edge) is one run, when the two ask for one pattern
    groups = source_runs(area, source_depths_m, freqs_hz)
    n_pieces = [pieces or 1] * len(groups)
    if pieces is None and balance and len(groups) % 2 == 1:
        n_pieces[-1] = 2
    runs = []
    for (sd, f, pattern), n in zip(groups, n_pieces):
        slices = fan_slices(prop.n_beams, prop.angle_min_deg, prop.angle_max_deg, n)
        for part, (n_beams, a1, a2) in enumerate(slices):
            spec = run_spec(area, title=f"tmakit {area.name} sd={sd:g} m f={f:.3f} Hz part {part + 1}/{len(slices)}",
                            freq_hz=f, source_depths_m=(sd,), receiver_depths_m=receiver_depths,
                            ranges_m=ranges, fan=(n_beams, a1, a2), pattern=pattern)
            runs.append(Run(env=env_text(area, spec), files=tuple(spec.side_files().items()), freq_hz=f,
                            source_depth_m=sd, part=part, n_parts=len(slices), n_beams=n_beams,
                            pattern_key=pattern.key if pattern is not None else "",
                            timeout_s=run_timeout_s(area, n_beams, len(spec.receiver_depth_m) * len(ranges))))
    return runs


def near_surface(area: Area, cls) -> bool:
    """Whether the surface acts on ``cls`` at its depth in any band (``bandruns.surface_acts``)."""
    c = source_speed_mps(area, cls.depth_m)
    return any(surface_acts(area, band, cls.depth_m, c) for band in area.bands)


def k_runs(area: Area, reciprocity_min_depth_m: float = RECIPROCITY_MIN_DEPTH_M
           ) -> tuple[list[float], list[float], dict[str, tuple[int, int]]]:
    """Source depths, receiver depths and, per class, the (source, receiver) index of its TL for
    K at the observer: classes at or below ``reciprocity_min_depth_m`` by reciprocity (source at
    the observer, receiver at the class depth), the others directly (source at the class depth).
    ``0`` puts every class on reciprocity, ``math.inf`` none; a class within the surface's reach
    (``near_surface``) always goes directly, so that its runs carry the surface at its end."""
    obs = area.observer.depth_m

    def by_reciprocity(cls) -> bool:
        return cls.depth_m >= reciprocity_min_depth_m and not near_surface(area, cls)

    deep = sorted({c.depth_m for c in area.classes if by_reciprocity(c)})
    shallow = sorted({c.depth_m for c in area.classes if not by_reciprocity(c)})
    sources = sorted(set(shallow) | ({obs} if deep else set()))
    receivers = sorted({obs} | set(deep))
    where = {}
    for cls in area.classes:
        if by_reciprocity(cls):
            where[cls.name] = (sources.index(obs), receivers.index(cls.depth_m))  # reciprocity
        else:
            where[cls.name] = (sources.index(cls.depth_m), receivers.index(obs))  # direct
    return sources, receivers, where


def plan_k_runs(area: Area, reciprocity_min_depth_m: float = RECIPROCITY_MIN_DEPTH_M
                ) -> tuple[list[Run], dict[tuple[str, str, float], str]]:
    """The runs of K at the observer, and the run key of each (class, band, run frequency)'s TL.

    Per run frequency, one run holds every source of ``k_runs`` without a source pattern
    (BELLHOP traces each source on its own; one run spares the start-up of several), and each
    source with a pattern (a class within the surface's reach) has a run of its own: a pattern
    file serves every source of its run."""
    sources, receivers, where = k_runs(area, reciprocity_min_depth_m)
    ranges = area.grid.range_m()
    prop = area.propagation
    runs: dict[str, Run] = {}
    key_of: dict[tuple[str, str, float], str] = {}

    def add(freq: float, depths: list[float], pattern: SourcePattern | None) -> str:
        spec = run_spec(area, title=f"tmakit sensitivity {area.name} f={freq:.3f} Hz", freq_hz=freq,
                        source_depths_m=depths, receiver_depths_m=receivers, ranges_m=ranges, pattern=pattern)
        run = Run(env=env_text(area, spec), files=tuple(spec.side_files().items()), freq_hz=freq,
                  source_depth_m=float(depths[0]), all_sources=True, n_beams=prop.n_beams,
                  pattern_key=pattern.key if pattern is not None else "",
                  timeout_s=run_timeout_s(area, spec.n_beams, len(depths) * len(receivers) * len(ranges)))
        runs.setdefault(run.key, run)
        return run.key

    for band in area.bands:
        for f in map(freq_key, run_frequencies_hz(area, band)):
            shared = None
            for cls in area.classes:
                isrc, _ = where[cls.name]
                sd = sources[isrc]
                pattern = run_pattern(area, cls, band, f, sd, source_speed_mps(area, sd)) \
                    if sd == cls.depth_m else None
                if pattern is None:
                    shared = shared or add(f, sources, None)
                    key_of[(cls.name, band.name, f)] = shared
                else:  # its own run; its one source is index 0 there
                    key_of[(cls.name, band.name, f)] = add(f, [sd], pattern)
    return list(runs.values()), key_of
