"""export-motion --fps 0.5 of a 2.995 s run said '2 keyframes over 2.00 s' and nothing of the
last second: the frames, every 1/fps from the start, stop at the last whole one. Where that
leaves out more than 5% of the run it is said, with the --fps that ends at the last sample."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from conftest import CREATURES

from legdsl.cli import main
from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions


@pytest.fixture(scope="module")
def run_dir(generated: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    session = RunSession.from_file(CREATURES / "hopper.leg", generated=generated)
    out = tmp_path_factory.mktemp("runs") / "h"
    session.run("hop", ["speed=1m/s"], options=RunOptions(duration=1.3)).write(out)
    return out


def export(run_dir: Path, generated: Path, out: Path, capsys: pytest.CaptureFixture[str],
           *fps: str) -> str:  # fmt: skip
    argv = ["export-motion", str(run_dir), "--generated", str(generated), "-o", str(out), *fps]
    assert main(argv) == 0
    captured = capsys.readouterr()
    return captured.out + captured.err


def test_the_run_end_a_low_rate_leaves_out_is_said(
    run_dir: Path, generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    said = export(run_dir, generated, tmp_path / "m.glb", capsys, "--fps", "1")
    assert "2 keyframes over 1.00 s" in said
    assert "the run's last 0.30 s (to 1.30 s) falls short of a whole frame and is left out" in said
    rate = re.search(r"--fps (\S+) ends at it", said).group(1)  # type: ignore[union-attr]
    said = export(run_dir, generated, tmp_path / "m.glb", capsys, "--fps", rate)
    assert "keyframes over 1.30 s" in said and "left out" not in said


def test_less_than_a_few_percent_short_is_not_said(
    run_dir: Path, generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    said = export(run_dir, generated, tmp_path / "m.glb", capsys)
    assert "left out" not in said


def test_the_player_and_the_video_say_it_too(
    run_dir: Path, generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """animate silently showed 3.33 s of a 4 s run at --fps 0.3 (0.03 s of a 0.04 s run)."""
    argv = ["animate", str(run_dir), "--generated", str(generated), "-o", str(tmp_path / "a.html")]
    assert main([*argv, "--fps", "1"]) == 0
    said = capsys.readouterr()
    said = said.out + said.err
    assert "2 frames, 1.00 s" in said
    assert "the run's last 0.30 s (to 1.30 s) falls short of a whole frame and is left out" in said
    rate = re.search(r"--fps (\S+) ends at it", said).group(1)  # type: ignore[union-attr]
    assert main([*argv, "--fps", rate]) == 0
    said = capsys.readouterr()
    assert "1.30 s" in said.out + said.err and "left out" not in said.out + said.err


def animate_video(run_dir: Path, generated: Path, out: Path, capsys: pytest.CaptureFixture[str],
                  *options: str) -> str:  # fmt: skip
    argv = ["animate", str(run_dir), "--generated", str(generated), "--video", str(out)]
    assert main([*argv, "--size", "64x64", *options]) == 0
    captured = capsys.readouterr()
    return captured.out + captured.err


def test_a_video_says_what_its_own_frames_leave_out(
    run_dir: Path, generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """animate --video at --fps 1 wrote 2 frames (the last at 1.00 s) of a 1.30 s run with no
    note and '1.30 s of motion': the note was of its keyframes (60 per second), not its frames.
    Its frames, every 1/(fps x slow-motion) of the run, are said, and their span; the --fps
    that ends at the last sample is not named below 60 frames of the run a second (the frames
    are read from keyframes 60 per second, which may end before it)."""
    said = animate_video(run_dir, generated, tmp_path / "v.gif", capsys, "--fps", "1")
    assert "2 frames at 1 fps, 1.00 s of motion)" in said
    assert "the run's last 0.30 s (to 1.30 s) falls short of a whole frame and is left out" in said
    assert "ends at it" not in said
    said = animate_video(
        run_dir, generated, tmp_path / "s.gif", capsys, "--fps", "2", "--slow-motion", "1.5"
    )
    assert "4 frames at 2 fps, 1.00 s of motion, 1.5 times slower)" in said
    assert "the run's last 0.30 s (to 1.30 s) falls short of a whole frame and is left out" in said


def test_a_videos_span_is_its_frames(
    run_dir: Path, generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A 7 fps video of the 1.30 s run: 10 frames, the last at 9/7 = 1.286 s, said as the span
    of motion it shows (its keyframes, 60 a second, end at 1.30 s, which was said), and nothing
    left out where that is less than 5% of the run."""
    said = animate_video(run_dir, generated, tmp_path / "v.gif", capsys, "--fps", "7")
    frames = int(re.search(r"(\d+) frames at 7 fps", said).group(1))  # type: ignore[union-attr]
    assert f"{frames} frames at 7 fps, {(frames - 1) / 7:.2f} s of motion)" in said
    assert "1.29 s of motion" in said and "left out" not in said
