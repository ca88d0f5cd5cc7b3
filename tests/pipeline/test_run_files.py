"""Run files others can read: a compressed npz, a CSV with the state by name, a run.json
that says what the run was made from; the commands that read a run refuse it once its
creature has changed, and a new run into a directory removes what was drawn from the old."""

from __future__ import annotations

import csv
import json
import shutil
import zipfile
from pathlib import Path

import pytest

from legdsl.cli import main
from legdsl.pipeline.session import DERIVED_FILES, RUN_FILES

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture
def hopper(tmp_path: Path, generated: Path) -> tuple[Path, Path]:
    """A copy of the hopper's .leg file (with the standard library it uses) and a 1 s run."""
    leg = tmp_path / "hopper.leg"
    shutil.copy(ROOT / "creatures" / "hopper.leg", leg)
    run = tmp_path / "run"
    argv = ["run", str(leg), "--controller", "hop", "--time", "1s", "--out", str(run),
            "--generated", str(generated)]  # fmt: skip
    assert main(argv) == 0
    return leg, run


def test_the_run_files(hopper: tuple[Path, Path]) -> None:
    leg, run = hopper
    with zipfile.ZipFile(run / "trajectory.npz") as z:
        assert {i.compress_type for i in z.infolist()} == {zipfile.ZIP_DEFLATED}
    rows = list(csv.DictReader((run / "trajectory.csv").open()))
    names = ("FLIGHT", "LOADING", "COMPRESSION", "THRUST", "UNLOADING")
    assert all(r["state_name"] == names[int(r["state"])] for r in rows)
    assert {r["state_name"] for r in rows} >= {"FLIGHT", "COMPRESSION", "THRUST"}
    info = json.loads((run / "run.json").read_text())
    assert len(info["source_sha256"]) == 64 and len(info["creature_fingerprint"]) == 16
    control = (ROOT / "generated" / "hopper" / "control_hop.py").read_text()
    assert f'FINGERPRINT = "{info["controller_fingerprint"]}"' in control


@pytest.mark.parametrize(
    "command",
    [["plot"], ["metrics"], ["animate"], ["export-motion", "--format", "bvh", "-o", "OUT.bvh"]],
)
def test_a_run_of_a_changed_creature_is_refused(
    hopper: tuple[Path, Path], command: list[str], capsys: pytest.CaptureFixture[str],
    generated: Path,
) -> None:  # fmt: skip
    leg, run = hopper
    text = leg.read_text()
    leg.write_text(text.replace("# A planar", "# Only a comment changed: a planar", 1))
    argv = [command[0], str(run), *[str(run.parent / a) if a == "OUT.bvh" else a
                                    for a in command[1:]]]  # fmt: skip
    if command[0] == "metrics":
        argv += ["--generated", str(generated)]
    assert main(argv) == 0, "a comment is not a change of the creature"
    leg.write_text(text.replace("mass 10 kg", "mass 12 kg", 1))
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert f"{leg} has changed since the run in {run} was recorded" in err
    assert (
        f"legdsl run {leg} --controller hop --time 1s --generated {generated} --out {run})" in err
    )


def test_the_rerun_asked_for_a_changed_creature_keeps_the_switches_and_scene(
    hopper: tuple[Path, Path], capsys: pytest.CaptureFixture[str], generated: Path,
    tmp_path: Path,
) -> None:  # fmt: skip
    """The command given to run again a run of a changed creature has its --switch values and
    its --scene (left out, it would record another run); run.json names the scene."""
    leg, run = hopper
    argv = ["run", str(leg), "--controller", "hop", "--switch", "0.5s=hop", "--time", "1s",
            "--out", str(run), "--generated", str(generated)]  # fmt: skip
    assert main(argv) == 0
    leg.write_text(leg.read_text().replace("mass 10 kg", "mass 12 kg", 1))
    assert main(["plot", str(run)]) == 2
    err = capsys.readouterr().err
    assert (
        f"--controller hop --switch 0.5s=hop --time 1s --generated {generated} --out {run})" in err
    )
    biped = tmp_path / "biped.leg"
    shutil.copy(ROOT / "creatures" / "biped.leg", biped)
    scene = tmp_path / "scene"
    argv = ["run", str(biped), "--scene", "run_gallop_run", "--time", "0.2s", "--out",
            str(scene), "--generated", str(generated)]  # fmt: skip
    assert main(argv) == 0
    assert json.loads((scene / "run.json").read_text())["scene"] == "run_gallop_run"
    biped.write_text(biped.read_text().replace("mass 23.1 kg", "mass 24 kg", 1))
    capsys.readouterr()
    assert main(["metrics", str(scene), "--generated", str(generated)]) == 2
    err = capsys.readouterr().err
    assert f"legdsl: {biped} has changed since the run" in err
    assert (
        f"{biped} --scene run_gallop_run --time 0.2s --generated {generated} --out {scene}" in err
    )


def test_a_new_run_removes_what_was_drawn_from_the_old(
    hopper: tuple[Path, Path], generated: Path
) -> None:
    leg, run = hopper
    assert main(["plot", str(run)]) == 0
    assert main(["animate", str(run)]) == 0
    assert main(["metrics", str(run), "--generated", str(generated)]) == 0
    assert main(["export-motion", str(run), "--generated", str(generated)]) == 0  # motion.glb
    drawn = {p.name for p in run.iterdir()} - set(RUN_FILES)
    assert "motion.glb" in drawn  # it was left beside the new run
    assert drawn and drawn <= set(DERIVED_FILES), drawn
    argv = ["run", str(leg), "--time", "0.5s", "--out", str(run), "--generated", str(generated)]
    assert main(argv) == 0
    assert {p.name for p in run.iterdir()} == set(RUN_FILES)


def test_a_run_into_a_folder_of_the_users_own_files_keeps_them(
    hopper: tuple[Path, Path], generated: Path, tmp_path: Path
) -> None:
    """A folder that held no run: its figure6.png, animation.html and metrics.json are the
    user's own, not drawn from a run before (they were removed without a word)."""
    leg, _ = hopper
    project = tmp_path / "project"
    project.mkdir()
    for name in DERIVED_FILES:
        (project / name).write_text(f"the user's {name}")
    argv = ["run", str(leg), "--time", "0.2s", "--out", str(project), "--generated", str(generated)]
    assert main(argv) == 0
    for name in DERIVED_FILES:
        assert (project / name).read_text() == f"the user's {name}"


def test_metrics_of_a_run_in_a_read_only_folder_are_printed(
    hopper: tuple[Path, Path],
    generated: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:
    """A run folder on a read-only disk: the measurement was lost ("cannot write
    metrics.json", nothing printed, exit 2); it is printed, and the file said not written."""
    import errno

    from legdsl.pipeline import measure

    def refused(*_: object) -> None:
        raise OSError(errno.EROFS, "Read-only file system")

    monkeypatch.setattr(measure, "write_json", refused)
    _, run = hopper
    assert main(["metrics", str(run), "--from", "0.1", "--generated", str(generated)]) == 0
    said = capsys.readouterr()
    assert said.out.startswith("gait metrics from 0.100 s")
    assert f"{run / 'metrics.json'} not written (Read-only file system)" in said.err


def test_the_command_to_run_again_keeps_what_the_run_was_given(
    tmp_path: Path, generated: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The command suggested for a run of a changed creature dropped its --time and --set."""
    leg, run = tmp_path / "hopper.leg", tmp_path / "run"
    shutil.copy(ROOT / "creatures" / "hopper.leg", leg)
    argv = ["run", str(leg), "--controller", "hop", "--time", "0.3s", "--set", "speed=1.5m/s",
            "--out", str(run), "--generated", str(generated)]  # fmt: skip
    assert main(argv) == 0
    leg.write_text(leg.read_text().replace("mass 10 kg", "mass 12 kg", 1))
    capsys.readouterr()
    assert main(["plot", str(run)]) == 2
    err = capsys.readouterr().err
    said = f"(legdsl run {leg} --controller hop --time 0.3s --set speed=1.5m/s --generated {generated} --out {run})"  # fmt: skip
    assert said in err


def test_a_run_is_held_while_a_command_draws_from_it(
    hopper: tuple[Path, Path], monkeypatch: pytest.MonkeyPatch
) -> None:
    """``plot`` read run A, a new run B replaced it meanwhile, and A's figure6.png was written
    beside B's trajectory. A command drawing from a run holds the run directory's lock, which a
    new run's write takes too: B waits until the picture is whole (and then removes it)."""
    import fcntl
    import os

    from legdsl.analysis import plot

    _, run = hopper
    drawing = plot.plot_run
    tried: list[bool] = []

    def while_drawing(*args: object, **kwargs: object) -> object:
        fd = os.open(run, os.O_RDONLY | os.O_DIRECTORY)  # as a new run's write takes it
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            tried.append(True)
        except BlockingIOError:
            tried.append(False)
        finally:
            os.close(fd)
        return drawing(*args, **kwargs)

    monkeypatch.setattr(plot, "plot_run", while_drawing)
    assert main(["plot", str(run)]) == 0
    assert tried == [False]  # held


def test_a_long_write_is_told_before_it_starts(
    tmp_path: Path, generated: Path, capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
) -> None:  # fmt: skip
    """The bar said "done", then a 30 min run's files took a silent minute to write: a write
    of ``SAY_WRITING`` seconds or more is told first, with its size and time."""
    from legdsl.cli import run as run_command

    argv = ["run", str(ROOT / "creatures" / "hopper.leg"), "--time", "0.5s", "--out",
            str(tmp_path / "run"), "--generated", str(generated)]  # fmt: skip
    assert main(argv) == 0
    assert "legdsl: writing" not in capsys.readouterr().err  # a moment's: nothing to say
    monkeypatch.setattr(run_command, "SAY_WRITING", 0.0)
    assert main(argv) == 0
    err = capsys.readouterr().err
    assert f"legdsl: writing {tmp_path / 'run'}/ (about " in err and " MB, about " in err
