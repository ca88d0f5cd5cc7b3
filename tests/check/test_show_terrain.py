"""``legdsl show`` lists each terrain feature with its values as read (in SI units, an angle in
degrees), so that a user can confirm how units and signs were taken; it listed the kinds."""

from __future__ import annotations

from pathlib import Path

from conftest import CREATURES

from legdsl.check.source import check_model
from legdsl.ir.describe import describe_model


def _ground_line(tmp_path: Path, name: str, terrain: str) -> str:
    text = CREATURES.joinpath(f"{name}.leg").read_text()
    anchor = "    friction none\n" if "    friction none\n" in text else "  ground {\n"
    source = tmp_path / f"{name}.leg"
    source.write_text(text.replace(anchor, anchor + f"    {terrain}\n", 1))
    (line,) = [
        x for x in describe_model(check_model(source)).splitlines() if x.startswith("ground:")
    ]
    return line


def test_a_planar_step_and_box_show_their_values_in_si(tmp_path: Path) -> None:
    line = _ground_line(tmp_path, "hopper", "terrain step(x = 200 cm, height = 5 cm)\n"
                        "    terrain box(x0 = 3 m, x1 = 350 cm, height = 10 cm)")  # fmt: skip
    assert line.endswith("; terrain step(x = 2 m, height = 0.05 m), "
                         "box(x0 = 3 m, x1 = 3.5 m, height = 0.1 m)")  # fmt: skip


def test_a_3d_box_shows_its_y_extent_and_a_slope_its_angle_in_degrees(tmp_path: Path) -> None:
    line = _ground_line(tmp_path, "quadruped",
                        "terrain box(x0 = 1 m, x1 = 2 m, y0 = -5 cm, y1 = 1 m, height = 3 cm)")  # fmt: skip
    assert line.endswith(
        "; terrain box(x0 = 1 m, x1 = 2 m, y0 = -0.05 m, y1 = 1 m, height = 0.03 m)"
    )
    assert _ground_line(tmp_path, "hopper", "terrain slope(angle = -0.1 rad)").endswith(
        "; terrain slope(angle = -5.73 deg)"
    )
