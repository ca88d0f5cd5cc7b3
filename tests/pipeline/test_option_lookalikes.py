"""``--set 'speed=−1m/s'`` (U+2212) was told only "not a number with an optional unit", where
the same character in a .leg file is told "'−' is a typographic minus sign"; options now say
what a look-alike character is, with the lang's own sentences."""

from __future__ import annotations

import pytest

from legdsl.lang.errors import UsageError
from legdsl.pipeline.settings import parse_given


@pytest.mark.parametrize(
    ("value", "said"),
    [
        ("−1m/s", "'−' is a typographic minus sign: write the ASCII '-', as in '-1m/s'"),
        ("–1m/s", "'–' is a dash (EN DASH, U+2013), not a minus sign: write the ASCII '-'"),
        ("１m/s", "'１' is FULLWIDTH DIGIT ONE, U+FF11, not the ASCII '1' it looks like"),
        ("1㎧", "'㎧' is one character (SQUARE M OVER S, U+33A7) for 'm/s'"),
    ],
)
def test_a_lookalike_character_in_an_option_is_named(value: str, said: str) -> None:
    with pytest.raises(UsageError) as e:
        parse_given(value, "--set 'speed=...'")
    assert said in str(e.value)
