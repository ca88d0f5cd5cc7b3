"""Values under a measurement's resolution print as 0: a quadruped trotting in place printed
a stride length of 1.61e-16 m and a running speed of -3.63e-17 m/s, a bound a roll
magnitude of 1.8e-14 deg, as if measured (analysis/resolution.py), weighed against what the
creature's size, mass and gravity make of each unit, so a tiny creature's values stay."""

from __future__ import annotations

import math

import pytest

from legdsl.analysis.resolution import creature_size, label_unit, natural, natural_sizes, resolved
from legdsl.analysis.results import GaitMetrics, Summary
from legdsl.sim.trajectory import empty


def _metrics(rows: list[Summary], size: float, mass: float) -> GaitMetrics:
    tr = empty(4, 7, 6, 1, 1, total_mass=mass)
    tr.leg_length[:] = size
    return GaitMetrics(0.0, 1.0, "fl", {"duration": [0.5]}, [], [], [], rows,
                       sizes=natural_sizes(tr))  # fmt: skip


def _row(table: str, label: str) -> list[str]:
    line = next(x for x in table.splitlines() if x.startswith(label))
    return line[len(label) :].split()


def test_round_off_of_a_zero_prints_as_zero() -> None:
    rows = [
        Summary("stride_length", "stride length (m)", 1.61e-16, 6e-17, 8),
        Summary("running_speed", "running speed (m/s)", -3.63e-17, 2.0e-16, 8),
        Summary("roll_magnitude", "roll magnitude (deg)", 1.8e-14, 1.4e-14, 17),
        Summary("work", "positive work, hip_fl_roll (J)", 7.4e-29, math.nan, 1347, "total"),
        Summary("friction", "friction coefficient needed, toe_fl (-)", 4e-14, math.nan, 8, "max"),
        Summary("stride_duration", "stride duration (s)", 0.785, 0.007, 8),
        Summary("speed_error", "error in running speed (m/s)", -0.0011, 0.1314, 33),
    ]
    table = _metrics(rows, 0.81, 20.0).table()
    assert _row(table, "stride length (m)") == ["0.000", "0.000", "8"]
    assert _row(table, "running speed (m/s)") == ["0.000", "0.000", "8"]
    assert _row(table, "roll magnitude (deg)") == ["0.000", "0.000", "17"]
    assert _row(table, "positive work, hip_fl_roll (J)") == ["0.000", "(window)", "1347"]
    assert _row(table, "friction coefficient needed, toe_fl (-)") == ["0.000", "(peak)", "8"]
    assert _row(table, "stride duration (s)") == ["0.785", "0.007", "8"]  # measured: as before
    assert _row(table, "error in running speed (m/s)") == ["-0.0011", "0.1314", "33"]
    assert "(5 rows read 0.000: under 1e-09 of what the creature's size (0.810 m)" in table


def test_a_tiny_creatures_small_values_are_its_own() -> None:
    """A creature of 0.1 mm strides 1e-5 m: its size's, not round-off."""
    rows = [Summary("stride_length", "stride length (m)", 1.2e-5, 1e-7, 8),
            Summary("running_speed", "running speed (m/s)", 3.0e-4, 1e-6, 8)]  # fmt: skip
    table = _metrics(rows, 1e-4, 1e-9).table()
    assert _row(table, "stride length (m)")[0] == "0.000012"
    assert _row(table, "running speed (m/s)")[0] == "0.00030"
    assert "read 0.000" not in table and "reads 0.000" not in table


def test_the_natural_size_of_each_unit() -> None:
    tr = empty(3, 7, 6, 1, 1, total_mass=20.0)
    tr.leg_length[:] = 0.8
    assert creature_size(tr) == pytest.approx(0.8)
    sizes = natural_sizes(tr)
    assert natural("m", sizes) == pytest.approx(0.8)
    assert natural("m/s", sizes) == pytest.approx(math.sqrt(9.81 * 0.8))
    assert natural("deg", sizes) == pytest.approx(180 / math.pi)
    assert natural("J", sizes) == pytest.approx(20 * 9.81 * 0.8)
    assert natural("-", sizes) == natural("g", sizes) == 1.0
    assert natural("furlongs", sizes) is None and natural("m", {}) is None
    assert label_unit("cost of transport, work / (m g d) (-)") == "-"
    assert label_unit("no unit") is None
    assert resolved(1e-12, 1.0) == 0.0 and resolved(1e-6, 1.0) == 1e-6
    assert resolved(1e-20, None) == 1e-20  # a size not known: as measured
