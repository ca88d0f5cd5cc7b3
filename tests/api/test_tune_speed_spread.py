"""The speed's stride-to-stride spread: seen by the tune's report and, with --spread-weight, by
its objective. The monopod's tuned gains ran 2.985 m/s at 3 m/s, reported as a near-perfect
"2.985", while swinging between 2.5 and 3.5 m/s over seconds (0.44 m/s from stride to stride);
a tune scored it 0.005 and had nothing to improve there."""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

import pytest

from legdsl.analysis.results import Summary
from legdsl.api.tune import Objective, score, tune_speed

SWINGING = {"outcome": "ok", "running_speed": 2.985, "running_speed_std": 0.44,
            "simulated": 10.0, "by_label": {}}  # fmt: skip


def test_the_spread_weight_adds_the_speeds_spread_relative_to_the_command() -> None:
    plain = Objective(speeds=(3.0,), duration=10.0, start=3.0)
    spread = Objective(speeds=(3.0,), duration=10.0, start=3.0, spread_weight=1.0)
    assert score([SWINGING], plain) == pytest.approx(0.005)
    assert score([SWINGING], spread) == pytest.approx(0.005 + 0.44 / 3)
    in_place = Objective(speeds=(0.0, 2.0), duration=10.0, start=3.0, spread_weight=1.0)
    still = {**SWINGING, "running_speed": 0.0, "running_speed_std": 0.2}
    steady = {**SWINGING, "running_speed": 2.0, "running_speed_std": 0.0}
    assert score([still, steady], in_place) == pytest.approx(0.2 / 2 / 2)  # against 2 m/s


def test_the_report_shows_the_speeds_spread() -> None:
    assert tune_speed(SWINGING) == "2.985 ± 0.44"
    fell = {**SWINGING, "outcome": "fell at 4.842 s"}
    assert tune_speed(fell) == "2.985 ± 0.44 (fell at 4.842 s)"


def test_a_sweep_row_keeps_the_speeds_spread(monkeypatch: pytest.MonkeyPatch) -> None:
    import legdsl.api.sweep as sweep_module
    from legdsl.api.sweep import Job, run_batch_of_jobs

    speed = Summary("running_speed", "running speed (m/s)", 2.985, 0.44, 12)

    class FakeRun:
        status, info = "ok", {"sim_time": 10.0}

        def metrics(self, start: float) -> Any:
            return SimpleNamespace(summaries=[speed], n_strides=12)

    class FakeCreature:
        def run_many(self, runs, threads):  # type: ignore[no-untyped-def]
            yield 0, FakeRun()

    monkeypatch.setattr(sweep_module, "_creature", lambda job: FakeCreature())
    job = Job(index=0, source="x.leg", creature=None, controller="hop", values={}, units={},
              fixed=(), duration=10.0, start=3.0, generated="generated", keep=None)  # fmt: skip
    (row,) = run_batch_of_jobs([job])
    assert row["running_speed_std"] == 0.44
    assert "running_speed_std" in sweep_module.METRICS  # a column of sweep.csv too
