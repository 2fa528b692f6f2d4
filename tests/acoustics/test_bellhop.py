"""The real BELLHOP: analytic cases, the .shd reader, and failures reported with BELLHOP's words."""

from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

import envdata
from acoustics.bellhop.envfile import RunSpec, env_text
from acoustics.bellhop.exe import find_bellhop
from acoustics.bellhop.runner import run_env
from acoustics.bellhop.shdfile import read_shd, tl_from_pressure
from acoustics.errors import BellhopError
from tests.fixtures.isovelocity import isovelocity_doc

pytestmark = pytest.mark.bellhop


def isovelocity_area(depth_m: float = 5000.0) -> envdata.Area:
    """Isovelocity water over an impedance-matched bottom: only the surface reflects."""
    return envdata.parse_area(isovelocity_doc("iso", depth_m=depth_m, observer_m=100.0, freq_hz=200.0,
                                              range_max_m=3000.0, range_step_m=100.0, depth_step_m=50.0), "iso")


def lloyd_mirror(mode: envdata.TlMode, beam_type: str):
    area = isovelocity_area()
    zs, zr = 100.0, np.array([50.0, 150.0, 300.0])
    r = np.arange(500.0, 3001.0, 100.0)
    spec = RunSpec(title="lloyd", freq_hz=200.0, source_depth_m=(zs,), receiver_depth_m=tuple(zr),
                   range_m=tuple(r), mode=mode, beam_type=beam_type, n_beams=3000,
                   angle_min_deg=-89.0, angle_max_deg=89.0, absorption=envdata.Absorption.NONE)
    tl = tl_from_pressure(run_env(env_text(area, spec)).field.pressure[0], 200.0)
    rr, zz = np.meshgrid(r, zr)
    r1 = np.hypot(rr, zz - zs)  # direct path
    r2 = np.hypot(rr, zz + zs)  # surface image, reflection coefficient -1
    return tl, r1, r2


def test_incoherent_tl_matches_lloyd_mirror_intensity_sum():
    tl, r1, r2 = lloyd_mirror(envdata.TlMode.INCOHERENT, "G")
    expected = -10 * np.log10(1 / r1 ** 2 + 1 / r2 ** 2)
    # 0.5 dB: geometric beams over 3000 rays reproduce spherical spreading to a few tenths of a dB
    assert_allclose(tl, expected, rtol=0, atol=0.5)


def test_coherent_tl_matches_lloyd_mirror_away_from_nulls():
    tl, r1, r2 = lloyd_mirror(envdata.TlMode.COHERENT, "B")
    k = 2 * np.pi * 200.0 / 1500.0
    p = np.exp(1j * k * r1) / r1 - np.exp(1j * k * r2) / r2
    expected = -20 * np.log10(np.abs(p))
    # compare where the two paths do not nearly cancel (within 10 dB of the direct-path level);
    # 1.5 dB: Gaussian beams smear the interference pattern slightly
    keep = expected < 20 * np.log10(r1) + 10
    assert keep.sum() > 20
    assert_allclose(tl[keep], expected[keep], rtol=0, atol=1.5)


def test_shd_reader_returns_the_requested_grid(tmp_path):
    area = isovelocity_area(1000.0)
    spec = RunSpec(title="shape", freq_hz=100.0, source_depth_m=(20.0, 70.0), receiver_depth_m=(10.0, 55.0, 90.0),
                   range_m=(100.0, 250.0, 400.0, 1000.0), n_beams=200)
    run_env(env_text(area, spec), keep_dir=tmp_path)
    field = read_shd(tmp_path / "tmakit.shd")
    assert field.pressure.shape == (2, 3, 4)
    assert_allclose(field.source_depth_m, [20.0, 70.0])
    assert_allclose(field.receiver_depth_m, [10.0, 55.0, 90.0])
    assert_allclose(field.range_m, [100.0, 250.0, 400.0, 1000.0], rtol=1e-6)
    assert field.freq_hz == 100.0


def test_truncated_shd_is_reported(tmp_path):
    area = isovelocity_area(1000.0)
    spec = RunSpec(title="t", freq_hz=100.0, source_depth_m=(20.0,), receiver_depth_m=(10.0, 55.0),
                   range_m=(100.0, 250.0), n_beams=50)
    run_env(env_text(area, spec), keep_dir=tmp_path)
    raw = (tmp_path / "tmakit.shd").read_bytes()
    (tmp_path / "cut.shd").write_bytes(raw[: len(raw) - 20])
    with pytest.raises(BellhopError, match="shade file is truncated"):
        read_shd(tmp_path / "cut.shd")


def _leftover_dirs() -> set[str]:
    return {p.name for p in Path(tempfile.gettempdir()).glob("tmakit-bellhop-*")}


def test_bellhop_failure_quotes_bellhop_and_leaves_no_files(tmp_path, monkeypatch):
    # the run's temporary folder in this test's own folder: other BELLHOP runs on the machine
    # (a second suite, a build) come and go in the system's
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    area = isovelocity_area(1000.0)
    spec = RunSpec(title="bad", freq_hz=100.0, source_depth_m=(20.0,), receiver_depth_m=(10.0,),
                   range_m=(100.0,), n_beams=50)
    bad_env = env_text(area, spec).replace("'IG'", "'XG'")  # no such run type
    before = _leftover_dirs()
    with pytest.raises(BellhopError, match=r"BELLHOP failed \(exit 1\): READIN: Unknown RunType selected") as info:
        run_env(bad_env)
    assert "*** FATAL ERROR ***" in info.value.prt_text
    assert info.value.returncode != 0 and info.value.command[-1] == "tmakit"
    assert _leftover_dirs() == before == set()


def test_missing_executable_is_a_clear_error():
    with pytest.raises(BellhopError, match="BELLHOP executable /no/such/bellhop.exe not found"):
        run_env("'x'\n", exe="/no/such/bellhop.exe")


def test_installed_executable_is_found_and_identified():
    exe = find_bellhop()
    assert exe.path.is_file()
    assert len(exe.sha256) == 64


def _process_running(pattern: str) -> bool:
    import subprocess

    return subprocess.run(["pgrep", "-f", pattern], capture_output=True).returncode == 0


def test_a_hung_bellhop_is_killed_at_its_limit(tmp_path):
    import time

    # a "BELLHOP" that never ends, and a child of it that would hold the output pipes open
    marker = f"tmakit-hang-{tmp_path.name}"
    hang = tmp_path / "hung-bellhop.sh"
    hang.write_text(f"#!/bin/sh\nsleep 1000 # {marker}\n")
    hang.chmod(0o755)
    start = time.perf_counter()
    with pytest.raises(BellhopError, match=r"BELLHOP did not finish within 1.5 s and was killed"):
        run_env("'x'\n", exe=hang, timeout_s=1.5)
    assert time.perf_counter() - start < 20.0
    time.sleep(0.2)
    assert not _process_running(marker)


def test_default_limit_grows_with_beams_and_receivers():
    from acoustics.bellhop.runner import MIN_TIMEOUT_S, default_timeout_s

    assert default_timeout_s(1500, 1000) == MIN_TIMEOUT_S  # small runs: the floor
    big = default_timeout_s(10_000, 5_000_000)
    assert big > MIN_TIMEOUT_S and default_timeout_s(20_000, 5_000_000) == pytest.approx(2 * big)
    assert default_timeout_s(0, 5_000_000) > big  # BELLHOP's automatic count: assume many


@pytest.fixture(scope="module")
def real_shd(tmp_path_factory):
    area = isovelocity_area(1000.0)
    spec = RunSpec(title="shd", freq_hz=100.0, source_depth_m=(20.0,), receiver_depth_m=(10.0, 50.0),
                   range_m=(100.0, 200.0, 300.0), n_beams=50)
    folder = tmp_path_factory.mktemp("shd")
    run_env(env_text(area, spec), keep_dir=folder)
    return (folder / "tmakit.shd").read_bytes()


@pytest.mark.parametrize("field, value, match", [
    (2, 0, r"header is inconsistent: Nfreq = 0"),
    (6, -3, r"header is inconsistent: NSz = -3"),
    (7, 10 ** 6, r"header is inconsistent: NRz = 1000000 does not fit a record"),
    (6, 20, r"shade file is truncated: \d+ bytes, need \d+"),
    (8, 2 ** 31 - 1, r"header is inconsistent: NRr = 2147483647"),
])
def test_shd_with_inconsistent_header_counts_is_a_bellhop_error(real_shd, tmp_path, field, value, match):
    raw = bytearray(real_shd)
    lrecl = int(np.frombuffer(bytes(raw[:4]), "<i4")[0])
    header = 2 * 4 * lrecl  # record 3: Nfreq, Ntheta, NSx, NSy, NSz, NRz, NRr
    offset = header + 4 * (field - 2)
    raw[offset:offset + 4] = np.int32(value).tobytes()
    bad = tmp_path / "bad.shd"
    bad.write_bytes(bytes(raw))
    assert read_shd(_write(tmp_path, real_shd)).pressure.shape == (1, 2, 3)  # the unedited file reads
    with pytest.raises(BellhopError, match=match):
        read_shd(bad)


def _write(folder, raw):
    path = folder / "good.shd"
    path.write_bytes(raw)
    return path
