"""The command line: legdsl animate, legdsl export-motion, and their mistakes."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from anim_runs import creature_run, generated_dir
from conftest import CREATURES

from legdsl.cli import main
from legdsl.export.animate import parse_size, seconds_text
from legdsl.lang.errors import UsageError


@pytest.fixture
def run_dir(tmp_path: Path) -> Path:
    return creature_run("kangaroo", tmp_path / "run")


def gen() -> list[str]:
    return ["--generated", str(generated_dir())]


def test_run_with_animate_writes_the_player(tmp_path: Path, capsys) -> None:
    out = tmp_path / "run"
    argv = ["run", str(CREATURES / "biped.leg"), "--time", "0.2", "--out", str(out), "--animate"]
    assert main(argv + gen()) == 0
    page = out / "animation.html"
    assert page.is_file() and '"creature":"biped"' in page.read_text()
    assert f"animation: {page}" in capsys.readouterr().out


def test_animate_writes_the_player_next_to_the_run(run_dir: Path, capsys) -> None:
    assert main(["animate", str(run_dir), *gen()]) == 0
    page = run_dir / "animation.html"
    assert page.is_file() and page.read_text().startswith("<!DOCTYPE html>")
    out = capsys.readouterr().out
    assert str(page) in out and "KiB" in out


def test_animate_to_a_file_with_chosen_overlays(run_dir: Path, tmp_path: Path) -> None:
    page = tmp_path / "out" / "k.html"
    assert (
        main(
            [
                "animate",
                str(run_dir),
                "-o",
                str(page),
                "--overlays",
                "forces,com",
                "--fps",
                "30",
                *gen(),
            ]
        )
        == 0
    )
    assert '"overlays":["forces","com"]' in page.read_text()


def test_animate_a_video(run_dir: Path, tmp_path: Path, capsys) -> None:
    gif = tmp_path / "k.gif"
    assert (
        main(
            [
                "animate",
                str(run_dir),
                "--video",
                str(gif),
                "--fps",
                "10",
                "--size",
                "320x180",
                *gen(),
            ]
        )
        == 0
    )
    assert gif.is_file() and gif.read_bytes()[:6] == b"GIF89a"
    assert "frames at 10 fps" in capsys.readouterr().out
    assert main(["animate", str(run_dir), "--video", str(gif), "--fps", "12Hz", *gen()]) == 0
    assert "frames at 12 fps" in capsys.readouterr().out  # a rate with its unit
    assert not (run_dir / "animation.html").exists()  # a video alone unless -o is given


def test_export_motion(run_dir: Path, tmp_path: Path, capsys) -> None:
    assert main(["export-motion", str(run_dir), *gen()]) == 0
    assert (run_dir / "motion.glb").read_bytes()[:4] == b"glTF"
    out = tmp_path / "k.gltf"
    assert main(["export-motion", str(run_dir), "--format", "gltf", "-o", str(out), *gen()]) == 0
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
        (["animate", "{run}", "--video", "x.gif", "--slow-motion", "-2"], "--slow-motion must be"),
        (["animate", "{run}", "--fps", "30kg"], "--fps is a frequency"),
        (["export-motion", "{run}", "--fps", "2m"], "--fps is a frequency"),
        (["animate", "{run}", "-o", "{tmp}/x.gif"], "HTML player; render a video with --video"),
        (["animate", "{run}", "-o", "{tmp}/x.png"], "writes the HTML player; name it"),
        (["export-motion", "{run}", "--fps", "-1"], "--fps must be positive"),
        # the word 'none' among overlays was told "unknown none; choose from ... or none"
        (["animate", "{run}", "--overlays", "none,state"], "'none' stands alone"),
        # an odd size was drawn one pixel smaller without a word
        (["animate", "{run}", "--video", "x.mp4", "--size", "961x541"], "write --size 962x542"),
        # options of a video alone were passed over
        (["animate", "{run}", "--slow-motion", "3"], "--slow-motion is for a video: add --video"),
        (["animate", "{run}", "--size", "640x360"], "--size is for a video: add --video"),
        # a stream has no name to take the format from: it was told to write /dev/stdout.mp4
        (["animate", "{run}", "--video", "/dev/stdout"], "a video is written to a file named"),
        # a word meant as a unit, apart from its number, was argparse's "unrecognized arguments"
        (["export-motion", "{run}", "--fps", "30", "fps"], "did you mean 'Hz'?"),
    ],
)
def test_mistakes_are_reported_with_status_2(
    run_dir: Path, tmp_path: Path, capsys, args: list[str], message: str
) -> None:
    argv = [a.format(run=run_dir, missing=tmp_path / "missing", tmp=tmp_path) for a in args]
    assert main(argv + gen()) == 2
    assert message in capsys.readouterr().err


def test_help_has_examples(capsys) -> None:
    for command in ("animate", "export-motion"):
        with pytest.raises(SystemExit):
            main([command, "--help"])
        assert "Example: legdsl" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("given", "output", "expected"),
    [(None, None, "glb"), (None, "m.bvh", "bvh"), (None, "m.USDA", "usda"), ("bvh", "m.txt", "bvh"),
     ("usda", "m.usd", "usda"), ("gltf", None, "gltf"), ("usd", "m.glb", None),
     ("usd", "m.usda", None), ("glb", "m.bvh", None)],
)  # fmt: skip
def test_the_motion_format_follows_the_name_or_is_refused(
    given: str | None, output: str | None, expected: str | None
) -> None:
    from legdsl.export.animate import motion_format
    from legdsl.lang.errors import UsageError

    if expected is None:
        with pytest.raises(UsageError, match="leave out --format"):
            motion_format(given, output)
    else:
        assert motion_format(given, output) == expected


def test_an_export_at_the_recorded_rate_says_so(
    run_dir: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--fps above the recorded rate keeps the recorded one (not a whole number: samples are
    on whole steps); the file's rate was that, and nothing said it was not --fps."""
    out = tmp_path / "k.bvh"
    assert main(["export-motion", str(run_dir), "--fps", "1000", "-o", str(out), *gen()]) == 0
    said = capsys.readouterr().out
    told = re.search(r", ([\d.]+) per second: the rate it was recorded at, below --fps 1000", said)
    assert told is not None, said
    frame_time = float(out.read_text().split("Frame Time:")[1].split()[0])
    assert float(told.group(1)) == pytest.approx(1.0 / frame_time, rel=1e-8)
    assert main(["export-motion", str(run_dir), "--fps", "30", "-o", str(out), *gen()]) == 0
    assert "per second" not in capsys.readouterr().out


@pytest.mark.parametrize(
    ("size", "said"),
    [
        ("8192x4320", "too large; a video is at most 7680 pixels wide and 4320 high"),
        ("7682x100", "too large; a video is at most 7680 pixels wide"),
        ("640x5000", "too large; a video is at most 7680 pixels wide and 4320 high"),
        ("32x32", "too small; a video is at least 64x64 pixels"),
    ],
)
def test_a_size_out_of_range_is_said_to_be_too_large_or_small(size: str, said: str) -> None:
    """A well-written size out of range was told to 'write WIDTHxHEIGHT', as if mistyped."""
    with pytest.raises(UsageError) as caught:
        parse_size(size)
    assert said in str(caught.value) and "WIDTHxHEIGHT" not in str(caught.value)
    assert parse_size("7680x4320") == (7680, 4320)


def test_a_summary_gives_a_short_runs_length_in_three_digits() -> None:
    """A 4.5 ms clip was "0.00 s of motion"."""
    assert seconds_text(0.0045) == "0.0045 s" and seconds_text(0.00417) == "0.00417 s"
    assert seconds_text(2.5) == "2.50 s" and seconds_text(0.0) == "0.00 s"


@pytest.mark.parametrize("slow", ["1e300", "1e20", "1e12", "1e6", "1001"])
def test_a_video_too_slow_is_refused_naming_the_slowest_and_its_frames(
    run_dir: Path, tmp_path: Path, capsys, monkeypatch: pytest.MonkeyPatch, slow: str
) -> None:
    """--slow-motion 1e20 was an internal error (numpy's array too large, exit 70), 1e12 was
    told to lower --fps, and 1e6 began a render of 90 million frames without a word."""
    from legdsl.export import video
    from legdsl.export.frames import enough_frames, every_frame

    def drawn(*_: object) -> None:
        raise AssertionError("a frame was drawn")

    monkeypatch.setattr(video, "_frame", drawn)

    out = tmp_path / "v.mp4"
    assert main(["animate", str(run_dir), "--video", str(out), "--slow-motion", slow] + gen()) == 2
    err = capsys.readouterr().err
    frames = re.search(r"would be (\S+) frames, about \S+ (years )?of video at --fps 30;", err)
    assert frames and "at most 1000 times slower than real time (--slow-motion 1000 or less)" in err
    if slow == "1001":  # the frames it names are those it would have drawn
        t = np.load(run_dir / "trajectory.npz")["t"]
        drawn = every_frame(float(t[-1] - t[0]), 30.0 * 1001)
        assert int(frames.group(1).replace(",", "")) == len(drawn)
    assert not out.exists()
    enough_frames(1.0, 240.0, slow=1000.0, top=240.0)  # the slowest is allowed
