"""Virtual legs: a group role read as one leg, and ``each LEG in ROLE { ... }`` applied per
member with that member's own members (checked once, lowered once per member)."""

from __future__ import annotations

from pathlib import Path

import sympy

from legdsl.check.source import check_model
from legdsl.ir import controller as ir
from legdsl.lower.control import lower_controller

ROOT = Path(__file__).resolve().parents[2]
CREATURE = (ROOT / "tests" / "bad" / "ctl_each_record.leg").read_text().split("controller")[0]


def _lowered(tmp_path: Path, table: str):  # type: ignore[no-untyped-def]
    path = tmp_path / "walker.leg"
    path.write_text(CREATURE + "controller run {\n  roles pair = (left, right)\n" + table + "}\n")
    model = check_model(path)
    return model.controller("run"), lower_controller(model, model.controller("run"))


def test_each_is_checked_once_and_lowered_per_member(tmp_path: Path) -> None:
    ctl, low = _lowered(
        tmp_path,
        "  table {\n"
        "    state A on liftoff(pair): each m in pair { m.spring.rest = m.length - 0.8 m }\n"
        "    state B on touchdown(pair): pair.spring.rest = pair.length - 0.8 m\n"
        "  }\n",
    )
    (each,) = [s for s in ctl.states[0].body if isinstance(s, ir.Each)]
    assert each.group == ir.Legs(role="pair")
    settings = low.bodies[(0, 0)].settings
    # each member's spring from its own length
    assert {s.actuator: str(s.value) for s in settings} == {
        "left_spring": "leg_left_length - 0.8",
        "right_spring": "leg_right_length - 0.8",
    }
    # the group as one leg: both springs from the mean length
    group = {str(s.value) for s in low.bodies[(0, 1)].settings}
    assert group == {"leg_left_length/2 + leg_right_length/2 - 0.8"}


def test_a_group_reads_as_one_virtual_leg(tmp_path: Path) -> None:
    _, low = _lowered(
        tmp_path,
        "  table {\n"
        "    state A on liftoff(pair): record ts = pair.stance_time; record tf = pair.flight_time;"
        " record n = pair.feet_down; record any = select(pair.touching > 0, 1, 0)\n"
        "  }\n",
    )
    records = dict(low.bodies[(0, 0)].records)
    left, right = sympy.symbols("leg_left_stance_time leg_right_stance_time")
    assert records["ts"] == sympy.Max(left, right)  # first touchdown to last liftoff
    lf, rf = sympy.symbols("leg_left_flight_time leg_right_flight_time")
    assert records["tf"] == sympy.Min(lf, rf)
    lt, rt = sympy.symbols("leg_left_touching leg_right_touching")
    assert records["n"] == lt + rt
    assert sympy.Max(lt, rt) in records["any"].atoms(sympy.Max)
