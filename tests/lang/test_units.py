"""Units: the grammar's hand-written unit regexes, parse_unit, dimension errors, SI in the model."""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest
from conftest import CREATURES

from legdsl.check.source import check_file, check_model
from legdsl.lang.errors import LegError
from legdsl.lang.lalr import lark_parser
from legdsl.lang.units import (
    KINDS,
    UNITS,
    UnitError,
    describe,
    parse_unit,
    unit_pattern,
    unknown_unit,
)

ANGLE = KINDS["angle"][0]


def terminal(name: str) -> str:
    pattern = lark_parser().get_terminal(name).pattern
    assert pattern.type == "re"
    return str(pattern.value)


# ------------------------------------------------------------ grammar vs units.py
@pytest.mark.parametrize("name", ["QUANTITY", "UNIT"])
def test_grammar_lists_exactly_the_unit_symbols(name: str) -> None:
    groups = re.findall(r"\(\?:((?:[A-Za-z]+\|)+[A-Za-z]+)\)", terminal(name))
    assert len(groups) == 2  # the first unit of a product, and each one after '*' or '/'
    for group in groups:
        symbols = group.split("|")
        assert len(symbols) == len(set(symbols))
        assert set(symbols) == set(UNITS)


SAMPLES = [
    "m", "kg", "g", "kg*m^2", "N*m*s/rad", "m/s^2", "deg", "deg/s", "cm", "mm", "km", "ms",
    "min", "Hz", "kN", "J", "W", "rev", "s^-1", "N*m/rad)", "m/s,", "kgs", "m/sec", "Nm",
    "N m", "x", "", "m^", "m*", "mx", "rad/s2", "N*", "kg*m^2*s^-2/rad",
]  # fmt: skip


@pytest.mark.parametrize("sample", SAMPLES)
def test_unit_pattern_matches_what_the_grammar_unit_matches(sample: str) -> None:
    ours = re.match(unit_pattern(), sample)
    grammar = re.match(terminal("UNIT"), sample)
    assert (ours and ours.group()) == (grammar and grammar.group())


@pytest.mark.parametrize("symbol", sorted(UNITS))
def test_every_unit_symbol_is_a_quantity_in_the_grammar(symbol: str) -> None:
    quantity = re.compile(terminal("QUANTITY"))
    for text in (f"5 {symbol}", f"2.5e3 {symbol}^2", f".5 {symbol}*{symbol}/{symbol}^-1"):
        assert quantity.fullmatch(text), text
    # A unit glued to more letters is no unit: the number stands alone.
    glued = quantity.match(f"5 {symbol}x")
    assert glued is not None and glued.group() == "5"


# ------------------------------------------------------------------- parse_unit
@pytest.mark.parametrize(
    ("text", "factor", "dim"),
    [
        ("N*m*s/rad", 1.0, (1, 2, -1, -1)),
        ("m/s^2", 1.0, (0, 1, -2, 0)),
        ("kg*m^2", 1.0, (1, 2, 0, 0)),
        ("deg", math.pi / 180, ANGLE),
        ("cm", 0.01, (0, 1, 0, 0)),
        ("g", 1e-3, (1, 0, 0, 0)),
        ("km", 1e3, (0, 1, 0, 0)),
        ("min", 60.0, (0, 0, 1, 0)),
        ("kN", 1e3, (1, 1, -2, 0)),
        ("rev", 2 * math.pi, ANGLE),
        ("Hz", 1.0, (0, 0, -1, 0)),
        ("kHz", 1e3, (0, 0, -1, 0)),
        ("deg/s", math.pi / 180, (0, 0, -1, 1)),
        ("N*m/deg", 180 / math.pi, (1, 2, -2, -1)),
        ("s^-1", 1.0, (0, 0, -1, 0)),
        ("N/m*s", 1.0, (1, 0, -1, 0)),  # '/' divides the next unit only: N*s/m
        ("mm^3", 1e-9, (0, 3, 0, 0)),
    ],
)
def test_parse_unit(text: str, factor: float, dim: tuple[int, int, int, int]) -> None:
    got_factor, got_dim = parse_unit(text)
    assert got_dim == dim
    assert got_factor == pytest.approx(factor, rel=1e-15)


@pytest.mark.parametrize("text", ["kgs", "m/sec", "", "N*", "*N", "Nm", "m^x", "m s", "µm"])
def test_parse_unit_rejects_unknown_units(text: str) -> None:
    with pytest.raises(UnitError):
        parse_unit(text)


def test_a_power_past_a_double_is_an_infinite_factor_not_an_overflow_error() -> None:
    assert parse_unit("km^200") == (math.inf, (0, 200, 0, 0))
    assert parse_unit("g^200")[0] == 0.0


def test_describe_names_dimensions() -> None:
    assert describe((1, 0, -2, 0)) == "linear stiffness (N/m)"
    assert describe((1, 2, -1, -1)) == "angular damping (N*m*s/rad)"
    assert describe((0, 0, 0, 0)) == "dimensionless"
    assert describe((1, -1, 0, 0)) == "kg*m^-1"


# ------------------------------------------------------- dimensions in the checker
def check_text(tmp_path: Path, text: str) -> None:
    path = tmp_path / "c.leg"
    path.write_text(text, encoding="utf-8")
    check_model(path)


def first_message(tmp_path: Path, text: str) -> str:
    with pytest.raises(LegError) as info:
        check_text(tmp_path, text)
    return info.value.diagnostics[0].message


def body(props: str, joint: str = "revolute hip") -> str:
    return (
        "creature c {\n  planar\n  body trunk free { mass 1 kg  inertia 1 kg*m^2 }\n"
        f"  body leg on trunk via {joint} {{ mass 1 kg  inertia 1 kg*m^2  {props} }}\n}}\n"
    )


@pytest.mark.parametrize(
    ("props", "joint", "message"),
    [
        ("length 1 kg/m", "revolute hip", "the link length is a length (m), but '1 kg/m' is a quantity in kg*m^-1; give it in m"),
        ("length 2 s", "revolute hip", "the link length is a length (m), but '2 s' is a time; give it in m"),
        (
            "velocity 1 m/s",
            "revolute hip",
            "the velocity hip is an angular velocity (rad/s), but '1 m/s' is a velocity; give it in rad/s",
        ),
        ("initial 5 deg", "prismatic hip", "the initial hip is a length (m), but '5 deg' is an angle; give it in m"),
        ("initial 5", "revolute hip", "the initial hip needs a unit: write e.g. '5 deg'"),
        ("direction (1 m, 0)", "revolute hip", "a component of the link direction takes no unit, but '1 m' is a length; leave the unit out"),
    ],
)  # fmt: skip
def test_dimension_errors(tmp_path: Path, props: str, joint: str, message: str) -> None:
    assert first_message(tmp_path, body(props, joint)) == message


def test_a_bare_zero_needs_no_unit(tmp_path: Path) -> None:
    check_text(tmp_path, body("initial 0  limits 0 to 1 rad  com 0"))
    check_text(tmp_path, body("initial 0  velocity 0", "prismatic hip"))


# --------------------------------------------------------------- SI in the model
CONVERTED = """\
creature c {
  planar
  body trunk free {
    mass 500 g  inertia 2e4 g*cm^2
    initial x = 10 cm, z = 1 m, pitch = 90 deg
    velocity x = 36 m/min, z = 0 m/s, pitch = 1 rev/min
  }
  body thigh on trunk via revolute hip at (10, -5) cm {
    length 1 cm  com 5 mm  mass 1 kg  inertia 1 kg*m^2
    initial 90 deg  limits -0.5 rev to 180 deg
  }
  body shank on thigh via prismatic knee at tip { mass 1 kg  inertia 1 kg*m^2  initial 5 mm }
  contact toe on shank at (0 m, -2 cm)
  actuator spring on knee spring(k = 2 kN/m, b = 3 N*s/cm, rest = 1 cm, max = 1 kN)
  actuator servo on hip servo(kp = 1 N*m/deg, setpoint = -45 deg)
  ground {
    normal pad(k = 1 kN, thickness = 1 cm, b = 60 N*s/m)
    tangent spring(k = 5000 N/m)
    terrain step(x = 1 km, height = 10 mm)
  }
}
"""


def test_si_conversion_in_the_model(tmp_path: Path) -> None:
    path = tmp_path / "c.leg"
    path.write_text(CONVERTED, encoding="utf-8")
    m = check_model(path)
    trunk, thigh = m.body("trunk"), m.body("thigh")
    assert trunk.mass == pytest.approx(0.5)
    assert trunk.inertia[1][1] == pytest.approx(2e4 * 1e-3 * 1e-4)
    assert m.q0[:3] == pytest.approx((0.1, 1.0, math.pi / 2))
    assert m.v0[:3] == pytest.approx((0.6, 0.0, 2 * math.pi / 60))
    assert m.joint("hip").origin == pytest.approx((0.1, 0.0, -0.05))
    assert thigh.length == pytest.approx(0.01)
    assert thigh.com == pytest.approx((0.0, 0.0, -0.005))  # along the link, which hangs down
    hip, knee = m.joint("hip").dofs[0], m.joint("knee").dofs[0]
    assert hip.initial == pytest.approx(math.pi / 2)
    assert hip.limits == pytest.approx((-math.pi, math.pi))
    assert knee.initial == pytest.approx(0.005)
    assert m.joint("knee").origin == pytest.approx((0.0, 0.0, -0.01))  # 'at tip' of 1 cm
    assert m.contacts[0].point == pytest.approx((0.0, 0.0, -0.02))
    spring, servo = m.actuators
    assert dict(spring.params) == pytest.approx({"k": 2000.0, "b": 300.0, "rest": 0.01})
    assert spring.max == pytest.approx(1000.0)
    assert servo.get("kp") == pytest.approx(180 / math.pi)
    assert servo.get("setpoint") == pytest.approx(-math.pi / 4)
    assert m.ground is not None
    assert (m.ground.normal.k, m.ground.normal.b) == pytest.approx((1000.0, 60.0))
    step = m.ground.terrain[0]
    assert (step.get("x"), step.get("height")) == pytest.approx((1000.0, 0.01))
    assert m.gravity == (0.0, 0.0, -9.81)


@pytest.mark.parametrize(
    ("text", "told"),
    [
        ("hz", "did you mean 'Hz'?"),
        ("m/sec", "did you mean 'm/s'?"),
        ("MS", "did you mean 'ms'?"),
        ("°", "did you mean 'deg'?"),
        # a prefix legdsl lacks, named with the units it has (the command line gives no
        # number beside it to convert)
        ("us", "'us' is not a unit legdsl knows: it has no prefix 'u' (micro); it writes times"),
        # symbols run together that read two ways: both are named (it said only N*ms/rad,
        # a newton-millisecond, for the N*m*s/rad of an angular damping)
        ("Nms/rad", "did you mean 'N*ms/rad' or 'N*m*s/rad'?"),
        ("Nm", "did you mean 'N*m'?"),
    ],
)
def test_an_unknown_unit_reads_as_a_files_does(text: str, told: str) -> None:
    """The command line's values (--dt 0.4MS, --set speed=1m/sec) print a UnitError: it says
    what a file's unknown unit is told, the unit to write with it (it said "unknown unit 'hz'")."""
    with pytest.raises(UnitError) as caught:
        parse_unit(text)
    assert told in str(caught.value)


@pytest.mark.parametrize(
    ("number", "unit", "told"),
    [
        # another system's unit in the denominator (it was "not a unit legdsl knows" with the
        # list of symbols, and a file's '10 km/h' was told of 'h' alone, with no value)
        # (and named the 'h' it lacks: a speed is not a time)
        ("10", "km/h", "'km/h' is not a unit legdsl knows: it has no 'h'; it writes times in "
         "s, ms, min: "
         "write '2.7777777778 m/s' or '0.1666666667 km/min'"),
        ("60", "rev/h", "write '0.1047197551 rad/s' or '1 rev/min'"),
        ("2", "ft/s^2", "it writes lengths in m, cm, mm, km: write '0.6096 m/s^2'"),
        ("100", "mN*m/rad", "it has no prefix 'm' (milli); it writes forces (its 'mN') in N, kN: "
         "write '0.1 N*m/rad'"),
        ("3", "m/us", "it has no prefix 'u' (micro); it writes times (its 'us') in s, ms, min: "
         "write '3e6 m/s'"),
        ("0.5", "in", "write '0.0127 m' or '1.27 cm'"),  # as before: the one nearest 1 beside SI
    ],
)  # fmt: skip
def test_a_unit_of_another_system_anywhere_in_the_unit_is_given_in_legdsls(
    number: str, unit: str, told: str
) -> None:
    assert told in unknown_unit(unit, number)


def test_a_files_unit_of_another_system_in_the_denominator_is_told_whole(tmp_path: Path) -> None:
    text = (CREATURES / "hopper.leg").read_text()
    leg = tmp_path / "kmh.leg"
    leg.write_text(text.replace("input speed = 1 m/s ", "input speed = 10 km/h", 1))
    with pytest.raises(LegError) as caught:
        check_file(leg)
    said = caught.value.render()
    assert "'km/h' is not a unit legdsl knows" in said and "write '2.7777777778 m/s'" in said
    assert "input speed = 10 km/h" in said and "\n                       ^~~~\n" in said + "\n"
