"""``legdsl replay DIR --mujoco``: the run on MuJoCo's model, drawn by MuJoCo's renderer."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from anim_runs import creature_motion, creature_run
from external_tools import ffmpeg, ffprobe_frames, loud_skip
from pixels import hue_mask

from legdsl.export.mjreplay import replay_frames
from legdsl.export.motion import quaternion_to_matrix

mujoco = pytest.importorskip("mujoco")


def test_mujoco_poses_are_the_runs(tmp_path: Path) -> None:
    """Setting MuJoCo's qpos from the run puts every body where legdsl's kinematics has it."""
    motion = creature_motion("quadruped", tmp_path / "run")
    mj, data, model, times, qpos = replay_frames(tmp_path / "run", fps=60)
    assert len(times) == motion.frames
    for f in range(0, motion.frames, 7):
        data.qpos[:] = qpos[f]
        mujoco.mj_kinematics(mj, data)
        for b, body in enumerate(model.bodies):
            assert np.allclose(data.body(body.name).xpos, motion.positions[f, b], atol=1e-6)
            rot = quaternion_to_matrix(motion.quaternions[f, b])
            assert np.allclose(data.body(body.name).xmat.reshape(3, 3), rot, atol=1e-6)


def test_replay_renders_an_mp4(tmp_path: Path) -> None:
    ffmpeg()
    run = creature_run("biped", tmp_path / "run")
    out = tmp_path / "biped-mujoco.mp4"
    args = ["replay", str(run), "--mujoco", "-o", str(out), "--fps", "10", "--size", "160x96"]
    # A process of its own, as from the shell: MuJoCo picks its OpenGL backend when it is first
    # imported, and this test session imported it already (with no MUJOCO_GL, that is GLFW).
    env = {k: v for k, v in os.environ.items() if k not in ("MUJOCO_GL", "DISPLAY")}
    env["PYTHONPATH"] = os.pathsep.join(sys.path)
    done = subprocess.run(
        [sys.executable, "-m", "legdsl", *args], capture_output=True, text=True, env=env
    )
    if done.returncode == 2 and "offscreen renderer could not start" in done.stderr:
        loud_skip(done.stderr.strip())  # only where no OpenGL context can be had
    assert done.returncode == 0, done.stderr
    assert "wrote" in done.stdout
    width, height, frames = ffprobe_frames(out)
    # 1 s recorded every 5.2 ms: samples to 0.9984 s, so frames at 0, 0.1, ..., 0.9 s
    assert (width, height) == (160, 96) and frames == 10
    raw = subprocess.run(
        ["ffmpeg", "-v", "error", "-i", str(out), "-frames:v", "1", "-f", "rawvideo",
         "-pix_fmt", "rgb24", "-"],
        capture_output=True, check=True,
    ).stdout  # fmt: skip
    image = np.frombuffer(raw, np.uint8).reshape(96, 160, 3).astype(float) / 255
    from conftest import CREATURES

    from legdsl.check.source import check_model

    trunk = check_model(CREATURES / "biped.leg").bodies[0].color or ""
    assert hue_mask(image, trunk).sum() > 20  # the trunk is in the picture


def test_a_replay_into_a_stream_is_refused(tmp_path: Path, capsys) -> None:
    """ffmpeg takes the format from the name: -o /dev/stdout was told to be named
    /dev/stdout.mp4."""
    from legdsl.cli import main

    run = creature_run("kangaroo", tmp_path / "run")
    assert main(["replay", str(run), "--mujoco", "-o", "/dev/stdout"]) == 2
    assert "a video is written to a file named .mp4 or .gif" in capsys.readouterr().err


def test_a_misspelt_mujoco_gl_is_a_usage_error(tmp_path: Path) -> None:
    """MuJoCo's import refuses an unknown MUJOCO_GL ('egI' for egl): that was an internal
    error (exit 70); it is the user's to fix, told which values MuJoCo takes."""
    run = creature_run("hopper", tmp_path / "run")
    env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    env.update(MUJOCO_GL="egI", PYTHONPATH=os.pathsep.join(sys.path))
    args = ["replay", str(run), "--mujoco", "-o", str(tmp_path / "x.mp4"), "--size", "64x64"]
    done = subprocess.run(
        [sys.executable, "-m", "legdsl", *args], capture_output=True, text=True, env=env
    )
    assert done.returncode == 2, done.stderr
    assert "MUJOCO_GL=egI is not a value MuJoCo takes" in done.stderr
    assert "glfw (with a display)" in done.stderr


def test_an_opengl_backend_that_will_not_load_is_a_usage_error(monkeypatch) -> None:
    """MUJOCO_GL=osmesa without libOSMesa fails inside PyOpenGL's import, as mujoco is
    imported ("'NoneType' object has no attribute 'glGetError'"): exit 2 with what to install."""
    from legdsl.export import mjreplay
    from legdsl.lang.errors import UsageError

    def no_osmesa(name: str) -> None:
        raise AttributeError("'NoneType' object has no attribute 'glGetError'")

    monkeypatch.setenv("MUJOCO_GL", "osmesa")
    monkeypatch.setattr(mjreplay, "import_held", no_osmesa)
    with pytest.raises(UsageError, match=r"MUJOCO_GL=osmesa.*libosmesa6"):
        mjreplay._mujoco()
