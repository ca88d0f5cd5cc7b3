"""A tune whose scoring window (--from to --time) is too short for a stride: an outside stilt
of 0.7 s strides tuned over 3 to 4 s at 1 and 2 m/s. Its runs at 1 m/s lasted without a whole
stride in the window, start and tuned alike: the report showed "n/a" beside an objective of 2,
a fall's score, though nothing fell; nothing warned that the window was too short, so the
search tuned 2 m/s alone; and the closing note left out 1 m/s, which ran 1.482 over twice the
time (+48%), and printed "over 3 to 8 s it runs fell" for 2 m/s."""

from __future__ import annotations

import math
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import pytest

from legdsl.analysis.results import Summary
from legdsl.api.tune import Objective, report, score, short_window, tune_speed, unsettled
from legdsl.api.tune_cli import _say_longer
from legdsl.cli import main

ROOT = Path(__file__).resolve().parents[2]
NAN = math.nan
STILT = Objective(speeds=(1.0, 2.0), duration=4.0, start=3.0)


def row(speed: float, running: float, outcome: str = "ok", **more: Any) -> dict[str, Any]:
    return {"speed": speed, "running_speed": running, "running_speed_std": NAN,
            "outcome": outcome, "simulated": 4.0, "by_label": {}, **more}  # fmt: skip


def test_a_window_without_a_stride_is_said_so_not_n_a() -> None:
    lasted = row(1.0, NAN)
    assert tune_speed(lasted) == "no whole stride"
    assert tune_speed(row(1.0, NAN, "fell at 2.000 s")) == "n/a (fell at 2.000 s)"
    assert score([lasted], Objective((1.0,), 4.0, 3.0)) == 2.0  # as said, in the report:
    result = {"start": {"values": {}, "objective": 2.0, "runs": [lasted, row(2.0, NAN)]},
              "best": {"values": {}, "objective": 1.07, "runs": [lasted, row(2.0, 2.297)]}}  # fmt: skip
    text = report(result, {})
    assert "  at 1         no whole stride      no whole stride\n" in text
    assert "no speed measured; scored 2 at that speed, as a run falling at its very end" in text


def test_a_window_too_short_for_a_stride_of_the_start_is_warned_of() -> None:
    rows = [row(1.0, NAN, run_stride_duration=0.674), row(2.0, NAN, run_stride_duration=0.632)]
    told = short_window(rows, STILT)
    assert told is not None
    assert "from --from 3 s to --time 4 s (1 s), held no whole stride of the file's own " in told
    assert "values at 1, 2 m/s" in told and "scores 2 there" in told
    assert told.endswith("about 0.67 s over the whole run: give a window of three strides or "
                         "more, --time 5.5 (or --from 1.5)")  # fmt: skip
    assert short_window([row(1.0, 1.1), row(2.0, 2.1)], STILT) is None
    assert short_window([row(1.0, NAN, "fell at 3.5 s"), row(2.0, 2.1)], STILT) is None
    never = short_window([row(1.0, NAN, run_stride_duration=NAN), row(2.0, 2.1)], STILT)
    assert never is not None and "no whole stride over the whole run either" in never
    assert "at 1 m/s:" in never and "--time" not in never.partition("; ")[2]


def test_every_speed_that_moved_is_in_the_closing_note(capsys: pytest.CaptureFixture[str]) -> None:
    scored = [row(1.0, NAN), row(2.0, 2.297)]
    longer = [row(1.0, 1.482), row(2.0, 2.859, "fell at 5.608 s")]
    found = unsettled(scored, longer, STILT.speeds)
    assert [s for s, _, _ in found] == [1.0, 2.0] and found[0][2] == 1.482
    assert unsettled([row(1.0, NAN)], [row(1.0, NAN)], (1.0,)) == []  # neither measured one
    _say_longer({"best": {"runs": scored}, "longer": longer}, STILT)
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err
    assert ("had not settled by --time 4 at 1, 2 m/s: over 3 to 8 s it runs 1.482 (+48.2%) at "
            "1 m/s and fell at 5.608 s at 2 m/s, against no whole stride and 2.297 (+14.9%) "
            "scored over 3 to 4 s; tune with a longer --time (8)") in err  # fmt: skip


def test_a_sweep_row_without_a_stride_keeps_the_whole_runs_stride(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    import legdsl.api.sweep as sweep_module
    from legdsl.api.sweep import Job, run_batch_of_jobs

    class FakeRun:
        status, info = "ok", {"sim_time": 4.0}

        def metrics(self, start: float) -> Any:
            if start == 0.0:  # the whole run
                stride = Summary("stride_duration", "stride duration (s)", 0.674, 0.01, 5)
                return SimpleNamespace(summaries=[stride], n_strides=5,
                                       value=lambda key: {"stride_duration": 0.674}[key])  # fmt: skip
            return SimpleNamespace(summaries=[], n_strides=0)

    class FakeCreature:
        def run_many(self, runs, threads):  # type: ignore[no-untyped-def]
            yield 0, FakeRun()

    monkeypatch.setattr(sweep_module, "_creature", lambda job: FakeCreature())
    job = Job(index=0, source="x.leg", creature=None, controller="hop", values={}, units={},
              fixed=(), duration=4.0, start=3.0, generated="generated", keep=None)  # fmt: skip
    (got,) = run_batch_of_jobs([job])
    assert got["strides"] == 0 and got["run_stride_duration"] == 0.674


@pytest.mark.usefixtures("hopper_modules")
def test_a_tune_on_a_window_too_short_says_so_before_its_generations(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The hopper strides every 0.63 s: a window of 1.5 to 2 s holds none."""
    code = main(["tune", str(ROOT / "creatures" / "hopper.leg"), "--controller", "hop",
                 "--param", "k_speed=0.02:0.2", "--speeds", "1", "--time", "2", "--from", "1.5",
                 "--generations", "1", "--popsize", "2", "--jobs", "1", "--out",
                 str(tmp_path / "t"), "--generated", str(tmp_path / "generated")])  # fmt: skip
    assert code == 0
    told = capsys.readouterr()
    assert "legdsl: warning: the scoring window, from --from 1.5 s to --time 2 s (0.5 s), " in (
        told.err
    )
    assert "a stride there takes about 0.63 s over the whole run: give a window of three " in (
        told.err
    )
    assert "--time 3.5 (or --from 0)" in told.err
    assert "  at 1         no whole stride" in told.out
