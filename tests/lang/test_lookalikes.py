"""A character that looks like an ASCII one (or an invisible line break) is named, with what
to write: the user sees the character they meant."""

from __future__ import annotations

import pytest

from legdsl.lang.errors import LegError
from legdsl.lang.lookalikes import ascii_for, lookalike
from legdsl.lang.parser import parse

HOPPER = """\
creature a {
  planar
  body trunk free { mass 5 kg  inertia 0.03 kg*m^2  initial x = 0 m, z = 1 m, pitch = 0 deg }
  body leg on trunk via revolute hip at (0 m, 0 m) { mass 1 kg  inertia 0.01 kg*m^2 }
}
"""


def _error(old: str, new: str) -> tuple[int, int, str]:
    text = HOPPER.replace(old, new, 1)
    assert text != HOPPER
    with pytest.raises(LegError) as caught:
        parse(text, "a.leg")
    (d,) = caught.value.diagnostics
    return d.span.line, d.span.col, d.message


@pytest.mark.parametrize(
    ("old", "new", "message", "fix"),
    [
        ("planar", "plаnar", "'а' is CYRILLIC SMALL LETTER A, U+0430, not the ASCII 'a'",
         "write 'a'"),
        ("mass 5 kg", "mass 5 \u212ag", "'\u212a' is KELVIN SIGN, U+212A, not the ASCII 'K'",
         "write 'K'"),
        ("pitch = 0", "pitch = \u20140", "'—' is a dash (EM DASH, U+2014), not a minus",
         "write the ASCII '-'"),
        ("at (0 m, 0 m)", "at （0 m, 0 m)", "'（' is FULLWIDTH LEFT PARENTHESIS, U+FF08",
         "write '('"),
        ("0.03 kg", "0.03 ㎏", "'㎏' is one character (SQUARE KG, U+338F) for 'kg'",
         "write the ASCII 'kg'"),
        ("planar\n", "planar\u2028", "an invisible character (LINE SEPARATOR, U+2028)",
         "replace it with an ordinary line break"),
    ],
)  # fmt: skip
def test_a_lookalike_is_named_with_what_to_write(
    old: str, new: str, message: str, fix: str
) -> None:
    line, col, told = _error(old, new)
    text = HOPPER.replace(old, new, 1)
    at = next(i for i, ch in enumerate(text) if not ch.isascii())  # the caret is on it
    assert (line, col) == (text.count("\n", 0, at) + 1, at - text.rfind("\n", 0, at))
    assert told.startswith(message)
    assert fix in told


def test_only_a_character_that_truly_looks_like_ascii_is_given_an_ascii_spelling() -> None:
    # 'º' (an ordinal, typed for '°') is no 'o'; '²' is told as a number elsewhere; a letter
    # with an accent has no ASCII twin
    assert [ascii_for(ch) for ch in "º²êµ〜"] == [None] * 5
    assert lookalike("ê") is None
    assert _error("planar", "plênar")[2].startswith("'ê' is not a letter of a name: names are")


@pytest.mark.parametrize(
    ("letter", "written"),
    [("м", "m"), ("к", "k"), ("с", "c"), ("о", "o"), ("а", "a"), ("е", "e"), ("р", "p"),
     ("х", "x"), ("у", "y"), ("ο", "o"), ("κ", "k"), ("ν", "v"), ("α", "a"), ("υ", "u"),
     ("χ", "x"), ("γ", "y"), ("ϲ", "c")],
)  # fmt: skip
def test_cyrillic_and_greek_letters_drawn_like_latin_ones_are_named(
    letter: str, written: str
) -> None:
    """'--set speed=1м/s' (a Cyrillic em) was told only that 'м/s' is no unit."""
    assert ascii_for(letter) == written
    line, col, told = _error("inertia 0.03 kg", f"inertia 0.03 {letter}g")
    assert (line, col) == (3, HOPPER.split("\n")[2].index("0.03 kg") + 6)
    assert told.startswith(f"'{letter}' is ") and f"not the ASCII '{written}'" in told


def test_a_cyrillic_em_in_an_option_unit_is_named() -> None:
    from legdsl.pipeline.settings import UsageError, parse_given

    with pytest.raises(UsageError) as caught:
        parse_given("1м/s", "--set 'speed=1м/s'")
    assert "'м' is CYRILLIC SMALL LETTER EM, U+043C, not the ASCII 'm'" in str(caught.value)
