"""``Run.metrics(joint=, against=)``: the rows of ``legdsl metrics --joint --against`` (the
kangaroo's tail against its hip, a Table 2 row) could not be had from the API, which had no
such arguments. They are measured as the command measures them, and checked as it checks
them, in the words of the call."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import ROOT

import legdsl
from legdsl.lang.errors import UsageError
from legdsl.pipeline.measure import measure_run


@pytest.fixture(scope="module")
def hopper(generated: Path) -> legdsl.api.Creature:
    return legdsl.load(ROOT / "creatures" / "hopper.leg", generated=generated)


@pytest.fixture(scope="module")
def run(hopper: legdsl.api.Creature) -> legdsl.api.Run:
    return hopper.run(controller="hop", set={"speed": "1 m/s"}, time=3)


def test_joint_and_against_are_the_command_s_rows(
    run: legdsl.api.Run, tmp_path: Path, generated: Path
) -> None:
    metrics = run.metrics(start=1, joint="hip", against="pitch")
    cli, _ = measure_run(run.save(tmp_path / "r"), 1.0, joint="hip", against="pitch",
                         generated=generated)  # fmt: skip
    assert metrics.to_dict() == cli.to_dict()
    rows = {s.key: s for s in metrics.summaries}
    assert rows["joint_magnitude"].label == "magnitude of hip (deg)"
    assert rows["joint_magnitude"].n > 0 and -1 <= rows["joint_correlation"].value <= 1


def test_a_sliding_joint_s_magnitude_is_a_length(run: legdsl.api.Run) -> None:
    rows = {s.key: s for s in run.metrics(start=1, joint="leg").summaries}
    assert rows["joint_magnitude"].label == "magnitude of leg (m)"


@pytest.mark.parametrize(
    ("given", "told"),
    [
        ({"against": "hip"}, "metrics(): against='hip' needs joint=: the correlation is of the"),
        ({"joint": "hp"}, "metrics(): joint='hp': no coordinate named so; did you mean 'hip'?"),
        ({"joint": "hip", "against": 3}, "metrics(): against= is the name of a coordinate"),
    ],
)
def test_a_joint_the_run_has_not_is_told_in_the_call_s_words(
    run: legdsl.api.Run, given: dict, told: str
) -> None:
    with pytest.raises(UsageError) as caught:
        run.metrics(**given)
    assert str(caught.value).startswith(told), caught.value


def test_a_quaternion_component_is_no_joint(generated: Path) -> None:
    biped = legdsl.load(ROOT / "creatures" / "biped.leg", generated=generated)
    run = biped.run(controller=None, time=0.05)
    with pytest.raises(UsageError, match=r"^metrics\(\): joint='qw' is a component of the root"):
        run.metrics(joint="qw")
