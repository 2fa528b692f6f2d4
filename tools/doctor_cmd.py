"""``tmakit doctor``: which BELLHOP is used, its version, and a tiny test run."""

from __future__ import annotations

from tools.report import Report


def register(sub, common) -> None:
    p = sub.add_parser("doctor", parents=[common], help="check the BELLHOP installation")
    p.set_defaults(func=run)


def run(args) -> Report:
    from acoustics.bellhop.exe import find_bellhop
    from acoustics.bellhop.selftest import self_test

    exe = find_bellhop()
    test = self_test(exe.path)
    data = {"bellhop": exe.describe(), "self_test": test}
    status = "works" if test["ok"] else "RUNS BUT GIVES WRONG NUMBERS"
    summary = (f"BELLHOP: {exe.path}\n"
               f"  found by: {exe.found_by}\n"
               f"  version:  {exe.version}\n"
               f"  sha256:   {exe.sha256[:16]}...\n"
               f"  tiny run: {status} in {test['seconds'] * 1000:.0f} ms "
               f"(TL {test['tl_db_at_100m']:.1f} dB at 100 m; spherical spreading gives 40 dB)")
    return Report(summary, data)
