"""The sentences for a word too many among properties, one '}' too many, a controller's line
without a kind and an unquoted 'use' path (lang.stray_words, lang.structure_slips) are
given where the slip is plain, and not where the parse failed for another reason; the
cases they are given in are in tests/bad (syntax_unit_twice, syntax_extra_brace_*, ...)."""

from __future__ import annotations

import pytest

from legdsl.lang.errors import LegError
from legdsl.lang.parser import parse
from legdsl.lang.structure_slips import _passes

HOPPER = """\
creature hopper {
  planar
  gravity 9.81 m/s^2
  body trunk free {
    mass 10 kg  inertia 0.4 kg*m^2
    initial x = 0 m, z = 0.95 m
  }
  body shank on trunk via prismatic slide at (0 m, 0 m) {
    length 0.5 m  com 0.25 m  mass 0.3 kg  inertia 0.006 kg*m^2
  }
  contact toe on shank at tip
}

controller hop {
  param kp = 150 N*m/rad
  param stroke = 3 cm
  table {
    state FLIGHT on liftoff(toe): slide.rest = 0 m
    state STANCE on touchdown(toe): slide.rest = stroke
  }
}
"""


def message(text: str) -> tuple[str, str]:
    with pytest.raises(LegError) as info:
        parse(text, "f.leg")
    diag = info.value.diagnostics[0]
    return diag.message, f"{diag.span.line}:{diag.span.col}"


def test_the_example_parses() -> None:
    parse(HOPPER, "f.leg")


def test_a_key_missing_its_equals_sign_is_not_called_a_word_too_many() -> None:
    # 'initial x 0 m': the words before the number are the property's own key and name
    told, _ = message(HOPPER.replace("initial x = 0 m", "initial x 0 m"))
    assert "word too many" not in told and "alone" not in told


def test_a_unit_word_after_a_number_on_its_line_is_told_as_a_unit() -> None:
    # '10 kgs' is the misspelt unit's sentence, not a word too many
    told, where = message(HOPPER.replace("mass 10 kg  inertia", "mass 10 kgs  inertia"))
    assert "kgs" in told and "word too many" not in told and where == "5:13"


def test_a_brace_too_many_in_an_unindented_file_is_not_guessed() -> None:
    # with no indentation to go by, a '}' that closes early cannot be told from a right one
    flat = "\n".join(line.strip() for line in HOPPER.split("\n"))
    told, where = message(flat.replace("}\nbody shank", "}\n}\nbody shank"))
    assert "'}' too many" not in told and "cannot start a line" not in told and where == "9:1"


def test_a_misspelt_top_level_keyword_is_not_blamed_on_the_brace_before_it() -> None:
    told, where = message(HOPPER.replace("controller hop", "controlr hop"))
    assert "did you mean 'controller'" in told and where == "14:1"


def test_a_word_in_a_declaration_s_value_is_not_a_line_of_the_controller() -> None:
    # 'per' is the value's mistake, mid-line: not "a declaration starts with its kind"
    told, where = message(HOPPER.replace("param stroke = 3 cm", "param stroke = 3 cm per s"))
    assert "cannot start a line" not in told and "table row" not in told and where == "16:23"


def test_a_quoted_use_path_passes_the_parse() -> None:
    assert parse('use "lib/gaits.leg"\n' + HOPPER, "f.leg").uses[0].target == "lib/gaits.leg"


def test_a_colour_comment_taking_a_brace_inside_a_string_is_not_told() -> None:
    # a '#' inside a string starts no comment: the '}' after it is read
    told, _ = message(HOPPER.replace("mass 10 kg  inertia", 'label "c #a0a0a0 }" kg  inertia'))
    assert "'#' starts a comment" not in told


def test_a_brace_is_one_too_many_only_if_the_file_reads_on_well_without_it() -> None:
    # Taking away a '}' the file needs leaves a block open at its end; a mistake on the line
    # after the one the parse failed on may be the same slip read another way.
    body = "creature a {\n  planar\n  body b free {\n    mass 1 kg\n"
    failed_at = len(body) - 3  # on 'mass 1 kg'
    assert not _passes(body + "}\n", failed_at)  # still open at the end
    assert not _passes(body + "mass }\n}\n", failed_at)  # fails on the next line
    assert _passes(body + "  }\n  contact c on b\n  mass\n}\n}\n", failed_at)
    assert _passes(body + "}\n}\n", failed_at)
