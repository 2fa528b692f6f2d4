"""Plots of the Grinenkov & Mashoshin experiment (analogues of Figs. 4-17).

Figures come from `acoustics.plots.figures.new_figure` (the Agg canvas, no pyplot state) and are
written with `acoustics.plots.figures.save_figure`.
"""

from __future__ import annotations

from pathlib import Path

from acoustics.plots.figures import new_figure, save_figure

#: Resolution of the PNG files, dots per inch.
DPI = 90


def plot_experiment(df, chunk, sc, names, out: Path, run: int = 0) -> list[str]:
    """RMS curves per hypothesis (Figs. 12-17) and one run's levels, SNR and estimates (4-11).

    ``run`` is the index within ``chunk`` of the run shown in ``run.png``.
    """
    err, est, sim = chunk
    files = []
    fig = new_figure(figsize=(14, 4), layout="constrained")
    axes = fig.subplots(1, 3)
    for ax, col, scale, label in zip(axes, ("course_rms_deg", "speed_rms_mps", "range_rms_m"),
                                     (1.0, 1.0, 1e-3),
                                     ("course RMS, deg", "speed RMS, m/s", "range RMS, km")):
        for name in names:
            d = df[df["class"] == name]
            ax.plot(d.t_s / 60.0, d[col] * scale, label=name)
        ax.set_xlabel("time since detection, min")
        ax.set_ylabel(label)
        ax.grid(True)
    axes[0].legend(title="class hypothesis")
    fig.suptitle(f"{sc.name}: RMS errors of smoothed estimates (eqs. 32-34)")
    files.append(str(save_figure(fig, out / "rms.png", dpi=DPI)))
    # one run of the chunk, true class hypothesis
    t = sim.t_s / 60.0
    ci = names.index(sc.target_class)
    fig = new_figure(figsize=(14, 7), layout="constrained")
    axes = fig.subplots(2, 3)
    for j, band in enumerate(sim.band_names):
        axes[0, 0].plot(t, sim.level_true_db[run, :, j], "k-")
        axes[0, 0].plot(t, sim.level_db[run, :, j], ".", ms=2, label=band)
        axes[0, 1].plot(t, sim.snr_db[run, :, j], label=band)
    axes[0, 0].set_ylabel("band level, dB re 1 uPa")
    axes[0, 1].set_ylabel("SNR 10 lg q, dB")
    axes[0, 0].legend()
    axes[0, 2].plot(t, sim.bearing_true_deg[run], "g-", t, sim.bearing_deg[run], "b.", ms=2)
    axes[0, 2].set_ylabel("bearing, deg")
    for ax, key, truth, scale, label in (
            (axes[1, 0], "range", sim.range_m[run], 1e-3, "range, km"),
            (axes[1, 1], "course", sim.course_deg[run], 1.0, "course, deg"),
            (axes[1, 2], "speed", sim.speed_mps[run], 1.0, "speed, m/s")):
        ax.plot(t, truth * scale, "g-", label="true")
        ax.plot(t, est[key][ci, run] * scale, "r-", label="smoothed")
        ax.set_ylabel(label)
        ax.set_xlabel("time, min")
        ax.grid(True)
    axes[1, 0].legend()
    fig.suptitle(f"{sc.name}: the design's centre run, hypothesis {sc.target_class} "
                 f"(cf. Figs. 4-11)")
    files.append(str(save_figure(fig, out / "run.png", dpi=DPI)))
    return files
