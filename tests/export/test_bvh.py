"""BVH export, read back with an independent parser (the ``bvh`` package on PyPI).

The skeleton must be the link tree with the joint origins as offsets; composing
the channels down the tree must give the run's world poses; and each hinge's
angle, read from the channels, must be the run's joint coordinate.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from anim_runs import creature_run, exported_into_a_pipe, generated_dir

from legdsl.cli import main
from legdsl.export.bvh import Z_UP_TO_Y_UP, bvh_text
from legdsl.export.frames import interpolate_q
from legdsl.export.motion import Motion, load_motion, quaternion_to_matrix, read_run

bvh = pytest.importorskip(
    "bvh", reason="the bvh parser is in the test extra: pip install '.[test]'"
)


def rot(axis: str, degrees: float) -> np.ndarray:
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    return {
        "X": np.array([[1, 0, 0], [0, c, -s], [0, s, c]]),
        "Y": np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]]),
        "Z": np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]),
    }[axis]


@pytest.fixture(scope="module", params=["kangaroo", "quadruped", "hopper"])
def exported(request, tmp_path_factory) -> tuple[Motion, object, np.ndarray, object]:
    run_dir = creature_run(request.param, tmp_path_factory.mktemp(request.param) / "run")
    motion = load_motion(run_dir, fps=30, generated=generated_dir())
    run = read_run(run_dir)
    q = interpolate_q(
        run.model, run.trajectory.t, run.trajectory.q, run.trajectory.t[0] + motion.times
    )
    return motion, bvh.Bvh(bvh_text(motion)), q, run.model


def axis_angle(axis: np.ndarray, angle: float) -> np.ndarray:
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k


def world_poses(mocap, frame: int) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Each joint's (position, rotation) in the file's frame: T(t) R, composed down the tree,
    read as Blender reads it: a joint with position channels has them as its whole local
    translation t, in place of its OFFSET (io_anim_bvh's import_bvh.py poses a bone at
    ``Matrix.Translation(Vector(bvh_loc) - bvh_node.rest_head_local)`` from its rest head at
    the OFFSET, and its exporter writes the bone's location there); t is the OFFSET otherwise."""
    out: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    for name in mocap.get_joints_names():  # parents are listed before their children
        channels = mocap.joint_channels(name)
        values = dict(zip(channels, mocap.frame_joint_channels(frame, name, channels), strict=True))
        if any(c.endswith("position") for c in channels):
            t = np.array([values.get(f"{a}position", 0.0) for a in "XYZ"], dtype=float)
        else:
            t = np.array(mocap.joint_offset(name), dtype=float)
        r = np.eye(3)
        for c in channels:
            if c.endswith("rotation"):
                r = r @ rot(c[0], values[c])
        parent = mocap.joint_parent(name)
        if parent is None:
            out[name] = (t, r)
        else:
            pt, pr = out[parent.name]
            out[name] = (pt + pr @ t, pr @ r)
    return out


def test_skeleton_is_the_link_tree(exported) -> None:
    motion, mocap, _, model = exported
    names = [b.name for b in motion.bodies]
    assert sorted(mocap.get_joints_names()) == sorted(names)
    joints = {j.child: j for j in model.joints}
    for b in motion.bodies:
        parent = mocap.joint_parent(b.name)
        assert (parent.name if parent is not None else None) == b.parent
        if b.parent is not None:
            offset = Z_UP_TO_Y_UP @ np.array(joints[b.name].origin)
            assert np.allclose(mocap.joint_offset(b.name), offset, atol=1e-6)
    assert mocap.nframes == motion.frames
    assert mocap.frame_time == pytest.approx(motion.duration / (motion.frames - 1), rel=1e-6)


def test_channels_replay_the_world_poses(exported) -> None:
    motion, mocap, _, _ = exported
    for f in range(0, motion.frames, 3):
        poses = world_poses(mocap, f)
        for b, body in enumerate(motion.bodies):
            p, r = poses[body.name]
            assert np.allclose(p, Z_UP_TO_Y_UP @ motion.positions[f, b], atol=2e-5), body.name
            expected = (
                Z_UP_TO_Y_UP @ quaternion_to_matrix(motion.quaternions[f, b]) @ Z_UP_TO_Y_UP.T
            )
            assert np.allclose(r, expected, atol=1e-5), body.name


def test_hinge_angles_are_the_runs_joint_coordinates(exported) -> None:
    motion, mocap, q, model = exported
    checked = 0
    for joint in model.joints:
        if joint.parent is None or any(d.motion != "hinge" for d in joint.dofs):
            continue
        for f in range(motion.frames):
            channels = mocap.joint_channels(joint.child)
            values = mocap.frame_joint_channels(f, joint.child, channels)
            r = np.eye(3)
            for c, v in zip(channels, values, strict=True):
                if c.endswith("rotation"):
                    r = r @ rot(c[0], v)
            # the joint's chain of hinges at the run's coordinates, in the file's axes
            expected = np.eye(3)
            for d in joint.dofs:
                expected = expected @ axis_angle(Z_UP_TO_Y_UP @ np.array(d.axis), q[f, d.q_index])
            assert np.allclose(r, expected, atol=1e-5), joint.name
            if len(joint.dofs) == 1:  # and the angle itself, about the hinge's axis
                axis = Z_UP_TO_Y_UP @ np.array(joint.dofs[0].axis)
                s = 0.5 * np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]]) @ axis
                angle = math.atan2(s, (np.trace(r) - 1) / 2)
                error = math.remainder(angle - q[f, joint.dofs[0].q_index], math.tau)
                assert error == pytest.approx(0, abs=1e-4)
            checked += 1
    assert checked >= motion.frames


def test_a_slides_position_channels_are_its_whole_local_translation(exported) -> None:
    """A joint that slides (the hopper's, the quadruped's legs) has position channels holding
    its origin plus the slide's displacement along its axis (the OFFSET at zero slide), as
    Blender reads them: they used to hold the displacement alone, which Blender put in place
    of the OFFSET, so the hopper's shank sat 0.3 m off."""
    motion, mocap, q, model = exported
    checked = 0
    for joint in model.joints:
        if joint.parent is None or [d.motion for d in joint.dofs] != ["slide"]:
            continue
        dof = joint.dofs[0]
        channels = [f"{a}position" for a in "XYZ"]
        for f in range(motion.frames):
            values = np.array(mocap.frame_joint_channels(f, joint.child, channels))
            local = np.array(joint.origin) + np.array(dof.axis) * q[f, dof.q_index]
            assert np.allclose(values, Z_UP_TO_Y_UP @ local, atol=2e-6), joint.name
            checked += 1
    if any(d.motion == "slide" for j in model.joints if j.parent is not None for d in j.dofs):
        assert checked >= motion.frames


def test_cli_writes_bvh(tmp_path: Path) -> None:
    run = creature_run("kangaroo", tmp_path / "run")
    out = tmp_path / "k.bvh"
    args = ["export-motion", str(run), "--format", "bvh", "-o", str(out)]
    assert main([*args, "--generated", str(generated_dir())]) == 0
    assert out.read_text().startswith("HIERARCHY\nROOT trunk")


@pytest.mark.parametrize("fmt", ["bvh", "gltf"])
def test_an_export_into_a_pipe_says_the_size_it_wrote(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], fmt: str
) -> None:
    """``-o /dev/stdout | cat`` said "wrote /dev/stdout (0 B: ...)": the size of the pipe."""
    run = creature_run("kangaroo", tmp_path / "run")
    pipe = tmp_path / "pipe"
    code, got = exported_into_a_pipe(run, fmt, pipe)
    assert code == 0
    said = "".join(capsys.readouterr())
    assert f"wrote {pipe} (" in said and f"wrote {pipe} (0 B" not in said, said
    assert len(got) > 1000
