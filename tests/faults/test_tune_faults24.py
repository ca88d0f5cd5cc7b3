"""Faults of the fault hunt of the newest features (faults24): `legdsl tune` stopped by a
signal as it writes its results."""

from __future__ import annotations

import json
import os
import signal
from pathlib import Path
from typing import Any

import pytest

import legdsl.api.tune_cli as tune_cli
from legdsl.cli import main

HOPPER = Path(__file__).resolve().parents[2] / "creatures" / "hopper.leg"

pytestmark = pytest.mark.usefixtures("hopper_modules")


def _tune(out: Path, generated: Path) -> int:
    return main([
        "tune", str(HOPPER), "--controller", "hop", "--param", "kp=50:300",
        "--speeds", "1,1.5", "--time", "2", "--from", "1", "--generations", "1",
        "--popsize", "4", "--jobs", "2", "--out", str(out), "--generated", str(generated),
    ])  # fmt: skip


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT])
def test_a_signal_as_the_tune_writes_its_files_waits_for_them(
    sig: int, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """A SIGTERM (or Ctrl-C) that came once the tune had finished, as it wrote its files,
    ended the command between them: tune.json there, saying "finished", and no tune.png, the
    journal left behind. Now it is noted, the three files are written, then it is obeyed."""
    drawn = tune_cli.plot_history

    def signalled_while_drawing(*args: Any, **kwargs: Any) -> Path:
        os.kill(os.getpid(), sig)  # delivered here, in the middle of the writing
        return drawn(*args, **kwargs)

    monkeypatch.setattr(tune_cli, "plot_history", signalled_while_drawing)
    out = tmp_path / "t"
    code = _tune(out, tmp_path / "generated")
    assert code == 128 + sig
    assert {p.name for p in out.iterdir()} >= {"hopper.leg", "tune.json", "tune.png"}
    assert json.loads((out / "tune.json").read_text())["ended"] == "finished"
    journal = json.loads((out / ".tune-journal.json").read_text())  # kept, to go further from
    assert len(journal["generations"]) == len(
        json.loads((out / "tune.json").read_text())["history"]
    )
    assert "its files are whole" in capsys.readouterr().err


@pytest.mark.parametrize("flag", ["--pitch-weight", "--spread-weight", "--energy-weight"])
def test_a_weight_with_a_unit_is_told_what_a_weight_is(
    flag: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """'--pitch-weight 0.5deg' was argparse's "invalid float value: '0.5deg'"."""
    with pytest.raises(SystemExit) as stop:
        main([
            "tune", str(HOPPER), "--controller", "hop", "--param", "kp=50:300", "--speeds",
            "1", "--out", str(tmp_path / "t"), flag, "0.5deg",
        ])  # fmt: skip
    assert stop.value.code == 2
    err = capsys.readouterr().err
    assert "a weight is a plain number" in err and "write 0.5" in err
    assert not (tmp_path / "t").exists()


def test_tune_json_is_strict_json(tmp_path: Path) -> None:
    """A run that fell has no metrics: tune.json held Python's NaN for them, which jq and
    JavaScript refuse; it is null now, as in run.json."""
    out = tmp_path / "t"
    assert _tune(out, tmp_path / "generated") == 0  # 2 s runs from 1 s: too few strides
    text = (out / "tune.json").read_text()
    assert "NaN" not in text and "Infinity" not in text
    json.loads(text, parse_constant=lambda c: pytest.fail(f"{c} in tune.json"))
