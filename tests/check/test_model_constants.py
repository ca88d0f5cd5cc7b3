"""Controllers read the model's own geometry: ``thigh.length``, ``trunk.mass``, ``hip.at_x``...

The kangaroo's foot placement reads its link lengths from the creature, so a longer thigh in
the file moves the joints to keep the foot where the controller puts it.
"""

from __future__ import annotations

import importlib.util
import math
from pathlib import Path

import pytest
import sympy

from legdsl.check.source import check_model
from legdsl.ir import controller as ir
from legdsl.lang.units import KINDS
from legdsl.pipeline.compile import compile_model
from legdsl.pipeline.generated import write_generated

ROOT = Path(__file__).resolve().parents[2]
KANGAROO = ROOT / "creatures" / "kangaroo.leg"
THIGH = "length 0.13 m  com 0.064 m"


def _flight_tuck_distance(tmp_path: Path, thigh: float) -> tuple[float, float]:
    """Set the hip and knee to the FLIGHT setpoints while rising (the foot tucked at the
    controller's ``tuck`` distance from the hip): the distance hip -> toe, and ``tuck``."""
    text = KANGAROO.read_text()
    assert text.count(THIGH) == 1
    path = tmp_path / "kangaroo.leg"
    path.write_text(text.replace(THIGH, f"length {thigh} m  com 0.064 m"))
    compiled = compile_model(path)
    write_generated(compiled, tmp_path / "generated")
    spec = importlib.util.spec_from_file_location(
        f"kangaroo_{thigh}", tmp_path / "generated" / "kangaroo" / "dynamics.py"
    )
    assert spec is not None and spec.loader is not None
    dynamics = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(dynamics)

    (hop,) = [c for c in compiled.lowered if c.name == "hop"]
    body = hop.bodies[(0, hop.states.index("FLIGHT"))]
    setpoint = {st.actuator: st.value for st in body.settings if st.key == "setpoint"}
    values = {f"input_{n}": v for n, v in hop.inputs} | {f"param_{n}": v for n, v in hop.params}
    state = {"com_vx": 2.0, "com_vz": 1.0, "coord_ankle_value": -1.9, "body_trunk_pitch": 0.0,
             "leg_main_stance_time": 0.1, "leg_main_hip_x": 0.0, "time": 2.0}  # fmt: skip
    subs = {**values, **state, "record_desired_now": 2.0, "record_speed_trim": 0.0}

    def number(expr: sympy.Expr) -> float:
        free = {s: subs.get(s.name, 0.0) for s in expr.free_symbols}
        return float(expr.xreplace(free))

    q = list(compiled.model.q0)
    names = compiled.model.q_names
    q[names.index("pitch")] = 0.0
    q[names.index("ankle")] = state["coord_ankle_value"]
    q[names.index("hip")] = number(setpoint["hip_servo"])
    q[names.index("knee")] = number(setpoint["knee_servo"])
    hip = dynamics.body_poses(q)[dynamics.BODY_NAMES.index("thigh")][0]
    toe = dynamics.contact_positions(q)[dynamics.CONTACT_NAMES.index("toe")]
    return math.dist(hip, toe), dict(hop.params)["tuck"]


@pytest.mark.parametrize("thigh", [0.16])  # the file says 0.13 m; a compile each
def test_the_kangaroos_foot_placement_follows_its_thigh(tmp_path: Path, thigh: float) -> None:
    distance, tuck = _flight_tuck_distance(tmp_path, thigh)
    assert distance == pytest.approx(tuck, abs=1e-9)


def test_constants_are_numbers_with_units(tmp_path: Path) -> None:
    creature = (
        (ROOT / "tests" / "bad" / "ctl_dim_comparison.leg").read_text().split("controller")[0]
    )
    path = tmp_path / "hopper.leg"
    path.write_text(
        creature + "controller hop {\n"
        "  signal reach = thigh.length + shank.length\n"
        "  signal weight = total_mass * g\n"
        "  signal hip_height = slide.at_z\n"
        "  signal lean = trunk.mass * main.hip_at_x\n"
        "  table {\n"
        "    state FLIGHT on liftoff(main): leg_spring.rest = reach - main.length\n"
        "  }\n}\n"
    )
    hop = check_model(path).controller("hop")
    reach = hop.signal("reach").value
    assert isinstance(reach, ir.Binary) and reach.left == ir.Num(0.3, KINDS["length"][0])
    assert hop.signal("weight").value.type == KINDS["force"][0]
    # the slide hangs at the thigh's tip: 0.3 m down the thigh (its direction is -z)
    assert hop.signal("hip_height").value == ir.Num(-0.3, KINDS["length"][0])
    assert hop.signal("lean").value.type == (1, 1, 0, 0)
