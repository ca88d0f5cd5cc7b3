"""``run.metrics(min_stance=...)`` is ``legdsl metrics --min-stance``: seconds or a text with
its unit, a wrong one refused naming the argument."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import CREATURES

import legdsl
from legdsl.lang.errors import UsageError


@pytest.fixture(scope="module")
def run(generated: Path) -> legdsl.api.Run:
    return legdsl.load(CREATURES / "hopper.leg", generated=generated).run(controller="hop", time=2)


def test_min_stance_is_read_with_its_unit_and_leaves_shorter_contacts_out(
    run: legdsl.api.Run,
) -> None:
    plain = run.metrics(start=0.1)
    assert plain.options["min_stance_s"] is None and plain.summary("stance_duration").n == 3
    assert run.metrics(start=0.1, min_stance="20 ms").table() == plain.table()  # no scuffs
    assert run.metrics(start=0.1, min_stance=0.02).options["min_stance_s"] == 0.02
    longer = run.metrics(start=0.1, min_stance="1 s")  # longer than every stance of the hop
    assert plain.n_strides == 2 and longer.n_strides == 0
    assert longer.summary("stance_duration").n == 0


@pytest.mark.parametrize(
    ("value", "said"),
    [
        ("20 kg", "min_stance='20 kg': min_stance= is a time"),
        (0, "min_stance= is seconds, a number more than zero"),
        (True, "min_stance= is seconds"),
        ([0.02], "min_stance= is seconds"),
    ],
)
def test_a_wrong_min_stance_is_refused(run: legdsl.api.Run, value: object, said: str) -> None:
    with pytest.raises(UsageError, match=said):
        run.metrics(min_stance=value)  # type: ignore[arg-type]
