"""A short simulated track on the tiny grid, through `tmakit simulate`, for the tests that read
a measurement file and its truth (the track plot, the Stone Soup converters)."""

from __future__ import annotations

from pathlib import Path

BAD = Path(__file__).parent.parent / "data" / "malformed"


def simulate_on_tiny_grid(grid_file: Path, folder: Path) -> tuple[Path, str]:
    """The simulator's folder (measurements.csv, truth.csv) of a target of the grid's first class,
    and that class's name."""
    import xarray as xr

    from tools.cli import main

    with xr.open_dataset(grid_file) as g:
        cls, cls_depth = str(g["class"].values[0]), float(g["source_depth_m"].values[0])
    sc = folder / "sc.toml"
    sc.write_text((BAD / "scenario" / "unknown_key.toml").read_text()
                  .replace('colour = "red"', "").replace('"TV"', f'"{cls}"')
                  .replace("depth_m = 8.0", f"depth_m = {cls_depth}")
                  .replace("130.0", "150.0").replace("10000.0", "3000.0"))
    assert main(["simulate", str(sc), "--grid", str(grid_file), "--out", str(folder / "sim"), "--seed", "2"]) == 0
    return folder / "sim", cls
