"""Two numbers told side by side are told apart: a fall was told 'the root fell to 0.21 m
above the ground (the limit is 0.21 m)' (an outside user's, at 0.2099 m)."""

from __future__ import annotations

from legdsl.lang.units import apart


def test_numbers_that_round_alike_get_the_digits_that_tell_them_apart() -> None:
    assert apart(0.2099, 0.21) == ("0.2099", "0.21")
    assert apart(0.899, 0.9) == ("0.899", "0.9")  # three digits tell these already
    assert apart(1.0000001, 1.0) == ("1.0000001", "1")
    assert apart(0.21, 0.21) == ("0.21", "0.21")  # equal numbers are shown alike
    assert apart(-0.0, 0.0) == ("-0", "0")
