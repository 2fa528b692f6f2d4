"""The figure helper writes a real PNG and leaves nothing behind when the save fails."""

from __future__ import annotations

import pytest

from acoustics.plots.figures import new_figure, save_figure


def test_save_figure_writes_png_without_pyplot(tmp_path):
    fig = new_figure(figsize=(3, 2))
    fig.add_subplot().plot([0, 1], [1, 0])
    out = save_figure(fig, tmp_path / "a.png")
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert [p.name for p in tmp_path.iterdir()] == ["a.png"]

def test_failed_save_keeps_existing_file(tmp_path):
    target = tmp_path / "a.png"
    target.write_bytes(b"old")
    fig = new_figure()
    with pytest.raises(ValueError):
        save_figure(fig, target, dpi=-1)
    assert target.read_bytes() == b"old"
    assert [p.name for p in tmp_path.iterdir()] == ["a.png"]
