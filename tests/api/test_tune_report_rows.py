"""The tune report's rows: the file's own values kept are said to be, with no bound claimed;
energy per metre is n/a where the speed is; a speed's error has one sign for both ways."""

from __future__ import annotations

import math

from legdsl.api.tune import Bound, report
from legdsl.api.tune_cli import _ran

RUN = {"outcome": "ok", "running_speed": 1.0, "simulated": 6.0, "speed": 1.0,
       "energy_per_metre": 40.0, "cost_of_transport": 0.5}  # fmt: skip
HISTORY = [{"generation": 1, "best": 0.3, "mean": 0.4, "runs": 4}]


def test_values_kept_for_want_of_a_better_are_said_kept_not_at_a_bound() -> None:
    """kp = 80 of --param kp=20:1e7, kept as no candidate beat it, was reported 'at its lower
    bound: widen it to search past it' (80 is within 1% of the range's width of 20)."""
    start = {"values": {"kp": 80.0, "kv": 8.0}, "objective": 0.1, "runs": [RUN]}
    result = {"start": start, "best": start, "history": HISTORY}
    bounds = [Bound("kp", 20.0, 1e7, 80.0), Bound("kv", 1.0, 1e5, 8.0)]
    text = report(result, {"kp": "N*m/rad", "kv": "N*m*s/rad"}, bounds)
    assert "bound" not in text
    assert "(the file's own values are kept: no candidate beat them)" in text
    best = {"values": {"kp": 25.0, "kv": 8.0}, "objective": 0.05, "runs": [RUN]}
    text = report({**result, "best": best}, {}, bounds)  # a search that met the bound
    assert "(at its lower bound: widen it to search past it)" in text
    assert "kept" not in text


def test_energy_per_metre_is_na_where_no_speed_was_measured() -> None:
    """'at 2  1.855, 0.0244' beside 'no whole stride', and numbers beside 'n/a (fell ...)'."""
    no_stride = {**RUN, "speed": 2.0, "running_speed": math.nan, "energy_per_metre": 1.855,
                 "cost_of_transport": 0.0244}  # fmt: skip
    fell = {**RUN, "speed": 3.0, "outcome": "fell at 1.384 s", "running_speed": math.nan,
            "simulated": 1.384, "energy_per_metre": 12.0}  # fmt: skip
    start = {"values": {"kp": 80.0}, "objective": 1.0, "runs": [RUN, no_stride, fell]}
    best = {"values": {"kp": 90.0}, "objective": 0.5, "runs": [RUN, no_stride, fell]}
    text = report({"start": start, "best": best, "history": HISTORY}, {})
    energy = text.split("cost of transport (-)")[1].splitlines()[1:4]
    assert energy[0].split() == ["at", "1", "40,", "0.5", "40,", "0.5"]
    assert energy[1].split() == ["at", "2", "n/a", "n/a"]
    assert energy[2].split() == ["at", "3", "n/a", "n/a"]


def test_a_speed_error_is_plus_for_faster_either_way() -> None:
    """-1.115 at -1 m/s said -11.5% (11.5% too fast backwards), 0.9611 at 1 said -3.9% (too
    slow): + is now faster than the command's size, - slower, whichever way."""
    ok = {"outcome": "ok"}
    assert _ran(-1.115, ok, -1.0) == "-1.115 (+11.5%)"
    assert _ran(0.9611, ok, 1.0) == "0.9611 (-3.9%)"
    assert _ran(-0.9, ok, -1.0) == "-0.9 (-10.0%)"
    assert _ran(0.2, ok, 0.0) == "0.2"
