"""legdsl metrics (and Run.metrics()) of a run that fell, diverged or was interrupted.

It measured such a run as any other, without a word and with exit status 0: a run diverged
at 0.285 s printed "3 strides" and a foot clearance at the apex of -0.336 m, and its
metrics.json held no status. Now a note says how the run ended, in plot's and animate's
words, metrics.json records it, and the window of a run that fell or diverged ends at the
reference's last touchdown before it did: the stride through the fall or the divergence is
not averaged in. A run told diverged after it ran on (an energy rise without a source) is
said to have diverged at its ``diverged_at``, as ``legdsl run`` says it, by every reader.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from conftest import CREATURES

from legdsl.analysis.plot_ending import run_ending
from legdsl.cli import main
from legdsl.sim.trajectory import empty

STEP = 0.0042  # s between samples; touchdowns of the toe at 0.252, 0.504, 0.756, 1.0038, 1.2516 s


def _run(tmp_path: Path, status: dict[str, Any]) -> Path:
    n = 300  # the last sample at 1.2558 s
    tr = empty(
        n, 3, 3, 1, 1, q_names=("x", "z", "pitch"), v_names=("x", "z", "pitch"),
        contact_names=("toe",), leg_names=("main",), leg_feet=(0,), total_mass=1.0,
    )  # fmt: skip
    tr.t[:] = np.arange(n) * STEP
    tr.contact[:, 0] = (tr.t % 0.25) / 0.25 < 0.4
    tr.com[:, 2] = 0.5 + 0.05 * np.sin(2 * np.pi * 4 * tr.t)
    tr.com_vel[:, 0] = 1.0
    tr.speed_command[:] = 1.0
    tr.save(tmp_path)
    info = {"source": str(CREATURES / "kangaroo.leg"), "creature": "kangaroo", **status}
    (tmp_path / "run.json").write_text(json.dumps(info))
    return tmp_path


# the energy rose without a source up to 1.2 s; the run went on to 1.2558 s
DIVERGED = {"status": "diverged", "ended_at": 1.2558, "diverged_at": 1.2,
            "cause": "the total energy rose from 1 J to 5e4 J"}  # fmt: skip
INTERRUPTED = {"status": "interrupted", "ended_at": 1.2558, "cause": "SIGINT"}


def _metrics(run: Path, capsys: pytest.CaptureFixture[str]) -> tuple[dict[str, Any], str]:
    assert main(["metrics", str(run)]) == 0
    err = capsys.readouterr().err
    return json.loads((run / "metrics.json").read_text()), err


def test_a_diverged_run_is_told_and_measured_up_to_its_last_touchdown_before(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    run = _run(tmp_path / "run", DIVERGED)
    data, err = _metrics(run, capsys)
    assert f"note: the run in {run} did not end ok (diverged at t = 1.2 s: the total" in err
    assert "measured up to 1.004 s, the last touchdown of main before then" in err
    assert data["status"] == "diverged" and data["ended_at"] == 1.2
    assert data["cause"].startswith("the total energy rose")
    assert data["window"]["to"] == pytest.approx(1.0038)
    assert data["n_strides"] == 3  # not the fourth, 1.0038 to 1.2516 s, through the divergence


def test_an_interrupted_run_is_told_and_measured_to_its_end(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    run = _run(tmp_path / "run", INTERRUPTED)
    data, err = _metrics(run, capsys)
    assert "did not end ok (interrupted at t = 1.2558 s: SIGINT); its metrics are of its" in err
    assert data["status"] == "interrupted" and data["n_strides"] == 4


def test_a_run_that_ended_ok_says_nothing_and_records_ok(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    run = _run(tmp_path / "run", {"status": "ok"})
    data, err = _metrics(run, capsys)
    assert "did not end ok" not in err
    assert data["status"] == "ok" and "ended_at" not in data and data["n_strides"] == 4


def test_a_window_ending_before_the_failing_stride_is_measured_whole(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    run = _run(tmp_path / "run", DIVERGED)
    assert main(["metrics", str(run), "--to", "0.8"]) == 0
    assert "the window ends before the stride it diverged in" in capsys.readouterr().err
    data = json.loads((run / "metrics.json").read_text())
    assert data["window"]["to"] == 0.8 and data["n_strides"] == 2


def test_every_reader_says_a_run_diverged_when_legdsl_run_said_it() -> None:
    ending = run_ending(DIVERGED)
    assert ending is not None and ending.at == 1.2  # not ended_at, 1.2558
    assert ending.text.startswith("diverged at t = 1.2 s")
    assert ending.title(80).startswith("diverged at 1.2 s: the total")


def test_run_metrics_warns_of_a_run_that_fell(tmp_path: Path, generated: Path) -> None:
    import legdsl
    from legdsl.api import LegdslWarning

    hopper = legdsl.load(CREATURES / "hopper.leg", generated=generated)
    where = hopper.run(controller="hop", time=1.5).save(tmp_path / "run")
    info = json.loads((where / "run.json").read_text())
    whole = legdsl.open_run(where).metrics()
    assert whole.status == "ok" and whole.ending_note() == ""
    fell = {"status": "fell", "ended_at": 1.4, "cause": "the root tilted 61 deg"}
    (where / "run.json").write_text(json.dumps(info | fell))
    with pytest.warns(LegdslWarning, match=r"this run did not end ok \(fell at t = 1.4 s: the"):
        metrics = legdsl.open_run(where).metrics()
    assert metrics.status == "fell" and metrics.t_to < 1.4
    assert metrics.n_strides <= whole.n_strides


def test_a_run_that_diverged_before_any_touchdown_measures_an_empty_window(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    run = _run(tmp_path / "run", DIVERGED | {"diverged_at": 0.2})
    data, err = _metrics(run, capsys)
    assert "measured up to 0.000 s, the window's start, as main did not touch down in it" in err
    assert data["window"]["to"] == 0.0 and data["n_strides"] == 0
