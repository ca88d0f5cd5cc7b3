"""The controller IR as the checker builds it: names resolved to typed nodes, actions inlined."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.check.source import check_model
from legdsl.ir import controller as ir
from legdsl.lang.units import KINDS

ROOT = Path(__file__).resolve().parents[2]


def walk(stmts: tuple[ir.Stmt, ...]) -> list[ir.Stmt]:
    out: list[ir.Stmt] = []
    for s in stmts:
        out.append(s)
        if isinstance(s, ir.Do):
            out += walk(s.body)
    return out


def write(tmp_path: Path, controller: str) -> Path:
    path = tmp_path / "hopper.leg"
    creature = (
        (ROOT / "tests" / "bad" / "ctl_dim_comparison.leg").read_text().split("controller")[0]
    )
    path.write_text(creature + controller)
    return path


def test_records_take_the_dimension_of_their_values() -> None:
    hop = check_model(ROOT / "creatures" / "kangaroo.leg").controller("hop")
    types = dict(hop.records)
    assert types["speed_trim"] == KINDS["velocity"][0]
    assert types["predicted_apex"] == KINDS["length"][0]


def test_a_library_action_is_inlined_with_its_arguments() -> None:
    hop = check_model(ROOT / "creatures" / "hopper.leg").controller("hop")
    flight = next(s for s in hop.states if s.name == "FLIGHT")
    (place,) = [s for s in walk(flight.body) if isinstance(s, ir.Place)]
    assert place.legs == ir.Legs(role="active")  # the parameter 'leg' became the role
    assert place.axes == ("x",)
    assert place.goals[0].type == KINDS["length"][0]
    (servo,) = place.servos
    assert servo == ir.Alias(ir.Legs(role="active"), "hip_servo", "actuator")
    calls = [s.action for s in walk(flight.body) if isinstance(s, ir.Do)]
    assert calls == ["relax", "swing", "trim_speed", "learn_apex", "place_foot"]


def test_assignments_carry_the_actuator_inputs_dimension() -> None:
    hop = check_model(ROOT / "creatures" / "hopper.leg").controller("hop")
    for state in hop.states:
        for s in walk(state.body):
            if isinstance(s, ir.Assign) and s.key == "kp":
                assert s.value.type in (KINDS["angular stiffness"][0], None)


def test_the_biped_swaps_between_two_bindings() -> None:
    run = check_model(ROOT / "creatures" / "biped.leg").controller("run")
    assert len(run.bindings) == 2
    first, second = (dict(b) for b in run.bindings)
    assert first["active"] == second["idle"] and first["idle"] == second["active"]
    # every (binding, state) pair says where its swaps lead
    assert len(run.after_entry) == 2 * len(run.states)


def test_a_bare_zero_fits_any_dimension_and_other_numbers_are_plain(tmp_path: Path) -> None:
    path = write(
        tmp_path,
        "controller hop {\n  table {\n"
        "    state FLIGHT on main.rate < 0: leg_spring.rest = 0.5 * main.length\n"
        "  }\n}\n",
    )
    (state,) = check_model(path).controller("hop").states
    assert isinstance(state.event, ir.Binary) and state.event.type == ir.BOOL
    zero = state.event.right
    assert isinstance(zero, ir.Num) and zero.type is None
    (assign,) = [s for s in state.body if isinstance(s, ir.Assign)]
    assert isinstance(assign.value, ir.Binary) and assign.value.type == KINDS["length"][0]
    assert assign.value.left == ir.Num(0.5, KINDS["dimensionless"][0])


@pytest.mark.parametrize(
    ("expression", "dimension"),
    [
        ("sqrt(main.length * main.length)", "length"),
        ("atan2(main.foot_x, main.foot_z)", "angle"),
        ("main.rate ^ 2 / (2 * g)", "length"),
        ("select(main.touching > 0.5, main.length, 1 cm)", "length"),
        ("abs(min(main.length, 1 m))", "length"),
    ],
)
def test_dimensions_propagate_through_functions(
    tmp_path: Path, expression: str, dimension: str
) -> None:
    path = write(
        tmp_path,
        "controller hop {\n"
        f"  signal probe = {expression}\n"
        "  table {\n"
        "    state FLIGHT on liftoff(main): record seen = probe\n"
        "  }\n}\n",
    )
    hop = check_model(path).controller("hop")
    assert hop.signal("probe").value.type == KINDS[dimension][0]
    assert dict(hop.records)["seen"] == KINDS[dimension][0]
