"""A tune's report gives each value its unit, the one the file writes it in: an outside user's
report read `k_speed 0.05  0.0541 s` (the start without its unit) and `tilt 0  0.02801 rad`
for a tilt the file, and the tuned file, write in degrees."""

from __future__ import annotations

import math
from pathlib import Path

from legdsl.api.sweep import units_of
from legdsl.api.tune import report
from legdsl.api.tune_cli import _file_units
from legdsl.check.source import check_model

HOPPER = Path(__file__).resolve().parents[2] / "creatures" / "hopper.leg"


def test_each_value_has_its_unit_in_the_files_unit() -> None:
    result = {
        "start": {"values": {"k_speed": 0.05, "tilt": 0.0}, "objective": 1.0, "runs": []},
        "best": {"values": {"k_speed": 0.0541, "tilt": 0.02801}, "objective": 0.1, "runs": []},
    }
    lines = report(result, {"k_speed": "s", "tilt": "deg"}, (), {"tilt": math.pi / 180})
    assert lines.splitlines()[1].split() == ["k_speed", "0.05", "s", "0.0541", "s"]
    assert lines.splitlines()[2].split() == ["tilt", "0", "deg", "1.605", "deg"]


def test_the_units_are_the_files() -> None:
    model = check_model(str(HOPPER), None)
    controller = model.controller("hop")
    dims = {c.name: c.dim for c in controller.params}
    units = units_of({n: dims[n] for n in ("stroke", "k_speed", "k_height")})
    shown, factors = _file_units(HOPPER, controller, units)
    assert shown == {"stroke": "cm", "k_speed": "s", "k_height": ""}
    assert factors == {"stroke": 0.01}
