"""A run directory whose trajectory.npz is another run's (run.json of a biped, trajectory.npz
of a hopper): ``plot`` drew it and exited 0, ``metrics`` measured it with a note, where
animate, export-motion and replay refused it. One check (``analysis.recorded.same_run``) now
refuses it in all of them: against the creature where its .leg file is at hand, else
against the samples run.json counts."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from legdsl.cli import main

ARM = """creature NAME {
  planar
  body base fixed at (0 m, 1 m) {
    mass 1 kg  inertia 0.1 kg*m^2
  }
  body a on base via revolute j1 {
    length 0.3 m  com 0.15 m  mass 0.5 kg  inertia 0.01 kg*m^2  initial 30 deg
  }
  body b on a via revolute j2 at tip {
    length 0.3 m  com 0.15 m  mass 0.5 kg  inertia 0.01 kg*m^2
  }
  MORE
  contact tip on b at tip
}
"""
THIRD = """body c on b via revolute j3 at tip {
    length 0.3 m  com 0.15 m  mass 0.5 kg  inertia 0.01 kg*m^2
  }"""


def _run(home: Path, name: str, more: str, time: str) -> Path:
    leg = home / f"{name}.leg"
    leg.write_text(ARM.replace("NAME", name).replace("MORE", more))
    out = home / f"{name}-{time}"
    argv = ["run", str(leg), "--time", time, "--out", str(out), "--backend", "python"]
    assert main([*argv, "--generated", str(home / "generated")]) == 0
    return out


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    home = tmp_path_factory.mktemp("mixed")
    return {
        "two": _run(home, "two", "", "0.2"),
        "two_longer": _run(home, "two", "", "0.3"),
        "three": _run(home, "three", THIRD, "0.2"),
    }


def _mixed(tmp_path: Path, info_of: Path, trajectory_of: Path) -> Path:
    run = tmp_path / "mix"
    run.mkdir()
    shutil.copy(info_of / "run.json", run / "run.json")
    for name in ("trajectory.npz", "trajectory.csv"):
        shutil.copy(trajectory_of / name, run / name)
    return run


@pytest.mark.parametrize("command", ["plot", "metrics"])
def test_another_creatures_trajectory_is_refused(
    runs: dict[str, Path], tmp_path: Path, command: str, capsys: pytest.CaptureFixture[str]
) -> None:
    run = _mixed(tmp_path, runs["three"], runs["two"])
    argv = [command, str(run)] + (["-o", str(tmp_path / "f.png")] if command == "plot" else [])
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert f"legdsl: {run}: the run has 2 coordinates but " in err
    assert "three.leg describes 3" in err
    assert not (tmp_path / "f.png").exists() and not (run / "metrics.json").exists()


@pytest.mark.parametrize("command", ["plot", "metrics", "animate"])
def test_another_runs_trajectory_of_the_same_creature_is_refused(
    runs: dict[str, Path], tmp_path: Path, command: str, capsys: pytest.CaptureFixture[str]
) -> None:
    run = _mixed(tmp_path, runs["two"], runs["two_longer"])
    out = {"plot": ["-o", str(tmp_path / "f.png")], "animate": ["-o", str(tmp_path / "a.html")]}
    assert main([command, str(run), *out.get(command, [])]) == 2
    err = capsys.readouterr().err
    assert "samples and its run.json says the run recorded" in err
    assert "they are not of one run" in err


def test_a_runs_own_files_are_read(runs: dict[str, Path], tmp_path: Path) -> None:
    assert main(["plot", str(runs["two"]), "-o", str(tmp_path / "f.png")]) == 0
