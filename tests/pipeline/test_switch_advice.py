"""``--switch 1m=gallop`` was advised "write e.g. --switch 1s, or 1ms if the m meant
milli=gallop": the alternatives were put whole in the place of the value. Each is written as
a whole option now."""

from __future__ import annotations

import pytest

from legdsl.lang.errors import UsageError
from legdsl.lang.units import KINDS
from legdsl.pipeline.settings import check_dimension, parse_given


def test_each_suggested_value_is_a_whole_option() -> None:
    with pytest.raises(UsageError) as e:
        check_dimension("--switch 1m=gallop", "the time before '=' is in seconds",
                        parse_given("1m", "x"), KINDS["time"][0], "--switch {}=gallop")  # fmt: skip
    assert str(e.value).endswith(
        "write e.g. --switch 1s=gallop, or --switch 1ms=gallop if the m meant milli"
    )
    with pytest.raises(UsageError) as e:  # a frequency for a time: its reciprocal, whole
        check_dimension("--switch 2Hz=gallop", "the time before '=' is in seconds",
                        parse_given("2Hz", "x"), KINDS["time"][0], "--switch {}=gallop")  # fmt: skip
    assert str(e.value).endswith("write e.g. --switch 0.5s=gallop (1/2Hz)")
