"""A scuffed touchdown (a foot touching for a few ms, leaving, then landing) is a stance and,
on the reference, starts a stride, as docs/metrics.md defines them; ``min_stance`` leaves
such contacts out, and without it a note names them and never changes a figure."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from legdsl.analysis.metrics import compute_metrics
from legdsl.analysis.results import MetricsError, Summary
from legdsl.analysis.rows import stat
from legdsl.cli import main
from legdsl.sim.trajectory import Trajectory, empty

DT = 0.001
SCUFF = slice(1300, 1303)  # a 3 ms touch between two landings 500 ms apart


def scuffed_run(n: int = 3001, scuff: bool = True) -> Trajectory:
    """One planar leg landing every 500 ms for 100 ms (touchdowns at 0.1, 0.6, ... 2.6 s),
    with a 3 ms scuff at 1.3 s, moving forward at 1 m/s."""
    tr = empty(
        n, 2, 2, 1, 1, q_names=("x", "z"), v_names=("x", "z"), contact_names=("toe",),
        leg_names=("main",), leg_feet=(0,), total_mass=10.0, gravity=9.81, planar=True,
    )  # fmt: skip
    tr.t[:] = np.arange(n) * DT
    tr.contact[:, 0] = ((np.arange(n) + 400) % 500 < 100).astype(np.int8)
    if scuff:
        tr.contact[SCUFF, 0] = 1
    tr.com[:, 0] = tr.t
    tr.com_vel[:, 0] = 1.0
    return tr


def test_by_default_a_scuff_starts_a_stride_and_a_note_names_it() -> None:
    m = compute_metrics(scuffed_run())
    assert m.per_stride["duration"] == pytest.approx([0.5, 0.5, 0.2, 0.3, 0.5, 0.5])
    assert m.summary("stance_duration").n == 7
    assert m.options["min_stance_s"] is None
    assert m.scuff_note == (
        "1 touchdown(s) look like scuffs, contacts under a third of the feet's median stance "
        "(0.100 s): main at 1.300 s (0.003 s); each counts as a stance and, on the reference, "
        "starts a stride; --min-stance 4ms leaves them out"
    )
    assert m.to_dict()["scuff_note"] == m.scuff_note
    # the note changes no figure: the same run without the scuff measures as before
    assert compute_metrics(scuffed_run(scuff=False)).scuff_note == ""


def test_min_stance_leaves_the_scuff_out_of_strides_stances_and_flights() -> None:
    plain = compute_metrics(scuffed_run(scuff=False))
    m = compute_metrics(scuffed_run(), min_stance=0.02)
    assert m.per_stride["duration"] == pytest.approx([0.5] * 5)
    assert m.table() == plain.table()
    assert [s.t_touchdown for s in m.stances] == [s.t_touchdown for s in plain.stances]
    assert len(m.flights) == len(plain.flights) == 5  # the scuff split one into two
    assert len(compute_metrics(scuffed_run()).flights) == 6
    assert m.scuff_note == "" and m.options["min_stance_s"] == 0.02
    # a contact as long as min_stance is a stance; 1 ms longer than the scuff is enough
    assert compute_metrics(scuffed_run(), min_stance=0.003).summary("stance_duration").n == 7
    assert compute_metrics(scuffed_run(), min_stance=0.004).summary("stance_duration").n == 6


@pytest.mark.parametrize("bad", [0.0, -0.01, math.nan, math.inf])
def test_min_stance_must_be_a_time_more_than_zero(bad: float) -> None:
    with pytest.raises(MetricsError, match="--min-stance"):
        compute_metrics(scuffed_run(), min_stance=bad)


# ---------------------------------------------------------------- legdsl metrics --min-stance


def test_metrics_notes_scuffs_and_min_stance_leaves_them_out(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    scuffed_run().save(tmp_path)
    run = str(tmp_path)
    assert main(["metrics", run, "--json"]) == 0
    captured = capsys.readouterr()
    assert json.loads(captured.out)["n_strides"] == 6
    assert "legdsl: note: 1 touchdown(s) look like scuffs" in captured.err
    assert "main at 1.300 s (0.003 s)" in captured.err and "--min-stance 4ms" in captured.err
    assert main(["metrics", run, "--min-stance", "20ms", "--json"]) == 0
    captured = capsys.readouterr()
    saved = json.loads(captured.out)
    assert saved["n_strides"] == 5 and saved["options"]["min_stance_s"] == pytest.approx(0.02)
    assert "note" not in captured.err
    assert json.loads((tmp_path / "metrics.json").read_text())["n_strides"] == 5


@pytest.mark.parametrize(
    ("value", "said"),
    [
        ("20kg", "--min-stance 20kg: --min-stance is a time (s), but 20kg is a mass (kg)"),
        ("0ms", "--min-stance 0ms: --min-stance must be more than zero"),
    ],
)
def test_a_wrong_min_stance_is_refused_saying_how_to_write_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], value: str, said: str
) -> None:
    scuffed_run().save(tmp_path)
    assert main(["metrics", str(tmp_path), "--min-stance", value]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"legdsl: {said}") and "Traceback" not in err, err
    assert "write e.g. --min-stance" in err or "more than zero" in err
    assert not (tmp_path / "metrics.json").exists()


def test_the_foot_speed_at_touchdown_leaves_the_scuffs_out_too(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """It read the raw contacts, so a scuff's touchdown counted there alone."""
    import legdsl.pipeline.measure as measure

    seen: list[np.ndarray] = []

    def touchdowns(kinematics: object, tr: Trajectory, *rest: object) -> Summary:
        seen.append(tr.contact[SCUFF, 0].copy())
        return stat("touchdown_foot_speed", "foot speed over the ground at touchdown (m/s)", [])

    # a run with its kinematics at hand (none of the other rows' business here)
    monkeypatch.setattr(measure, "kinematics_or_why", lambda *args: object())
    monkeypatch.setattr(measure, "clearance_row", lambda *args: None)
    monkeypatch.setattr(measure, "terrain_rows", lambda *args: [])
    monkeypatch.setattr(measure, "touchdown_speed_row", touchdowns)
    scuffed_run().save(tmp_path)
    assert main(["metrics", str(tmp_path), "--min-stance", "20ms"]) == 0
    assert main(["metrics", str(tmp_path)]) == 0
    assert [s.tolist() for s in seen] == [[0, 0, 0], [1, 1, 1]]


def test_a_min_stance_that_leaves_out_stances_says_so() -> None:
    """A --min-stance longer than the stances (20 given without its unit: 20 s) erased them
    all, and the table blamed the run for touching down too few times."""
    m = compute_metrics(scuffed_run(), min_stance=20.0)
    assert m.n_strides == 0 and m.summary("stance_duration").n == 0
    assert m.note.endswith("(--min-stance 20 s left out 7 more)"), m.note
    said = m.option_notes["--min-stance"]
    assert said.startswith("--min-stance 20 s left out all 6 stances of the feet"), said
    assert "median stance, 0.100 s" in said and "at most --min-stance 33ms" in said
    assert m.to_dict()["option_notes"] == m.option_notes
    uneven = scuffed_run()
    uneven.contact[200:250, 0] = 1  # the first stance lasts 150 ms, the others 100
    partly = compute_metrics(uneven, min_stance=0.12).option_notes["--min-stance"]
    assert partly.startswith("--min-stance 120 ms left out 5 of the 6 stances of the feet"), partly
    # the scuff alone, as min_stance is meant: nothing to say
    assert compute_metrics(scuffed_run(), min_stance=0.033).option_notes == {}


@pytest.mark.parametrize(("value", "bare"), [("20", True), ("20s", False)])
def test_legdsl_metrics_says_a_time_without_its_unit_is_seconds(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], value: str, bare: bool
) -> None:
    scuffed_run().save(tmp_path)
    assert main(["metrics", str(tmp_path), "--min-stance", value]) == 0
    captured = capsys.readouterr()
    assert "legdsl: note: --min-stance 20 s left out all 6 stances of the feet" in captured.err
    assert "(--min-stance 20 s left out 7 more)" in captured.out
    hint = "a time without its unit is seconds: for 20 ms write --min-stance 20ms"
    assert (hint in captured.err) == bare, captured.err
