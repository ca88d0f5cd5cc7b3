"""Names a row or action gives for a while (action parameters, ``let``, ``each``) may not
hide a built-in value or, in the controller's own file, a name of the creature or the
controller: ``let time = 3 deg`` made the row's ``time`` 3 deg, ``action p(x, x)`` took the
last argument for both. tests/bad/ctl_let_* and ctl_action_param_twice hold the refusals;
here, what stays allowed and what another file's action may do."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.check.source import check_file
from legdsl.lang.errors import LegError

CREATURE = """
creature arms {
  planar
  gravity 0 m/s^2
  body base free { mass 1 kg  inertia 0.1 kg*m^2  length 0.1 m }
  body a on base via revolute j { length 0.5 m  com 0.25 m  mass 1 kg  inertia 0.02 kg*m^2 }
  actuator sa on j servo(kp = 2000 N*m/rad, kv = 60 N*m*s/rad)
}
"""


def messages(tmp_path: Path, controller: str, other: str = "") -> list[str]:
    path = tmp_path / "arms.leg"
    path.write_text(('use "other.leg"\n' if other else "") + CREATURE + controller)
    (tmp_path / "other.leg").write_text(other)
    try:
        check_file(path)
    except LegError as e:
        return [d.message for d in e.diagnostics]
    return []


def test_parameters_may_be_named_like_parts_and_values(tmp_path: Path) -> None:
    """As the library's ``leg`` and ``body``, and the biped's ``tuck(..., balance)``."""
    controller = """controller c {
  param gain = 2
  action p(sa, gain, a) { sa.setpoint = gain * 1 deg + a.length * 1 deg/m }
  table { state A on time >= 0 s: let x = 1 deg; let z = 2 deg; p(sa, gain, a) }
}
"""  # the free root's x and z: a local x is a distance
    assert messages(tmp_path, controller) == []


@pytest.mark.parametrize(
    ("body", "message"),
    [
        ("let time = 3 deg; sa.setpoint = x + time", "'time' is a built-in value"),
        ("let pi = 3; sa.setpoint = x * pi", "'pi' is a built-in value"),
        ("let g = 1 m/s^2; sa.setpoint = x", "'g' is a built-in value"),
        ("let com = 1 deg; sa.setpoint = x", "'com' is a built-in name"),
        ("let j = 2 deg; sa.setpoint = x + j", "'j' is already a name of creature 'arms' (a joint"),
        ("let sa = 2 deg; sa.setpoint = x", "'sa' is already a name of creature 'arms' (an actu"),
        ("let k = 2 deg; sa.setpoint = x + k", "'k' is already a name of controller 'c' (a param"),
        ("let x = 2 deg; sa.setpoint = x", "'x' is already given at "),
    ],
)
def test_an_actions_let_may_not_hide_a_name(tmp_path: Path, body: str, message: str) -> None:
    controller = f"""controller c {{
  param k = 1 deg
  action p(x) {{ {body} }}
  table {{ state A on time >= 0 s: p(20 deg) }}
}}
"""
    told = messages(tmp_path, controller)[0]  # the let, told first
    assert told.startswith(message)
    assert "choose another name" in told


def test_a_called_action_listing_a_parameter_twice_is_refused(tmp_path: Path) -> None:
    controller = """controller c {
  action p(x, x) { sa.setpoint = x }
  table { state A on time >= 0 s: p(1 deg, 2 deg) }
}
"""
    assert messages(tmp_path, controller) == [
        f"parameter 'x' is listed twice in action 'p' (first at {tmp_path / 'arms.leg'}:10:12); "
        "give each parameter a name of its own"
    ]


def test_another_files_action_may_hide_parts_but_not_built_ins(tmp_path: Path) -> None:
    controller = """controller c {
  table { state A on time >= 0 s: p(sa, 1 deg) }
}
"""
    other = "action p(leg, x) { let j = x; leg.setpoint = j }\n"
    assert messages(tmp_path, controller, other) == []
    told = messages(
        tmp_path,
        controller,
        other.replace("let j = x; leg.setpoint = j", "let pi = x; leg.setpoint = pi"),
    )
    assert len(told) == 1 and told[0].startswith("'pi' is a built-in value of every controller")
