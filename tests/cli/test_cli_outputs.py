"""Files named by -o: a name ends in its format's suffix (else refused with the name to
write), and a command writing to standard output says its messages on standard error."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from anim_runs import creature_run, generated_dir
from conftest import CREATURES

from legdsl.cli import main

HOPPER = str(CREATURES / "hopper.leg")


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return creature_run("hopper", tmp_path_factory.mktemp("outputs") / "run", duration=0.3)


def gen() -> list[str]:
    return ["--generated", str(generated_dir())]


@pytest.mark.parametrize(
    ("command", "flag", "name", "wanted"),
    [
        ("plot", "-o", "fig", "fig.png"),
        ("animate", "-o", "player", "player.html"),
        ("animate", "--video", "clip", "clip.mp4"),
        ("export-motion", "-o", "motion", "motion.glb"),
        ("export-motion", "-o", "motion.txt", "motion.glb"),
        ("replay", "-o", "clip", "clip.mp4"),
    ],
)
def test_a_name_without_its_suffix_is_refused_with_the_name_to_write(
    run_dir: Path, tmp_path: Path, capsys, command: str, flag: str, name: str, wanted: str
) -> None:
    argv = [command, str(run_dir), flag, str(tmp_path / name)]
    argv += ["--mujoco"] if command == "replay" else [] if command == "plot" else gen()
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert str(tmp_path / wanted) in err and err.count("\n") == 1, err
    assert list(tmp_path.iterdir()) == []  # nothing written, under either name


def test_export_names_its_format(tmp_path: Path, capsys) -> None:
    assert main(["export", HOPPER, "--format", "urdf", "-o", str(tmp_path / "hop")]) == 2
    assert f"name it {tmp_path / 'hop.urdf'}" in capsys.readouterr().err
    assert main(["export", HOPPER, "--format", "mjcf", "-o", str(tmp_path / "hop.urdf")]) == 2
    assert f"name it {tmp_path / 'hop.xml'}" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []
    assert main(["export", HOPPER, "--format", "mjcf", "-o", str(tmp_path / "hop.mjcf")]) == 0


def test_plot_writes_the_names_it_says(run_dir: Path, tmp_path: Path, capsys) -> None:
    assert main(["plot", str(run_dir), "-o", str(tmp_path / "fig.svg")]) == 0
    said = capsys.readouterr().out
    for name in ("fig.svg", "fig-footfall.svg"):
        assert f"wrote {tmp_path / name}" in said
        assert (tmp_path / name).read_text().lstrip().startswith("<?xml")


def _to_stdout(argv: list[str], tmp_path: Path) -> tuple[bytes, str]:
    """Run ``legdsl argv`` with standard output sent to a file: (the file, stderr)."""
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).parents[2] / "src")}
    with open(tmp_path / "stdout", "wb") as f:
        done = subprocess.run(
            [sys.executable, "-m", "legdsl", *argv], stdout=f, stderr=subprocess.PIPE,
            env=env, text=True, cwd=tmp_path, check=False,
        )  # fmt: skip
    assert done.returncode == 0, done.stderr
    return (tmp_path / "stdout").read_bytes(), done.stderr


def test_export_to_stdout_is_exactly_the_file(tmp_path: Path) -> None:
    from legdsl.check.source import check_model
    from legdsl.export.formats import export_text

    content, err = _to_stdout(["export", HOPPER, "--format", "mjcf", "-o", "/dev/stdout"], tmp_path)
    assert content.decode() == export_text(check_model(HOPPER, None), "mjcf")
    assert "wrote /dev/stdout" in err


def test_a_motion_to_stdout_is_exactly_the_file(run_dir: Path, tmp_path: Path) -> None:
    argv = ["export-motion", str(run_dir), "--format", "bvh", *gen()]
    content, err = _to_stdout([*argv, "-o", "/dev/stdout"], tmp_path)
    assert main([*argv, "-o", str(tmp_path / "m.bvh")]) == 0
    assert content == (tmp_path / "m.bvh").read_bytes()
    assert "wrote /dev/stdout" in err


def test_the_player_to_stdout_says_its_message_on_stderr(run_dir: Path, capsys) -> None:
    assert main(["animate", str(run_dir), "-o", "/dev/stdout", *gen()]) == 0
    said = capsys.readouterr()
    assert "wrote" not in said.out and "wrote /dev/stdout" in said.err


def test_a_dash_names_dev_stdout_where_only_export_reads_it(run_dir: Path, capsys) -> None:
    assert main(["plot", str(run_dir), "-o", "-"]) == 2
    assert "write -o /dev/stdout" in capsys.readouterr().err  # as plot --help spells it


def test_a_urdf_may_be_named_xml(tmp_path: Path, capsys) -> None:
    assert main(["export", HOPPER, "--format", "urdf", "-o", str(tmp_path / "hop.xml")]) == 0
    assert (tmp_path / "hop.xml").read_text().startswith("<robot")
    assert f"wrote {tmp_path / 'hop.xml'}" in capsys.readouterr().out


def test_a_plot_to_stdout_is_exactly_the_picture(run_dir: Path, tmp_path: Path) -> None:
    content, err = _to_stdout(["plot", str(run_dir), "-o", "/dev/stdout"], tmp_path)
    assert content.startswith(b"\x89PNG\r\n") and b"wrote" not in content
    assert "wrote /dev/stdout" in err and f"wrote {run_dir / 'footfall.png'}" in err


def test_run_takes_o_for_its_output_directory(tmp_path: Path) -> None:
    """Every other command writes to -o; `legdsl run F -o DIR` was "unrecognized arguments"."""
    out = tmp_path / "r"
    argv = ["run", HOPPER, "--controller", "hop", "--time", "0.05", "-o", str(out)]
    assert main([*argv, "--generated", str(generated_dir())]) == 0
    assert (out / "run.json").is_file() and (out / "trajectory.npz").is_file()
