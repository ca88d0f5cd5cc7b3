"""The command line: legdsl animate, legdsl export-motion, and their mistakes."""

from __future__ import annotations

from pathlib import Path

import pytest
from anim_runs import creature_run
from standin import ModelKinematics

from legdsl.cli import main


@pytest.fixture
def run_dir(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.setattr(
        "legdsl.runner.load_dynamics",
        lambda model, source, generated, log=None: ModelKinematics(model),
    )
    return creature_run("kangaroo", tmp_path / "run", duration=0.5)


def test_animate_writes_the_player_next_to_the_run(run_dir: Path, capsys) -> None:
    assert main(["animate", str(run_dir)]) == 0
    page = run_dir / "animation.html"
    assert page.is_file() and page.read_text().startswith("<!DOCTYPE html>")
    out = capsys.readouterr().out
    assert str(page) in out and "KiB" in out


def test_animate_to_a_file_with_chosen_overlays(run_dir: Path, tmp_path: Path) -> None:
    page = tmp_path / "out" / "k.html"
    assert (
        main(["animate", str(run_dir), "-o", str(page), "--overlays", "forces,com", "--fps", "30"])
        == 0
    )
    assert '"overlays":["forces","com"]' in page.read_text()


def test_animate_a_video(run_dir: Path, tmp_path: Path, capsys) -> None:
    gif = tmp_path / "k.gif"
    assert (
        main(["animate", str(run_dir), "--video", str(gif), "--fps", "10", "--size", "320x180"])
        == 0
    )
    assert gif.is_file() and gif.read_bytes()[:6] == b"GIF89a"
    assert "6 frames at 10 fps" in capsys.readouterr().out
    assert not (run_dir / "animation.html").exists()  # a video alone unless -o is given


def test_export_motion(run_dir: Path, tmp_path: Path, capsys) -> None:
    assert main(["export-motion", str(run_dir)]) == 0
    assert (run_dir / "motion.glb").read_bytes()[:4] == b"glTF"
    out = tmp_path / "k.gltf"
    assert main(["export-motion", str(run_dir), "--format", "gltf", "-o", str(out)]) == 0
    assert out.read_text().lstrip().startswith("{")
    assert "8 links" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["animate", "{missing}"], "not a run directory"),
        (["animate", "{run}", "--overlays", "force"], "unknown force"),
        (["animate", "{run}", "--video", "x.gif", "--size", "big"], "WIDTHxHEIGHT"),
        (["animate", "{run}", "--video", "x.webm"], ".mp4 or a .gif"),
        (["animate", "{run}", "--fps", "0"], "--fps must be positive"),
        (["export-motion", "{run}", "--fps", "-1"], "--fps must be positive"),
    ],
)
def test_mistakes_are_reported_with_status_2(
    run_dir: Path, tmp_path: Path, capsys, args: list[str], message: str
) -> None:
    argv = [a.format(run=run_dir, missing=tmp_path / "missing") for a in args]
    assert main(argv) == 2
    assert message in capsys.readouterr().err


def test_help_has_examples(capsys) -> None:
    for command in ("animate", "export-motion"):
        with pytest.raises(SystemExit):
            main([command, "--help"])
        assert "Example: legdsl" in capsys.readouterr().out
