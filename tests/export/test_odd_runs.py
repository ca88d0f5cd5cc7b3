"""Animate, export-motion and replay on odd creatures and odd run directories, as people
outside the team make them: a fixed-base arm, runs of another creature, damaged runs."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from legdsl.cli import main

ARM = """creature arm {
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
  contact tip on b at tip
}
"""


@pytest.fixture(scope="module")
def arm_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A short run of a fixed-base two-link arm (no ground, no legs, no controller)."""
    home = tmp_path_factory.mktemp("arm")
    (home / "arm.leg").write_text(ARM)
    run = home / "run"
    argv = ["run", str(home / "arm.leg"), "--time", "0.2", "--out", str(run)]
    assert main([*argv, "--backend", "python", "--generated", str(home / "generated")]) == 0
    return run


def test_a_run_of_another_creature_with_as_many_coordinates_is_refused(
    arm_run: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # an older run.json has no fingerprint: the same coordinates but another contact set
    # was drawn with the wrong forces, and the video stopped with an internal error
    other = tmp_path / "arm2.leg"
    other.write_text(
        ARM.replace("creature arm", "creature arm2").replace(
            "contact tip on b at tip", "contact tip on b at tip\n  contact elbow on a at tip"
        )
    )
    info = json.loads((arm_run / "run.json").read_text())
    del info["creature_fingerprint"], info["motion_fingerprint"]
    info["source"], info["creature"] = str(other), "arm2"
    run = tmp_path / "run"
    run.mkdir()
    for name in ("trajectory.npz", "trajectory.csv"):
        (run / name).write_bytes((arm_run / name).read_bytes())
    (run / "run.json").write_text(json.dumps(info))
    gen = ["--generated", str(tmp_path / "generated")]
    for argv in (
        ["animate", str(run), "-o", str(tmp_path / "a.html")],
        ["export-motion", str(run), "-o", str(tmp_path / "a.glb")],
    ):
        assert main(argv + gen) == 2
        err = capsys.readouterr().err
        assert "the run's contacts (tip) are not those of" in err
        assert "--source FILE" in err
    assert not (tmp_path / "a.html").exists() and not (tmp_path / "a.glb").exists()


@pytest.fixture(scope="module")
def sparse_run(arm_run: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The arm for 1 s recorded at 10 Hz (11 samples)."""
    home = arm_run.parent
    run = tmp_path_factory.mktemp("sparse") / "run"
    argv = ["run", str(home / "arm.leg"), "--time", "1", "--record-rate", "10", "--out", str(run)]
    assert main([*argv, "--backend", "python", "--generated", str(home / "generated")]) == 0
    return run


def test_replay_frames_of_a_sparse_run_are_one_over_fps_apart(sparse_run: Path) -> None:
    # the frames were never denser than the samples, and the mp4 played them at --fps: a run
    # recorded at 10 Hz played three times too fast at 30 fps
    pytest.importorskip("mujoco")
    from legdsl.export.mjreplay import replay_frames

    _, _, _, times, qpos = replay_frames(sparse_run, fps=30)
    assert len(times) == len(qpos) == 31
    assert np.allclose(np.diff(times), 1 / 30) and times[-1] == pytest.approx(1.0)


def test_a_gif_plays_in_real_time(
    sparse_run: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # GIF delays are whole 10 ms steps: 30 ms each at 30 fps played the run 10% fast
    pytest.importorskip("PIL")
    from PIL import Image

    out = tmp_path / "arm.gif"
    argv = ["animate", str(sparse_run), "--video", str(out), "--fps", "30", "--size", "64x64"]
    assert main([*argv, "--generated", str(sparse_run.parent.parent / "generated")]) == 0
    frames = int(capsys.readouterr().out.split(" frames at ")[0].rsplit(" ", 1)[1])
    with Image.open(out) as gif:
        delays = []
        for frame in range(gif.n_frames):
            gif.seek(frame)
            delays.append(gif.info["duration"])
    # a still frame is merged into the one before it, with both delays
    assert frames >= 30 and sum(delays) == pytest.approx(frames * 1000 / 30, abs=10)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["animate", "{run}", "--fps", "inf"], "--fps must be positive and finite, not inf"),
        (["export-motion", "{run}", "--fps", "nan"], "--fps must be positive and finite"),
        (["animate", "{run}", "--video", "{out}.mp4", "--fps", "1e6"], "1 to 240 frames"),
        (["animate", "{run}", "--video", "{out}.mp4", "--fps", "0.001"], "1 to 240 frames"),
        (["animate", "{run}", "--video", "{out}.gif", "--fps", "60"], "write an .mp4 for more"),
        (["animate", "{run}", "--video", "{out}.gif", "--fps", "1e-3"], "1 to 50 frames"),
        (["replay", "{run}", "--mujoco", "-o", "{out}.mp4", "--fps", "inf"], "and finite"),
        (["replay", "{run}", "--mujoco", "-o", "{out}.mp4", "--fps", "1e9"], "1 to 240 frames"),
        # one keyframe of the whole run, written without a word
        (["export-motion", "{run}", "-o", "{out}.bvh", "--fps", "1"], "gives one frame of this"),
        (
            ["animate", "{run}", "-o", "{out}.html", "--fps", "1e-3"],
            "two frames need --fps 5.07 or more (the default is 60)",
        ),
        # a still picture, each written without a word
        (["animate", "{run}", "--video", "{out}.mp4", "--fps", "1"], "--fps 1 gives one frame"),
        # a video is told the least --slow-motion (a GIF was told an --fps it then refused) and
        # the least rate named is the least, not a whole number above it (6 for 5.07)
        (
            ["animate", "{run}", "--video", "{out}.gif", "--fps", "1"],
            "two frames need --slow-motion 5.07 or more, or --fps 5.07 or more (a video shows",
        ),
        (
            ["animate", "{run}", "--video", "{out}.mp4", "--fps", "4", "--slow-motion", "0.5"],
            "--fps 4 at --slow-motion 0.5 gives one frame",
        ),
        (
            ["replay", "{run}", "--mujoco", "-o", "{out}.mp4", "--fps", "1"],
            "two frames need --fps 5.07 or more (the default is 30)",
        ),
    ],
)
def test_frame_rates_no_video_can_show_are_refused(
    arm_run: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], args: list[str], message: str
) -> None:
    # inf was an internal error (a zero frame step), a million frames a second rendered for
    # hours, a GIF's delay of 1000 s overflowed its 16 bits
    argv = [a.format(run=arm_run, out=tmp_path / "v") for a in args]
    if argv[0] != "replay":
        argv += ["--generated", str(arm_run.parent / "generated")]
    assert main(argv) == 2
    assert message in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_a_video_too_short_for_two_frames_names_its_own_rate(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A GIF of a 5 ms run at its default 30 fps said "--fps 60 gives one frame": the rate its
    frames are read at, not the video's."""
    (tmp_path / "arm.leg").write_text(ARM)
    run, generated = tmp_path / "run", tmp_path / "generated"
    assert main(["run", str(tmp_path / "arm.leg"), "--time", "5ms", "--record-rate", "1000",
                 "--out", str(run), "--generated", str(generated), "--backend", "python"]) == 0  # fmt: skip
    capsys.readouterr()
    gif = tmp_path / "v.gif"
    assert main(["animate", str(run), "--video", str(gif), "--generated", str(generated)]) == 2
    assert "--fps 30 gives one frame of this" in capsys.readouterr().err and not gif.exists()


def test_an_output_that_is_an_input_is_refused(
    arm_run: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # export -o FILE.leg replaced the user's .leg file with MJCF, export-motion -o
    # DIR/trajectory.npz the run's recording with a glb
    leg = tmp_path / "arm.leg"
    leg.write_text(ARM)
    run = tmp_path / "run"
    run.mkdir()
    for name in ("trajectory.npz", "trajectory.csv", "run.json"):
        (run / name).write_bytes((arm_run / name).read_bytes())
    before = {p: p.read_bytes() for p in (leg, *run.iterdir())}
    gen = ["--generated", str(arm_run.parent / "generated")]
    for argv in (
        ["export", str(leg), "--format", "mjcf", "-o", str(leg)],
        ["export-motion", str(run), "-o", str(run / "trajectory.npz"), "--format", "glb", *gen],
        ["animate", str(run), "-o", str(run / "run.json"), *gen],
        ["export-motion", str(run), "--source", str(leg), "-o", str(leg), "--format", "bvh"],
    ):
        assert main(argv) == 2
        assert "this is an input of the command" in capsys.readouterr().err
    # the .leg file run.json names (no --source given) was replaced with glTF, exit 0
    source = Path(json.loads((run / "run.json").read_text())["source"])
    for command in ("export-motion", "animate"):
        assert main([command, str(run), "-o", str(source), *gen]) == 2
        assert "a .leg name is for a creature's source" in capsys.readouterr().err
    assert {p: p.read_bytes() for p in before} == before
