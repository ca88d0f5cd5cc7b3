"""A creature's ``simulation`` block (the step, control interval and record rate of a small
or scaled creature) sets ``run``'s, ``run_many``'s and ``run_copies``' defaults, as it sets
``legdsl run``'s: the 3 g insect_pogo runs at its 0.1 ms step, not the runner's 0.4 ms."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import ROOT

import legdsl

POGO = ROOT / "tests" / "good" / "outside" / "insect_pogo.leg"  # dt 0.1 ms, 0.5 ms, 800 Hz


@pytest.fixture(scope="module")
def pogo(generated: Path) -> legdsl.api.Creature:
    return legdsl.load(POGO, generated=generated)


def _steps(run: legdsl.api.Run) -> tuple[float, float, float]:
    o = run.info["options"]
    return o["dt"], o["control_dt"], o["record_rate"]


def test_run_takes_the_files_step_control_interval_and_record_rate(pogo) -> None:
    assert _steps(pogo.run(controller="hop", time=0.05)) == (1e-4, 5e-4, 800.0)
    ((_, many),) = pogo.run_many([{"controller": "hop", "time": 0.05}])
    assert _steps(many) == (1e-4, 5e-4, 800.0)
    copies = pogo.run_copies(2, "hop", time=0.05)
    assert _steps(copies[1]) == (1e-4, 5e-4, 800.0)


def test_an_option_given_overrides_only_itself(pogo) -> None:
    run = pogo.run(controller="hop", time=0.05, dt="0.05 ms", record_rate="400 Hz")
    assert _steps(run) == (5e-5, 5e-4, 400.0)
