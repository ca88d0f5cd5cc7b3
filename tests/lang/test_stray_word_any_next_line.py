"""A word too many after a property's value, last on its line, is told at the word whatever
follows it: a property written with '=' ('initial x = 0 m', where the parse fails at the
'='), a list ('joints hip, knee', at the ','), a number, a string, the block's '}', or a
property that lets the file parse ('shape box(...)'). A unit after a call's ')' is told
as the call's units (lang.stray_words)."""

from __future__ import annotations

import pytest

from legdsl.lang.errors import LegError
from legdsl.lang.parser import parse

BODY = """\
creature hopper {
  planar
  gravity 9.81 m/s^2
  body trunk free {
    mass 10 kg  inertia 0.5 kg*m^2
STRAY
NEXT
  }
  body shank on trunk via prismatic slide at (0 m, 0 m) {
    length 0.5 m  com 0.25 m  mass 0.3 kg  inertia 0.006 kg*m^2
  }
  contact toe on shank at tip
}
"""

STRAYS = {
    # the line, the column of the word too many, a part of the sentence
    "word": ("    shape box(0.4 m, 0.1 m) foo", 29, "'foo' is a word too many"),
    "word after a vector": ("    com (0.1, 0) m foo", 20, "'foo' is a word too many"),
    "unit twice": ("    mass 10 kg kg", 16, "'10 kg' has its unit already: remove this 'kg'"),
    "unit of a product twice": (
        "    inertia 0.5 kg*m^2 kg",
        24,
        "'0.5 kg*m^2' has its unit already: remove this 'kg'",
    ),
    "unit after a call": (
        "    shape box(0.4, 0.1) m",
        25,
        "write 'box(0.4 m, 0.1 m)'",
    ),
}
NEXTS = {
    "initial": "    initial x = 0 m, z = 1 m, pitch = 0 deg",
    "velocity": "    velocity x = 1 m/s",
    "limits": "    limits -60 deg to 60 deg",
    "mass": "    mass 10 kg",
    "color": '    color "#406080"',
    "joints": "    joints hip, knee",
    "shape": "    shape box(0.4 m, 0.1 m)",
    "com": "    com (0.1 m, 0 m)",
    "brace": None,
}


def told(text: str) -> tuple[str, int, int]:
    with pytest.raises(LegError) as info:
        parse(text, "f.leg")
    diag = info.value.diagnostics[0]
    return diag.message, diag.span.line, diag.span.col


@pytest.mark.parametrize("stray", list(STRAYS))
@pytest.mark.parametrize("next_line", list(NEXTS))
def test_a_word_too_many_is_told_at_the_word_whatever_follows(stray: str, next_line: str) -> None:
    line, col, sentence = STRAYS[stray]
    after = NEXTS[next_line]
    text = BODY.replace("STRAY", line).replace("NEXT\n", "" if after is None else after + "\n")
    message, at_line, at_col = told(text)
    assert (at_line, at_col) == (6, col), message
    assert sentence in message
    assert "properties take no '='" not in message


def test_a_unit_after_a_call_names_the_call_and_keeps_keyword_arguments() -> None:
    text = BODY.replace("STRAY", "    shape capsule(radius = 0.05, length = 0.3) m").replace(
        "NEXT", "    initial x = 0 m"
    )
    message, line, col = told(text)
    assert (line, col) == (6, 48)
    assert "write 'capsule(radius = 0.05 m, length = 0.3 m)'" in message


def test_a_word_before_the_brace_on_its_line_is_told() -> None:
    text = BODY.replace("STRAY\nNEXT\n  }", "    mass 3 kg foo }")
    message, line, col = told(text)
    assert (line, col) == (6, 15) and "no value before the block's '}'" in message


@pytest.mark.parametrize(
    ("line", "after"),
    [
        ("    com (0.1, 0) m", "    initial x = 0 m z = 1 m"),  # a vector's unit is its own
        ("    mass 10 kg", "    initial x = 0 m z = 1 m"),
    ],
)
def test_a_value_s_own_unit_is_not_a_word_too_many(line: str, after: str) -> None:
    message, at_line, _ = told(BODY.replace("STRAY", line).replace("NEXT", after))
    assert at_line == 7 and "word too many" not in message and "already" not in message


def test_a_word_before_the_next_item_of_the_creature_is_told() -> None:
    # 'foo' took 'body' and the parse failed at the body's '{'
    text = BODY.replace("  gravity 9.81 m/s^2\n", "  gravity 9.81 m/s^2 foo\n").replace(
        "STRAY\nNEXT\n", ""
    )
    message, line, col = told(text)
    assert (line, col) == (3, 22) and "'foo' took the next line's 'body'" in message


def test_a_word_before_a_block_s_next_call_is_told() -> None:
    # 'tangent spring(k = ...)' read as the value 'tangent' and a vector '(k = ...'
    ground = (
        "  ground {\n    normal spring(k = 2e4 N/m, b = 200 N*s/m) foo\n"
        "    tangent spring(k = 1e4 N/m, b = 100 N*s/m)\n  }\n}\n"
    )
    text = BODY.replace("STRAY\nNEXT\n", "").removesuffix("}\n") + ground
    message, line, col = told(text)
    assert (line, col) == (12, 47) and "'foo' took 'tangent'" in message


@pytest.mark.parametrize(
    "line",
    [
        '    shape cylinder(0.03 m)  color "#8b4513"',  # a string: blank to the slips' reading
        "    com (0.1, 0) m  # a vector's unit",
    ],
)
def test_a_line_that_ends_in_a_whole_value_is_not_blamed_for_the_next(line: str) -> None:
    message, at_line, _ = told(
        BODY.replace("STRAY", line).replace("NEXT", "    initial x = 0 m z = 1 m")
    )
    assert at_line == 7 and "word too many" not in message and "takes each value" not in message


def test_a_gait_band_alone_after_a_value_is_not_a_word_too_many() -> None:
    scene = (
        "scene s {\n  gait by speed {\n    walk to 1 m/s  trot\n    gallop from = 2 m/s\n  }\n}\n"
    )
    message, line, _ = told(BODY.replace("STRAY\nNEXT\n", "") + scene)
    assert line == 15 and "word too many" not in message
