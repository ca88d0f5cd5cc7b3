"""URDF has no ground: exporting a creature whose ground has terrain says that the terrain is
not in the file and which format carries it (before, the slope or steps were dropped silently)."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import CREATURES

from legdsl.cli import main


def _hopper(tmp_path: Path, terrain: str) -> Path:
    text = CREATURES.joinpath("hopper.leg").read_text()
    assert "    friction none\n  }" in text
    path = tmp_path / "hopper.leg"
    if terrain:
        text = text.replace("    friction none\n  }", f"    friction none\n    {terrain}\n  }}", 1)
    path.write_text(text)
    return path


def test_urdf_of_a_creature_on_terrain_says_the_terrain_is_left_out(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    leg = _hopper(tmp_path, "terrain step(x = 2 m, height = 5 cm)")
    assert main(["export", str(leg), "--format", "urdf", "-o", str(tmp_path / "h.urdf")]) == 0
    err = capsys.readouterr().err
    assert "URDF describes no ground, so the terrain of" in err
    assert "(step)" in err and "--format mjcf writes the ground and its terrain" in err


def test_urdf_on_level_ground_and_mjcf_on_terrain_say_nothing_of_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    flat = _hopper(tmp_path, "")
    assert main(["export", str(flat), "--format", "urdf", "-o", str(tmp_path / "h.urdf")]) == 0
    sloped = _hopper(tmp_path, "terrain slope(angle = 5 deg)")
    assert main(["export", str(sloped), "--format", "mjcf", "-o", str(tmp_path / "h.xml")]) == 0
    assert "note" not in capsys.readouterr().err
