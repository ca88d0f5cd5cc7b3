"""Messages about names that named the wrong thing or advised what is refused: 'own w' of an
input advised "record it in the table ('record w = ...')", which is refused (it would hide
the input); integral(integral(speed)) said "'this' is not an input"; "'sb' is a actuator";
a derived controller's plain-number parameter was said to be used as an angle by its base
at its own declaration, not at the base's line that reads it."""

from __future__ import annotations

from pathlib import Path

from legdsl.check.source import check_file
from legdsl.lang.errors import LegError

CREATURE = """
creature arms {
  planar
  gravity 0 m/s^2
  body base fixed at (0 m, 2 m) { mass 1 kg  inertia 0.1 kg*m^2  length 0.1 m }
  body a on base via revolute j { length 0.5 m  com 0.25 m  mass 1 kg  inertia 0.02 kg*m^2 }
  body b on base via revolute k { length 0.5 m  com 0.25 m  mass 1 kg  inertia 0.02 kg*m^2 }
  actuator sa on j servo(kp = 2000 N*m/rad, kv = 60 N*m*s/rad)
  actuator sb on k servo(kp = 2000 N*m/rad, kv = 60 N*m*s/rad)
}
"""


def messages(tmp_path: Path, controller: str) -> list[str]:
    path = tmp_path / "arms.leg"
    path.write_text(CREATURE + controller)
    try:
        check_file(path)
    except LegError as e:
        return [d.message for d in e.diagnostics]
    return []


def test_own_of_an_input_parameter_or_signal_advises_leaving_it_out(tmp_path: Path) -> None:
    controller = """controller c {
  input w = 1 deg/s
  param p = 1 deg
  signal s = 2 * p
  own w, p, s
  table { state A on time >= 0 s: record r = r + 1 deg; sa.setpoint = r + s + integral(w) }
}
"""
    told = messages(tmp_path, controller)
    assert told == [
        "'own w': 'own' lists records, and 'w' is an input of controller 'c': it starts from "
        "its latest command when a controller takes over; '--set c.w=VALUE' gives this "
        "controller its own default; leave it out of 'own'",
        "'own p': 'own' lists records, and 'p' is a parameter of controller 'c': it is each "
        "controller's own already; leave it out of 'own'",
        "'own s': 'own' lists records, and 's' is a signal of controller 'c': it is computed "
        "anew every tick from what it reads; leave it out of 'own'",
    ]
    assert all("record" not in m.split("lists records")[1] for m in told)


def test_integral_of_an_expression_says_it_takes_an_inputs_name(tmp_path: Path) -> None:
    controller = """controller c {
  input speed = 1 m/s
  table { state A on time >= 0 s: sa.setpoint = 1 deg/m * integral(2 * speed) }
}
"""
    (told,) = messages(tmp_path, controller)
    assert "'this'" not in told
    assert told == (
        "integral() takes the name of one of the controller's inputs, as in integral(speed), "
        "not an expression: write what scales it outside, as in '2 * integral(speed)' (an "
        "input alone is integrated, its commands being known between ticks)"
    )
    fixed = controller.replace("integral(2 * speed)", "2 * integral(speed)")
    assert messages(tmp_path, fixed) == []


def test_an_actuator_read_as_a_number_takes_an(tmp_path: Path) -> None:
    controller = "controller c { table { state A on time >= 0 s: sa.setpoint = sb } }\n"
    assert messages(tmp_path, controller) == [
        "'sb' is an actuator, not a number: use one of its members, as in 'sb.force'"
    ]


def test_a_derived_plain_number_names_where_the_base_reads_it(tmp_path: Path) -> None:
    controller = """controller base {
  param off = 10 deg
  table { state A on time >= 0 s: sb.setpoint = off }
}
controller child extends base { param off = 0.2 }
"""
    path = tmp_path / "arms.leg"
    assert messages(tmp_path, controller) == [
        "param 'off' is a plain number (no unit), but controller 'base', which this one "
        f"extends, declares it an angle (deg) ('10 deg', {path}:12:9) and uses it as one "
        f"({path}:13:49); write it with a unit of angle (deg)"
    ]
