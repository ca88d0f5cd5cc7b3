"""``run.metrics(friction_edge=...)`` is ``legdsl metrics --friction-edge``: seconds or a text
with its unit, a wrong one refused naming the argument."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import CREATURES

import legdsl
from legdsl.lang.errors import UsageError


@pytest.fixture(scope="module")
def run(generated: Path) -> legdsl.api.Run:
    return legdsl.load(CREATURES / "hopper.leg", generated=generated).run(controller="hop", time=2)


def test_the_friction_edge_is_read_with_its_unit(run: legdsl.api.Run) -> None:
    paper = run.metrics(start=0.1)
    assert paper.options["friction_edge_s"] == 0.01  # the paper's, by default
    assert run.metrics(start=0.1, friction_edge="10 ms").table() == paper.table()
    short = run.metrics(start=0.1, friction_edge=0.002)
    assert short.options["friction_edge_s"] == 0.002
    assert "past first/last 2 ms" in short.table() and "past first/last 10 ms" in paper.table()


@pytest.mark.parametrize(
    ("value", "said"),
    [
        ("2 kg", "friction_edge='2 kg': friction_edge= is a time"),
        (-0.001, "friction_edge= is seconds, a number 0 or more"),
        (True, "friction_edge= is seconds"),
    ],
)
def test_a_wrong_friction_edge_is_refused(run: legdsl.api.Run, value: object, said: str) -> None:
    with pytest.raises(UsageError, match=said):
        run.metrics(friction_edge=value)  # type: ignore[arg-type]
