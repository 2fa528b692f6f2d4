"""Writing the measured k_error_sd_db into a copy of an area file."""

from __future__ import annotations

import pytest

import envdata
from acoustics import sensitivity as sens
from envdata.errors import InputError
from tests.conftest import DATA


def test_write_k_error_keeps_the_file_and_replaces_the_values(tmp_path):
    out = sens.write_k_error(DATA / "tiny-munk.toml", {"SUB": 3.14159, "SHIP": 0.5}, tmp_path / "a.toml")
    area = envdata.load_area(out)
    assert {c.name: c.k_error_sd_db for c in area.classes} == {"SUB": 3.14, "SHIP": 0.5}
    text = out.read_text()
    assert "# A tiny Munk area for tests" in text and text.count("k_error_sd_db") == 2
    # a class without the key gets it
    src = tmp_path / "nokey.toml"
    src.write_text((DATA / "tiny-munk.toml").read_text().replace("k_error_sd_db = 1.5\n", ""))
    area = envdata.load_area(sens.write_k_error(src, {"SHIP": 0.75}, tmp_path / "b.toml"))
    assert area.target_class("SHIP").k_error_sd_db == 0.75 and area.target_class("SUB").k_error_sd_db == 2.0
    with pytest.raises(InputError, match=r"tiny-munk.toml: no \[\[classes\]\] entry named 'NOPE'"):
        sens.write_k_error(DATA / "tiny-munk.toml", {"NOPE": 1.0}, tmp_path / "c.toml")
    assert not (tmp_path / "c.toml").exists()
