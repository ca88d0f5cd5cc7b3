"""Slips an outside user's mutation corpus found told with a wrong fix: 'nan'/'inf' as a value
anywhere, a declaration without its name or its kind, a missing value."""

from __future__ import annotations

import pytest

from legdsl.lang.errors import LegError
from legdsl.lang.parser import parse

CREATURE = """\
creature hopper {
  planar
  body trunk free {
    mass 3 kg
    inertia 0.03 kg*m^2
    shape cylinder(0.04 m)
  }
}
"""
CONTROLLER = """\
controller hop {
  input speed = 1 m/s
  param kv = 15 N*m*s/rad
  param stroke = 3 cm
  signal reach = select(abs(speed) < 1 mm/s, stroke, 2 * stroke)
  table {
    state GO on active.rate > 0: servo_pitch(active, trunk, 0 deg, 2 * stroke, kv)
  }
}
"""


def told(text: str) -> str:
    with pytest.raises(LegError) as err:
        parse(text, "f.leg")
    return str(err.value)


NAN = "is not a number legdsl reads: every quantity is a finite number with its unit"


@pytest.mark.parametrize(
    ("old", "new", "where"),
    [
        ("cylinder(0.04 m)", "cylinder(nan m)", "f.leg:6:20:"),  # in a call
        ("param kv = 15 N*m*s/rad", "param kv = inf N*m*s/rad", "f.leg:11:14:"),  # a param
        ("2 * stroke, kv)", "inf * stroke, kv)", "f.leg:15:"),  # in an expression
    ],
)
def test_nan_and_inf_are_told_as_numbers_legdsl_does_not_read(
    old: str, new: str, where: str
) -> None:
    message = told((CREATURE + CONTROLLER).replace(old, new))
    assert message.startswith(where), message
    assert NAN in message
    assert "a unit follows a number, not a name" not in message
    assert "declare it" not in message


@pytest.mark.parametrize(
    ("old", "new", "kind"),
    [
        ("signal reach = select(", "signal = select(", "signal"),
        ("input speed = 1 m/s", "input = 1 m/s", "input"),
        ("param stroke = 3 cm", "param = stroke 3 cm", "param"),
        ("servo_pitch(active,", "let = 2 * stroke; servo_pitch(active,", "let"),
    ],
)
def test_a_declaration_without_its_name_is_told_so(old: str, new: str, kind: str) -> None:
    message = told((CREATURE + CONTROLLER).replace(old, new))
    assert (
        f"the {kind}'s name is missing: give the {kind} a name, as in '{kind} NAME = ...'"
        in message
    )
    assert "takes no '='" not in message


@pytest.mark.parametrize("name", ["reach", "ste", "kp2"])
def test_a_declaration_without_its_kind_is_told_so_not_a_spelling(name: str) -> None:
    message = told((CREATURE + CONTROLLER).replace("signal reach = ", f"{name} = "))
    assert message.startswith("f.leg:13:3:"), message
    assert f"a declaration starts with its kind: write 'param {name} = ...'" in message
    assert "not a word of legdsl" not in message


TEMPLATE = """\
creature c {
  planar
  body trunk free { mass 1 kg  inertia 0.1 kg*m^2 }
  template arm(S) {
    body arm_S on trunk via revolute j_S at (0 m, 0 m) { length 0.3 m  mass 0.1 kg  inertia 0.01 kg*m^2 }
  }
  instance a = arm(S = l)
}
"""


@pytest.mark.parametrize("line", [3, 5], ids=["creature", "template"])
def test_a_lookalike_letter_is_named_in_a_template_too(line: int) -> None:
    lines = TEMPLATE.split("\n")
    lines[line - 1] = lines[line - 1].replace("body", "b\u03bfdy", 1)
    message = told("\n".join(lines))
    col = lines[line - 1].index("\u03bf") + 1
    assert message.startswith(
        f"f.leg:{line}:{col}: error: '\u03bf' is GREEK SMALL LETTER OMICRON, U+03BF"
    )


def test_a_property_without_its_value_is_told_at_its_line() -> None:
    message = told(CREATURE.replace("  planar\n", "  planar\n  gravity\n\n"))
    assert message.startswith(
        "f.leg:3:3: error: 'gravity' stands alone on its line: a property is a key"
    )
    assert "the next line's 'body' was read as the value of 'gravity'" in message


def test_a_declaration_without_its_value_is_told_at_its_line() -> None:
    message = told((CREATURE + CONTROLLER).replace("param kv = 15 N*m*s/rad", "param kv ="))
    assert message.startswith(
        "f.leg:11:12: error: the value of 'kv' is missing: write it after the '=' on the same "
        "line, 'param kv = VALUE'; the next line's 'param' was read as its value"
    ), message


def test_an_extra_brace_at_the_block_s_own_indent_is_found_far_back() -> None:
    # the '}' closes the controller at its own indentation; its actions parse at the top
    # level, so the parse fails only at its table, lines further on
    text = (CREATURE + CONTROLLER).replace(
        "  signal reach = select(abs(speed) < 1 mm/s, stroke, 2 * stroke)\n",
        "  signal reach = select(abs(speed) < 1 mm/s, stroke, 2 * stroke)\n}\n"
        "  # a comment\n  action a() {\n    record r = 1\n  }\n  action b() {\n    record q = 2\n  }\n",
    )
    message = told(text)
    assert message.startswith(
        "f.leg:14:1: error: one '}' too many: this one closes controller 'hop' (line 9)"
    ), message


@pytest.mark.parametrize("ch", ["\u2028", "\u2029"])
def test_a_line_separator_in_a_comment_is_named(ch: str) -> None:
    message = told(f"# a hopper{ch}use raibert\n" + CREATURE)
    assert message.startswith(
        f"f.leg:1:11: error: an invisible character ({'LINE' if ch == chr(0x2028) else 'PARAGRAPH'} SEPARATOR"
    )
    assert "in a comment or a string, what follows it on its line is part of it" in message
