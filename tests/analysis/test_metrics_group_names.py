"""A --group named like a leg, or two groups of one name: the error said what was wrong but
not what to write instead."""

from __future__ import annotations

import pytest

from legdsl.analysis.metrics import compute_metrics, parse_groups
from legdsl.analysis.results import MetricsError


def test_two_groups_of_one_name_say_to_name_each() -> None:
    with pytest.raises(MetricsError, match="is given twice: give each --group a name of its own"):
        parse_groups(["a=fl,mr,rl", "a=fr,ml,rr"])


def test_a_group_named_like_a_leg_says_what_to_write() -> None:
    from test_metrics import Hopper

    with pytest.raises(
        MetricsError, match=r"give it a name of its own \(--group main_group=main\)"
    ):
        compute_metrics(Hopper().run(1.0), groups={"main": ["main"]})
