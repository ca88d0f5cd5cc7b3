"""The trunk's stride pitch magnitude: seen by the tune's report and, with --pitch-weight, by its
objective. The fast knee biped, tuned for speed alone (tests/good/outside/knee_biped_fast.leg
before its second tune), held 1 to 2.4 m/s within 2% while its trunk pitched 12 to 14.6 degrees
each stride: the objective had no term for it, and drove the idle leg's `balance` to 0."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from legdsl.api.tune import Objective, report, score, tune_pitch
from legdsl.cli import main

ROOT = Path(__file__).resolve().parents[2]
HOPPER = ROOT / "creatures" / "hopper.leg"

# two candidates at 2 m/s: one on the command with the trunk rocking 13.5 degrees a stride
# (the fast knee biped's), one 1% slow with 1.6 degrees
ROCKING = {"outcome": "ok", "running_speed": 2.0, "running_speed_std": 0.02,
           "pitch_magnitude": 13.5, "simulated": 10.0, "by_label": {}}  # fmt: skip
LEVEL = {**ROCKING, "running_speed": 1.98, "pitch_magnitude": 1.6}

pytestmark = pytest.mark.usefixtures("hopper_modules")


def test_the_pitch_weight_adds_the_pitch_magnitude_in_radians() -> None:
    plain = Objective(speeds=(2.0,), duration=10.0, start=3.0)
    pitched = Objective(speeds=(2.0,), duration=10.0, start=3.0, pitch_weight=0.5)
    assert score([ROCKING], plain) == 0.0
    assert score([ROCKING], pitched) == pytest.approx(0.5 * math.radians(13.5))
    assert score([LEVEL], pitched) == pytest.approx(0.01 + 0.5 * math.radians(1.6))
    # the weight changes which candidate wins
    assert score([ROCKING], plain) < score([LEVEL], plain)
    assert score([LEVEL], pitched) < score([ROCKING], pitched)
    # no strides measured, no pitch: the speed term says
    unmeasured = {**LEVEL, "pitch_magnitude": math.nan}
    assert score([unmeasured], pitched) == pytest.approx(0.01)


def test_the_report_shows_each_speeds_pitch_magnitude() -> None:
    result = {
        "start": {"values": {"balance": 0.02}, "objective": 0.2, "runs": [{**ROCKING, "speed": 2}]},
        "best": {"values": {"balance": 8.0}, "objective": 0.04, "runs": [{**LEVEL, "speed": 2}]},
    }
    text = report(result, {"balance": ""})
    assert "pitch magnitude (deg)" in text
    assert any(line.split() == ["at", "2", "13.5", "1.6"] for line in text.splitlines()), text
    assert tune_pitch({"pitch_magnitude": math.nan}) == "n/a"


def run_tune(out: Path, generated: Path, weight: str) -> dict:  # type: ignore[type-arg]
    code = main([
        "tune", str(HOPPER), "--controller", "hop", "--param", "k_speed=0.02:0.2",
        "--speeds", "1", "--time", "3", "--from", "1", "--generations", "1", "--popsize", "2",
        "--seed", "1", "--jobs", "1", "--pitch-weight", weight, "--out", str(out),
        "--generated", str(generated),
    ])  # fmt: skip
    assert code == 0
    return json.loads((out / "tune.json").read_text())  # type: ignore[no-any-return]


def test_a_tune_adds_the_weighted_pitch_of_each_run_and_keeps_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    plain = run_tune(tmp_path / "plain", tmp_path / "generated", "0")
    weighted = run_tune(tmp_path / "weighted", tmp_path / "generated", "3")
    (row,) = weighted["start"]["runs"]  # tune.json keeps each run's pitch magnitude (deg)
    assert 0 < row["pitch_magnitude"] < 90
    assert weighted["start"]["runs"] == plain["start"]["runs"]
    error = abs(row["running_speed"] - 1.0)
    assert plain["start"]["objective"] == pytest.approx(error)
    assert weighted["start"]["objective"] == pytest.approx(
        error + 3 * math.radians(row["pitch_magnitude"])
    )
    assert f"at 1         {row['pitch_magnitude']:.3g}" in capsys.readouterr().out


def test_a_negative_pitch_weight_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code = main(["tune", str(HOPPER), "--controller", "hop", "--param", "k_speed=0.02:0.2",
                 "--speeds", "1", "--pitch-weight", "-1", "--out", str(tmp_path / "t")])  # fmt: skip
    assert code == 2
    assert "--pitch-weight -1: give a weight of 0 or more" in capsys.readouterr().err
