"""The advice of legdsl run's option checks leads to a run, not to the next refusal:
'--time 1e-320' was told 'give --record-rate infHz or more', '--time 2e-12' a record rate that
then met '--dt 0.0004s is longer than the run', '--dt 1e-170' 'give --dt 1e-09s or more' while
1e-160 passed, and '0.03m/s' for a length 'write e.g. 0.03cm' (100 times less than 0.03 m)."""

from __future__ import annotations

import re

import pytest

from legdsl.lang.errors import UsageError
from legdsl.lang.units import KINDS
from legdsl.pipeline.options import Numeric, check_run_options, read_numeric
from legdsl.pipeline.settings import check_dimension, parse_given
from legdsl.sim.run_loop import RunOptions


def refusal(options: RunOptions) -> str:
    with pytest.raises(UsageError) as e:
        check_run_options(options)
    return str(e.value)


@pytest.mark.parametrize("record_rate", [200.0, 0.0])
def test_a_run_shorter_than_its_step_is_told_so_first(record_rate: float) -> None:
    said = refusal(RunOptions(duration=2e-12, record_rate=record_rate))
    assert (
        "--dt 0.0004s is longer than the run (--time 2e-12s); give --time 0.0004s or more" in said
    )
    assert "or a --dt of 2e-12s or less" in said


def test_a_run_too_short_for_any_step_is_not_advised_one() -> None:
    said = refusal(RunOptions(duration=1e-320))
    assert "longer than the run" in said and "inf" not in said and "a --dt of" not in said


def test_the_smallest_step_advised_is_the_smallest_that_passes() -> None:
    said = refusal(RunOptions(duration=1.0, dt=1e-170, control_dt=1e-170))
    least = float(re.search(r"give --dt (\S+)s or more", said).group(1))  # type: ignore[union-attr]
    assert least * least > 0 and (least / 10) ** 2 == 0
    check_run_options(RunOptions(duration=1e-150, dt=least, control_dt=least, record_rate=0.0))


def test_a_wrong_unit_is_advised_with_the_users_own() -> None:
    with pytest.raises(UsageError, match=r"write e\.g\. stroke=0\.03m$"):
        check_dimension("--set 'stroke=0.03m/s'", "stroke is a length", parse_given("0.03m/s", "x"),
                        KINDS["length"][0], "stroke={}", "cm")  # fmt: skip
    with pytest.raises(
        UsageError, match=r"write e\.g\. --min-stance 20s, or 20ms if the m meant milli$"
    ):
        read_numeric("--min-stance", "20m", Numeric("time", "s"))
    with pytest.raises(UsageError, match=r"write e\.g\. speed=2m/s$"):  # no prefix to keep
        check_dimension("--set 'speed=2m'", "speed is a velocity", parse_given("2m", "x"),
                        KINDS["velocity"][0], "speed={}")  # fmt: skip
