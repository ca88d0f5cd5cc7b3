"""Friendly messages for common syntax slips (grammar/friendly_errors.toml).

Each entry's examples must give exactly its message; so must a realistic
multi-line file with the same slip deeper inside it (after other items, in
another body, with comments), which is where matching by example can fail.
"""

from __future__ import annotations

import pytest

from legdsl.lang.errors import LegError
from legdsl.lang.parser import parse
from legdsl.lang.syntax_errors import friendly_errors

ENTRIES = friendly_errors()
EXAMPLES = [(message, example) for message, examples in ENTRIES for example in examples]

HOPPER = """\
# A planar hopper.
creature hopper {
  planar
  gravity 9.81 m/s^2
  body trunk free {
    mass 3 kg
    inertia 0.03 kg*m^2   # about y
  }
  body shank on trunk via prismatic slide at (0 m, -0.05 m) {
    mass 1 kg  inertia 0.01 kg*m^2  length 0.5 m
  }
  contact toe on shank at tip
  leg main { joints slide  foot toe  alias spring = leg_spring }
  actuator leg_spring on slide spring(k = 1000 N/m, b = 10 N*s/m)
}
"""


def controller(table: str, before: str = "") -> str:
    return (
        HOPPER
        + "\ncontroller hop {\n  input speed = 2 m/s\n  roles active = main\n"
        + before
        + "  table {\n"
        + table
        + "  }\n}\n"
    )


# A fragment of each entry's message -> a realistic file with that slip, and
# the line:col where it must be reported.
TEMPLATE = """\
  template foot(S) {
    contact toe_S on shank at tip  # one foot
  }
"""

REALISTIC: dict[str, tuple[str, str]] = {
    "write an instance as": (
        HOPPER.replace("  leg main", TEMPLATE + "  instance front foot(S = f)\n  leg main"),
        "16:18",
    ),
    "say which mirror": (
        HOPPER.removesuffix("}\n") + TEMPLATE + "  instance front = foot(S = f) mirror\n}\n",
        "19:1",
    ),
    "properties take no '='": (
        HOPPER.replace("length 0.5 m", "length = 0.5 m"),
        "10:44",
    ),
    "properties take no ':'": (
        HOPPER.replace("  gravity 9.81 m/s^2", "  gravity: 9.81 m/s^2"),
        "4:10",
    ),
    "a '}' is missing: a block is still open at the end": (
        HOPPER.removesuffix("}\n") + "  # the end\n",
        "14:66",
    ),
    "a '}' is missing: a new declaration starts here": (
        HOPPER.replace("    inertia 0.03 kg*m^2   # about y\n  }\n", "    inertia 0.03 kg*m^2\n"),
        "8:3",
    ),
    "a '{' is missing": (
        HOPPER.replace(
            "at (0 m, -0.05 m) {\n    mass 1 kg  inertia 0.01 kg*m^2  length 0.5 m\n  }",
            "at (0 m, -0.05 m)\n    mass 1 kg  inertia 0.01 kg*m^2  length 0.5 m",
        ),
        "10:5",
    ),
    "a joint needs a kind and a name": (
        HOPPER.replace("via prismatic slide at", "via prismatic at"),
        "9:40",
    ),
    "a body hangs from its parent 'via' a joint": (
        HOPPER.replace("on trunk via prismatic slide", "on trunk prismatic slide"),
        "9:23",
    ),
    "put commas between": (
        HOPPER.replace("spring(k = 1000 N/m, b = 10 N*s/m)", "spring(k = 1000 N/m b = 10 N*s/m)"),
        "14:52",
    ),
    "';' separates the actions": (
        HOPPER.replace("mass 1 kg  inertia", "mass 1 kg;  inertia"),
        "10:14",
    ),
    "the ':' after the event is missing": (
        controller(
            "    state FLIGHT on liftoff(active): active.spring.rest = 0.1 m\n"
            "    state STANCE on active.length < 0.4 m\n"
            "      active.spring.rest = 0 m\n"
        ),
        "23:7",
    ),
    "the 'on' before the event is missing": (
        controller("    state FLIGHT active.length > 0.5 m: active.spring.rest = 0.1 m\n"),
        "21:18",
    ),
    "a table row starts with the word 'state'": (
        controller(
            "    state FLIGHT on liftoff(active): active.spring.rest = 0.1 m\n"
            "    # the stance phase\n"
            "    STANCE on touchdown(active): active.spring.rest = 0 m\n"
        ),
        "23:5",
    ),
    "actions in a row or an action body are separated by ';'": (
        controller(
            "    state FLIGHT on liftoff(active): lengthen(active)\n",
            before="  action lengthen(l) {\n"
            "    l.spring.rest = 0.1 m\n"
            "    l.spring.k = 900 N/m\n"
            "  }\n",
        ),
        "22:5",
    ),
    "'==' compares; a statement sets a value": (
        controller("    state FLIGHT on liftoff(active): active.spring.rest == 0.1 m\n"),
        "21:58",
    ),
    "properties are not separated by ','": (
        HOPPER.replace("mass 1 kg  inertia 0.01 kg*m^2", "mass 1 kg, inertia 0.01 kg*m^2"),
        "10:24",
    ),
    "a comparison needs a value on both sides": (
        controller("    state FLIGHT on active.touching = 0: active.spring.rest = 0.1 m\n"),
        "21:37",
    ),
}


def only_diagnostic(text: str) -> tuple[str, str]:
    with pytest.raises(LegError) as info:
        parse(text, "f.leg")
    (diag,) = info.value.diagnostics
    return diag.message, f"{diag.span.line}:{diag.span.col}"


@pytest.mark.parametrize(("message", "example"), EXAMPLES, ids=[e for _, e in EXAMPLES])
def test_example_gives_its_message(message: str, example: str) -> None:
    assert only_diagnostic(example)[0] == message


def test_every_entry_has_one_realistic_case() -> None:
    for message, _ in ENTRIES:
        fragments = [f for f in REALISTIC if f in message]
        assert len(fragments) == 1, (message, fragments)
    assert len(REALISTIC) == len(ENTRIES)


@pytest.mark.parametrize("fragment", sorted(REALISTIC))
def test_realistic_file_gives_the_message(fragment: str) -> None:
    text, where = REALISTIC[fragment]
    (message,) = [m for m, _ in ENTRIES if fragment in m]
    assert only_diagnostic(text) == (message, where)


def test_plain_message_when_no_example_fits() -> None:
    # '}' where a property value belongs matches no example: the parser's own words.
    message, where = only_diagnostic("creature a {\n  planar\n  body b free { mass }\n}\n")
    assert message == "unexpected '}'; expected '(', '-', a name, a number, a string"
    assert where == "3:22"


def test_examples_of_different_slips_that_fit_equally_give_the_plain_message() -> None:
    # After 'rest = 0.1 m' a name could start a row that lacks 'state' or an action that
    # lacks ';'; with nothing after it to tell them apart, neither message is given.
    message, _ = only_diagnostic(controller("    state A on liftoff(active): x = 0.1 m y\n"))
    assert message.startswith("unexpected name 'y'; expected ")


@pytest.mark.parametrize("line", ["kp2 = 1 N*m/rad", "pa", "param stroke = 3 cm per s"])
def test_a_row_s_sentence_is_not_given_outside_the_table(line: str) -> None:
    # A controller's declaration ends in an expression as a row's event does, and the parser
    # is in the same last state after it; the rest of its stack is not a row's.
    before = f"  param stroke = 3 cm\n  {line}\n"
    message, _ = only_diagnostic(controller("    state A on liftoff(active): x = 1 m\n", before))
    assert "table row" not in message and "separated by ';'" not in message
