"""A run with ``record_rate 0 Hz`` records every step; exported with too few samples for its
stances, the note told it to 'record it faster for more (legdsl run --record-rate)', which it
cannot: only a smaller step (--dt) records more. The note says so where the run recorded every
step (run.json's steps and samples; legdsl run --animate's own result), and still names
--record-rate where it did not.

The hopper's stances are long (about 0.2 s); the median stance is taken to be one step long
here, as a creature that brushes the ground has it (an outside user's: 0.4 ms at 0.4 ms)."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import CREATURES

import legdsl.export.stances as stances
from legdsl.cli import main
from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions

STEP = 0.0004  # s: the hopper's
EVERY_STEP = "they are every step it took, so only a smaller step gives more (legdsl run --dt)"
FASTER = "record it faster for more (legdsl run --record-rate)"


@pytest.fixture(scope="module")
def runs(generated: Path, tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    session = RunSession.from_file(CREATURES / "hopper.leg", generated=generated)
    out = tmp_path_factory.mktemp("runs")
    made = {}
    for name, rate in (("every", 0.0), ("sampled", 200.0)):
        options = RunOptions(duration=0.3, dt=STEP, record_rate=rate)
        session.run("hop", ["speed=1m/s"], options=options).write(out / name)
        made[name] = out / name
    return made


@pytest.fixture(autouse=True)
def one_step_stances(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(stances, "typical_stance", lambda model, tr: ("leg main", STEP))


def said(capsys: pytest.CaptureFixture[str], *argv: str) -> str:
    assert main(list(argv)) == 0
    captured = capsys.readouterr()
    return captured.out + captured.err


def test_a_run_recorded_every_step_is_told_a_smaller_step(
    runs: dict[str, Path], generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    common = ["--generated", str(generated), "--fps", "2500"]
    text = said(capsys, "export-motion", str(runs["every"]), "-o", str(tmp_path / "m.glb"), *common)
    assert "the run's 2500 samples per second give it the most (--fps 2500)" in text
    assert EVERY_STEP in text and "--record-rate" not in text
    text = said(capsys, "animate", str(runs["every"]), "-o", str(tmp_path / "a.html"), *common)
    assert EVERY_STEP in text and "--record-rate" not in text


def test_a_run_recorded_less_often_is_still_told_to_record_faster(
    runs: dict[str, Path], generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    common = ["--generated", str(generated), "--fps", "2500"]
    text = said(
        capsys, "export-motion", str(runs["sampled"]), "-o", str(tmp_path / "m.glb"), *common
    )
    assert FASTER in text and "--dt" not in text


def test_run_animate_of_a_run_recorded_every_step(
    generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """legdsl run --animate's player (60 frames a second) of a run at --record-rate 0: a
    one-step stance would need 10000 a second, above the 2500 samples, so the note says the
    samples give the most, and that only a smaller step gives more."""
    from legdsl.export.stances import recorded_every_step

    assert recorded_every_step(1500, 1501) and not recorded_every_step(1500, 116)
    assert not recorded_every_step(None, 1501) and not recorded_every_step(0, 1)
    argv = ["run", str(CREATURES / "hopper.leg"), "--controller", "hop", "--time", "0.3",
            "--record-rate", "0", "--generated", str(generated), "--out", str(tmp_path / "r"),
            "--animate"]  # fmt: skip
    assert main(argv) == 0
    text = capsys.readouterr()
    text = text.out + text.err
    assert "the run's 2500 samples per second give it the most (--fps 2500)" in text
    assert EVERY_STEP in text and "--record-rate" not in text


def test_the_apis_animate_of_a_run_recorded_every_step(
    runs: dict[str, Path], tmp_path: Path, generated: Path
) -> None:
    """Run.animate() gave the old advice (--record-rate) where the command said --dt."""
    import legdsl
    from legdsl.api import LegdslWarning

    with pytest.warns(LegdslWarning) as told:
        legdsl.open_run(runs["every"], generated=generated).animate(tmp_path / "a.html", fps=2500)
    text = " ".join(str(w.message) for w in told)
    assert EVERY_STEP in text and "--record-rate" not in text


def test_the_apis_frame_rate_takes_a_whole_number(runs: dict[str, Path], generated: Path) -> None:
    """Run.animate(fps=30) died of AttributeError ('int' object has no attribute 'isascii')."""
    import legdsl
    from legdsl.api import LegdslWarning
    from legdsl.lang.errors import UsageError

    run = legdsl.open_run(runs["sampled"], generated=generated)
    with pytest.warns(LegdslWarning, match="record it faster"):  # the one-step stances
        assert run.animate(fps=30).name == "animation.html"
    with pytest.raises(UsageError, match=r"fps=True: give the frames per second as a number"):
        run.animate(fps=True)


def test_a_frame_rate_of_numpys_numbers() -> None:
    """fps=np.int64(30), np.float32(30), np.array(30) were told 'give the frames per second as
    a number' (as run()'s time= takes them), and fps=10**400 raised OverflowError."""
    import numpy as np

    from legdsl.export.animate import frame_rate
    from legdsl.lang.errors import UsageError

    for fps in (np.int64(30), np.float32(30), np.int32(30), np.array(30), np.array(30.0)):
        assert frame_rate(fps, "animate(): fps=") == 30.0
    for refused in (np.True_, np.array([30]), 10**400):
        with pytest.raises(UsageError, match=r"^animate\(\): fps="):
            frame_rate(refused, "animate(): fps=")
