"""The pairs' refusal counts a creature's legs in words that fit the count."""

from __future__ import annotations

import pytest

from legdsl.analysis.pairs import pair_groups
from legdsl.analysis.results import MetricsError


@pytest.mark.parametrize(("legs", "said"), [(1, "has 1 leg (l0)"), (2, "has 2 legs (l0, l1)")])
def test_a_creature_of_one_leg_has_1_leg_not_1_legs(legs: int, said: str) -> None:
    """'this creature has 1 legs (main)', quoted by legdsl tune --table2 too."""
    positions = {f"l{i}": (float(i), 0.0) for i in range(legs)}
    with pytest.raises(MetricsError, match=said.replace("(", r"\(").replace(")", r"\)")):
        pair_groups(positions, "diagonal")
