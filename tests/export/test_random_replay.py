"""Random rigs (tests/random_rigs.py, the rigs of tests/sim/test_random_rigs.py) and odd runs
through ``legdsl replay --mujoco`` (``legdsl.export.mjreplay``).

Each rig runs passively for 0.3 s on the Python backend (half with the default fall rules, so
some end by a fall or a divergence), recorded at a rate drawn from 100 Hz, 37 Hz and 0 (every
step), and is replayed at a frame rate drawn from 10 to 100 per second. ``replay_frames`` must
give a frame every 1/fps from the first sample to the last (docs/export.md: as ``legdsl animate
--video``); at every frame that is a recorded sample, MuJoCo's ``mj_kinematics`` of the frame's
``qpos`` must put EVERY body (position and rotation) where the generated kinematics has it at
the recorded coordinates, to 1e-9 (docs/export.md) times the links' largest distance from the
origin in metres where that exceeds 1 m (a diverged run's last sample). One rig in three is
also rendered, by ``legdsl replay DIR --mujoco -o x.mp4 --fps F --size WxH``: ffprobe must
count as many frames at that size. The odd runs: a one-sample run, a ``--record-rate 0`` run,
a planar rig, and a ``--scale`` run, which replay cannot show and must refuse in one line.

``LEGDSL_RANDOM_REPLAYS=N`` checks N rigs (default ``CI_RIGS``) from seeds
``LEGDSL_RANDOM_REPLAY_SEED``, +1, ...; a failure names its seed and prints the rig's text.
"""

from __future__ import annotations

import contextlib
import io
import math
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from runtime_helpers import legdsl_in_process
from seeded import told_with_seed

from legdsl.cli import main
from legdsl.export.motion import read_run
from legdsl.lang.errors import UsageError
from legdsl.pipeline.generated import load_dynamics

# MuJoCo picks its OpenGL backend when it is first imported: an offscreen one (EGL) if this
# module imports it first; imported before without MUJOCO_GL it is GLFW, which aborts the
# process at a second renderer without a display, so ``legdsl replay`` then runs on its own
RENDERS_HERE = "mujoco" not in sys.modules or bool(os.environ.get("MUJOCO_GL"))
os.environ.setdefault("MUJOCO_GL", "egl")
mujoco = pytest.importorskip("mujoco")
from random_rigs import recorded_rig, rig_shown  # noqa: E402  (needs mujoco)

from legdsl.export.mjcf import mjcf_names  # noqa: E402
from legdsl.export.mjreplay import replay_frames  # noqa: E402

CI_RIGS = 1
COUNT = int(os.environ.get("LEGDSL_RANDOM_REPLAYS", CI_RIGS))
FIRST_SEED = int(os.environ.get("LEGDSL_RANDOM_REPLAY_SEED", "0"))
DURATION = 0.3
RECORD_RATES = (100.0, 37.0, 0.0)
FRAME_RATES = (10.0, 24.0, 25.0, 30.0, 50.0, 60.0, 100.0)
TOLERANCE = 1e-9  # m, and for rotation matrices' entries (docs/export.md: the MuJoCo replay)


def promised_frames(span: float, fps: float) -> int:
    """docs/export.md, as ``animate --video``: 0, 1/fps, ... up to the run's last sample."""
    return math.floor(span * fps + 1e-9) + 1


def check_poses(run_dir: Path, generated: Path, fps: float) -> int:
    """A frame every 1/fps; at the frames that are samples, MuJoCo's bodies where legdsl's are
    (how many such frames there were)."""
    run = read_run(run_dir)
    tr = run.trajectory
    mj, data, model, times, qpos = replay_frames(run_dir, fps)
    span = float(tr.t[-1] - tr.t[0])
    assert len(times) == promised_frames(span, fps), f"{len(times)} frames over {span:g} s"
    assert np.allclose(times, np.arange(len(times)) / fps, rtol=0, atol=1e-12)
    assert qpos.shape == (len(times), mj.nq)
    kinematics = load_dynamics(run.model, run.source, generated)
    named = mjcf_names(model)[0]  # a body 'world' is not MuJoCo's world
    t = tr.t - tr.t[0]
    compared = 0
    for f, time in enumerate(times):
        i = int(np.argmin(np.abs(t - time)))
        if abs(t[i] - time) >= 1e-9:
            continue
        compared += 1
        poses = kinematics.body_poses([float(x) for x in tr.q[i]])
        reach = max(1.0, max(float(np.max(np.abs(p))) for p, _ in poses))
        data.qpos[:] = qpos[f]
        mujoco.mj_kinematics(mj, data)
        for body, (p, r) in zip(model.bodies, poses, strict=True):
            got_p = data.body(named[body.name]).xpos
            got_r = data.body(named[body.name]).xmat.reshape(3, 3)
            want_r = np.asarray(r, dtype=float).reshape(3, 3)
            error = max(
                float(np.max(np.abs(got_p - np.asarray(p)))) / reach,
                float(np.max(np.abs(got_r - want_r))),
            )
            assert error <= TOLERANCE, (
                f"body {body.name} at frame {f} (t = {time:g} s, sample {i}) is off MuJoCo's "
                f"by {error:.3g} (position {got_p} vs {list(p)})"
            )
    return compared


WROTE: dict[str, str] = {}  # each mp4's "legdsl: wrote ..." line


def replay(args: list[str]) -> tuple[int, str]:
    """``legdsl replay ARGS`` in this process, or in a process of its own where this one's
    MuJoCo was imported without an offscreen OpenGL backend (MUJOCO_GL is read on import)."""
    status, said = 2, "offscreen renderer could not start"
    if RENDERS_HERE:
        printed, told = io.StringIO(), io.StringIO()  # legdsl_in_process's, with the stdout
        with contextlib.redirect_stdout(printed), contextlib.redirect_stderr(told):
            status = main(["replay", *args])
        said = told.getvalue()
        WROTE[args[args.index("-o") + 1]] = printed.getvalue() + said
    if status == 2 and "offscreen renderer could not start" in said:
        env = {k: v for k, v in os.environ.items() if k not in ("MUJOCO_GL", "DISPLAY")}
        env["PYTHONPATH"] = os.pathsep.join(sys.path)
        done = subprocess.run(
            [sys.executable, "-m", "legdsl", "replay", *args],
            capture_output=True,
            text=True,
            env=env,
            timeout=300,
        )
        status, said = done.returncode, done.stderr
        WROTE[args[args.index("-o") + 1]] = done.stdout + said
        if status == 2 and "offscreen renderer could not start" in said:
            from external_tools import loud_skip

            loud_skip(said.strip())
    return status, said


def check_mp4(run_dir: Path, out: Path, fps: float, size: tuple[int, int]) -> str:
    """The mp4 of ``legdsl replay``: ffprobe's frame count and size; what it said it wrote."""
    from external_tools import ffmpeg, ffprobe_frames

    ffmpeg()
    tr = read_run(run_dir).trajectory
    args = [str(run_dir), "--mujoco", "-o", str(out), "--fps", f"{fps:g}"]
    status, said = replay([*args, "--size", f"{size[0]}x{size[1]}"])
    assert status == 0, said
    assert "Traceback" not in said and "internal error" not in said
    width, height, frames = ffprobe_frames(out)
    assert (width, height) == size
    assert frames == promised_frames(float(tr.t[-1] - tr.t[0]), fps)
    return WROTE.get(str(out), "")


def check_rig(seed: int, where: Path) -> None:
    rng = np.random.default_rng([seed, 11])
    record_rate = float(rng.choice(RECORD_RATES))
    fps = float(rng.choice(FRAME_RATES))
    recorded_rig(seed, where, DURATION, record_rate)
    t = read_run(where / "run").trajectory.t
    span = float(t[-1] - t[0])
    if span > 0 and promised_frames(span, fps) < 2:  # a run stopped early (seed 16400: 0.05 s)
        with pytest.raises(UsageError, match=r"gives one frame .*two frames need") as refused:
            replay_frames(where / "run", fps)  # one still picture is refused, saying what to give
        named = re.search(r"two frames need --fps (\S+) or more", str(refused.value))
        assert named is not None, refused.value
        fps = float(named.group(1))  # the rate it names
    check_poses(where / "run", where / "generated", fps)
    if rng.random() < 1 / 3 and shutil.which("ffprobe"):
        size = (2 * int(rng.integers(32, 100)), 2 * int(rng.integers(32, 80)))  # even: H.264's
        check_mp4(where / "run", where / "x.mp4", fps, size)


SEEDS = range(FIRST_SEED, FIRST_SEED + COUNT)


@pytest.mark.parametrize("seed", SEEDS)
def test_random_rig_replays_with_every_body_where_the_run_had_it(seed: int, tmp_path: Path) -> None:
    rerun = f"LEGDSL_RANDOM_REPLAY_SEED={seed} LEGDSL_RANDOM_REPLAYS=1"
    with told_with_seed(f"random rig of seed {seed}", rerun, lambda: rig_shown(seed, tmp_path)):
        check_rig(seed, tmp_path)


def test_a_rig_whose_light_body_cannot_carry_an_anchor_pad_replays(tmp_path: Path) -> None:
    """Seed 1's 3D welded rig (a ball, a slide, a mirrored limb): body m_a is too light for its
    toe's anchor pad, and the replay was refused, saying to export with --no-anchor-pads,
    which replay has not; it draws the bare link tree (pads are for MuJoCo's simulation)."""
    recorded_rig(1, tmp_path, DURATION, 100.0)
    check_poses(tmp_path / "run", tmp_path / "generated", 30.0)


def test_a_one_sample_run_replays_as_one_frame(tmp_path: Path) -> None:
    """A rig that fell at its first sample (tilted past a fall tilt of 0.001 deg): one frame
    at any rate."""
    source, _ = recorded_rig(6, tmp_path, DURATION, 100.0)  # planar, free root
    argv = ["run", str(source), "--time", "0.3", "--backend", "python", "--fall-tilt", "0.001deg"]
    argv += ["--out", str(tmp_path / "one"), "--generated", str(tmp_path / "generated")]
    status, said = legdsl_in_process(argv)
    assert status == 4, said
    assert len(read_run(tmp_path / "one").trajectory) == 1
    assert check_poses(tmp_path / "one", tmp_path / "generated", 24.0) == 1
    if shutil.which("ffprobe"):
        wrote = check_mp4(tmp_path / "one", tmp_path / "one.mp4", 24.0, (96, 64))
        assert "(1 frame, MuJoCo's renderer)" in wrote, wrote  # it said "1 frames"


def test_a_planar_rig_recorded_at_every_step_replays(tmp_path: Path) -> None:
    """Seed 8's planar welded rig with a mirrored limb and a slide, ``--record-rate 0``: each
    frame at 100 per second is a sample (steps of a divisor of 10 ms)."""
    recorded_rig(8, tmp_path, DURATION, 0.0)
    frames = check_poses(tmp_path / "run", tmp_path / "generated", 100.0)
    assert frames == promised_frames(float(read_run(tmp_path / "run").trajectory.t[-1]), 100.0)


def test_a_scaled_run_is_refused_in_one_line(tmp_path: Path) -> None:
    """A ``--scale`` run holds the scaled creature's motion but names the unscaled file."""
    source, _ = recorded_rig(0, tmp_path, DURATION, 100.0)
    argv = ["run", str(source), "--time", "0.1", "--backend", "python", "--scale", "2"]
    argv += ["--out", str(tmp_path / "scaled"), "--generated", str(tmp_path / "generated")]
    argv += ["--fall-height", "0", "--fall-tilt", "180"]
    status, said = legdsl_in_process(argv)
    assert status in (0, 3), said
    status, said = legdsl_in_process(
        ["replay", str(tmp_path / "scaled"), "--mujoco", "-o", str(tmp_path / "s.mp4")]
    )
    assert status == 2 and said.count("\n") == 1, said
    assert "legdsl scale" in said and "Traceback" not in said and "internal error" not in said
    assert not (tmp_path / "s.mp4").exists()


def test_the_camera_frames_the_feet_of_the_bare_link_tree() -> None:
    """The replay's model has no anchor pads, the bodies that stood at the contacts: the
    camera's extent takes the contacts, so the biped is framed as before (0.83 m, not the
    0.2 m between its body origins, which put the camera 3 times closer)."""
    from conftest import CREATURES

    from legdsl.check.source import check_model
    from legdsl.export.mjcf import model_to_mjcf
    from legdsl.export.mjreplay import _camera

    model = check_model(CREATURES / "biped.leg")
    mj = mujoco.MjModel.from_xml_string(model_to_mjcf(model, pads=False))
    camera = _camera(mujoco, model, mj, mujoco.MjData(mj), mj.qpos0)
    assert camera.distance == pytest.approx(4.5 * (0.83 + 0.5), abs=1e-9)


def test_a_body_with_its_contacts_at_its_origin_is_seen_from_outside(tmp_path: Path) -> None:
    from legdsl.check.source import check_file
    from legdsl.export.mjcf import model_to_mjcf
    from legdsl.export.mjreplay import _camera

    source = tmp_path / "dot.leg"
    source.write_text(
        "creature dot {\n  spatial\n  body b0 free {\n    mass 1 kg\n"
        "    inertia (0.01 kg*m^2, 0.01 kg*m^2, 0.01 kg*m^2)\n  }\n  contact c0 on b0\n}\n"
    )
    model = check_file(source)[0]
    mj = mujoco.MjModel.from_xml_string(model_to_mjcf(model, pads=False))
    camera = _camera(mujoco, model, mj, mujoco.MjData(mj), mj.qpos0)
    assert camera.distance > 0


def test_a_creature_lighter_than_mujocos_inertia_floor_replays(tmp_path: Path) -> None:
    """A 1 mm dot (inertia 4e-17 kg*m^2, under MuJoCo's 1e-14): replay was refused with the
    export's advice to scale the creature up; a drawing needs no inertia, so it is raised."""
    source = tmp_path / "dot.leg"
    source.write_text(
        "creature dot {\n  spatial\n  body b0 free {\n    mass 0.0001 kg\n"
        "    inertia (4e-17 kg*m^2, 4e-17 kg*m^2, 4e-17 kg*m^2)\n"
        "    initial z = 0.001 m\n  }\n  contact c0 on b0 at (0.001 m, 0 m, 0 m)\n}\n"
    )
    argv = ["run", str(source), "--time", "0.02", "--backend", "python", "--fall-height", "0"]
    argv += ["--out", str(tmp_path / "run"), "--generated", str(tmp_path / "generated")]
    status, said = legdsl_in_process(argv)
    assert status in (0, 4), said  # a fall through its ground, 16 ms in, is a run too
    assert check_poses(tmp_path / "run", tmp_path / "generated", 100.0) >= 1


NAMES_MUJOCO_KEEPS = """creature names {
  spatial
  body world free {
    mass 2 kg
    inertia (0.02 kg*m^2, 0.03 kg*m^2, 0.04 kg*m^2)
    initial x = 0.1 m, z = 0.5 m
    velocity vx = 0.4 m/s, wx = 1 rad/s, wz = 2 rad/s
  }
  body arm on world via revolute root at (0.1 m, 0 m, 0 m) {
    axis (0, 1, 0)
    initial 30 deg
    length 0.3 m  com 0.15 m  mass 0.5 kg  inertia (0.004, 0.004, 0.0001) kg*m^2
  }
  contact toe on arm at tip
}
"""


def test_a_body_named_world_and_a_coordinate_named_root_replay(tmp_path: Path) -> None:
    """MuJoCo names its world body 'world' and legdsl's MJCF the free root's joint 'root':
    ``legdsl export`` refuses such a creature at the clashing line (a file a person reads keeps
    the .leg's names), both lines at once (it told the second only once the first was
    renamed), and replay refused it the same way; it draws it under fresh names."""
    source = tmp_path / "names.leg"
    source.write_text(NAMES_MUJOCO_KEEPS)
    status, said = legdsl_in_process(
        ["export", str(source), "--format", "mjcf", "-o", str(tmp_path / "n.xml")]
    )
    assert status == 2 and f"{source}:3:3:" in said and "rename this body" in said, said
    assert f"{source}:9:34: error: in MJCF the free root's joint is called 'root'" in said, said
    argv = ["run", str(source), "--time", "0.2", "--backend", "python", "--fall-height", "0"]
    argv += ["--fall-tilt", "180", "--record-rate", "100", "--out", str(tmp_path / "run")]
    status, said = legdsl_in_process([*argv, "--generated", str(tmp_path / "generated")])
    assert status == 0, said
    # the free root's seven coordinates in MuJoCo's free joint, the hinge's in its own
    assert check_poses(tmp_path / "run", tmp_path / "generated", 50.0) >= 10
