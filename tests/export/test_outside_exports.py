"""Creatures written outside the team through every export: a planar one with knees
(knee_runner) and a quadruped whose gaits come from a used file (dachs, ``use``).

Each is run for 0.5 s (recorded at 100 Hz), then exported as glTF (with and without
``--skin``), USD, BVH, MJCF and URDF and replayed in MuJoCo. Every file is read back: its
links, joints and frames are counted against the model and the run, and a foot's position,
composed from what the file says, is the contact's position at the run's recorded
coordinates (generated kinematics), at every exported frame that is a recorded sample.
"""

from __future__ import annotations

import math
import shutil
import tempfile
from pathlib import Path

import numpy as np
import pytest
from anim_runs import export_animations
from conftest import ROOT
from test_bvh import world_poses
from test_gltf import accessor, read_glb

from legdsl.cli import main
from legdsl.export.bvh import Z_UP_TO_Y_UP
from legdsl.export.motion import quaternion_to_matrix, read_run
from legdsl.pipeline.generated import load_dynamics

bvh = pytest.importorskip("bvh")
mujoco = pytest.importorskip("mujoco")
pytest.importorskip("pygltflib", reason="needs pygltflib: pip install 'legdsl[export]'")
pytest.importorskip("pxr", reason="needs usd-core: pip install 'legdsl[export]'")
from pxr import Usd, UsdGeom  # noqa: E402

OUTSIDE = ROOT / "tests" / "good" / "outside"
FPS = 50  # every other recorded sample (100 Hz)
# (file, controller, the foot followed)
CREATURES = [("knee_runner", "run", "toe_r"), ("dachs", "trot", "toe_rl")]


class Exported:
    def __init__(self, name: str, controller: str, foot: str, where: Path) -> None:
        self.name, self.source = name, OUTSIDE / f"{name}.leg"
        generated, self.run_dir = where / "generated", where / "run"
        argv = ["run", str(self.source), "--controller", controller, "--time", "0.5"]
        argv += ["--record-rate", "100", "--out", str(self.run_dir)]
        assert main([*argv, "--generated", str(generated)]) == 0
        run = read_run(self.run_dir)
        self.model, tr = run.model, run.trajectory
        kinematics = load_dynamics(run.model, run.source, generated)
        self.foot = [c.name for c in self.model.contacts].index(foot)
        self.foot_contact = self.model.contacts[self.foot]
        # the frames, 1/FPS apart from the first sample to the last, and their recorded samples
        span = float(tr.t[-1] - tr.t[0])
        self.frames = math.floor(span * FPS + 1e-9) + 1
        self.samples: dict[int, int] = {}
        for f in range(self.frames):
            i = int(np.argmin(np.abs(tr.t - tr.t[0] - f / FPS)))
            if abs(tr.t[i] - tr.t[0] - f / FPS) < 1e-9:
                self.samples[f] = i
        assert len(self.samples) == self.frames
        self.q = tr.q
        self.foot_at = {
            f: np.asarray(kinematics.contact_positions([float(x) for x in tr.q[i]]))[self.foot]
            for f, i in self.samples.items()
        }
        self.files = export_animations(self.run_dir, where / name, FPS, generated)
        for fmt, extra in (("mjcf", []), ("urdf", ["--link-mass", "1e-6"])):
            out = where / f"{name}.{fmt}"
            assert main(["export", str(self.source), "--format", fmt, "-o", str(out), *extra]) == 0
            self.files[fmt] = out

    @property
    def body_names(self) -> list[str]:
        return [b.name for b in self.model.bodies]

    def foot_from(self, position: np.ndarray, rotation: np.ndarray) -> np.ndarray:
        """The foot contact's world position, from its body's pose (legdsl's axes)."""
        return position + rotation @ np.asarray(self.foot_contact.point, dtype=float)


@pytest.fixture(scope="module", params=CREATURES, ids=[c[0] for c in CREATURES])
def exported(request):
    where = Path(tempfile.mkdtemp(prefix=f"legdsl-outside-{request.param[0]}-"))
    try:
        yield Exported(*request.param, where)
    finally:
        shutil.rmtree(where, ignore_errors=True)


@pytest.mark.parametrize("key", ["glb", "skin"])
def test_gltf_links_frames_and_foot(exported: Exported, key: str) -> None:
    doc, blob = read_glb(exported.files[key])
    nodes = doc["nodes"]
    index = {n.get("name"): i for i, n in enumerate(nodes)}
    assert set(exported.body_names) <= set(index)
    (animation,) = doc["animations"]
    assert len(animation["channels"]) == 2 * len(exported.body_names)
    times = accessor(doc, blob, animation["samplers"][0]["input"])
    assert len(times) == exported.frames
    assert float(times[-1]) == pytest.approx((exported.frames - 1) / FPS, abs=1e-6)
    if key == "skin":
        (skin,) = doc["skins"]
        assert sorted(nodes[j]["name"] for j in skin["joints"]) == sorted(exported.body_names)
    channels = {
        (c["target"]["node"], c["target"]["path"]): accessor(
            doc, blob, animation["samplers"][c["sampler"]]["output"]
        )
        for c in animation["channels"]
    }
    parent_of = {c: i for i, n in enumerate(nodes) for c in n.get("children", [])}
    chain = [index[exported.foot_contact.body]]
    while chain[-1] != index[exported.model.name]:
        chain.append(parent_of[chain[-1]])
    top = np.eye(4)
    top[:3, :3] = quaternion_to_matrix(np.array(nodes[chain[-1]]["rotation"]))
    for f, expected in exported.foot_at.items():
        world = top
        for node in reversed(chain[:-1]):
            local = np.eye(4)
            local[:3, 3] = channels[(node, "translation")][f]
            local[:3, :3] = quaternion_to_matrix(channels[(node, "rotation")][f].astype(float))
            world = world @ local
        # back to legdsl's z-up axes; float32 keys
        position, rotation = Z_UP_TO_Y_UP.T @ world[:3, 3], Z_UP_TO_Y_UP.T @ world[:3, :3]
        assert np.allclose(exported.foot_from(position, rotation), expected, atol=1e-6), f


def test_usd_links_frames_and_foot(exported: Exported) -> None:
    stage = Usd.Stage.Open(str(exported.files["usda"]))
    assert stage.GetEndTimeCode() == exported.frames - 1
    assert stage.GetTimeCodesPerSecond() == FPS
    links = {
        p.GetName(): p
        for p in stage.Traverse()
        if p.IsA(UsdGeom.Xform) and p.GetName() in exported.body_names
    }
    assert sorted(links) == sorted(exported.body_names)
    foot_link = links[exported.foot_contact.body]
    for f, expected in exported.foot_at.items():
        m = np.array(UsdGeom.XformCache(Usd.TimeCode(f)).GetLocalToWorldTransform(foot_link)).T
        assert np.allclose(exported.foot_from(m[:3, 3], m[:3, :3]), expected, atol=1e-9), f


def test_bvh_skeleton_frames_and_foot(exported: Exported) -> None:
    mocap = bvh.Bvh(exported.files["bvh"].read_text())
    assert sorted(mocap.get_joints_names()) == sorted(exported.body_names)
    for body in exported.model.bodies:
        parent = mocap.joint_parent(body.name)
        assert (parent.name if parent is not None else None) == body.parent
    assert mocap.nframes == exported.frames
    assert mocap.frame_time == pytest.approx(1 / FPS, rel=1e-8)
    for f, expected in exported.foot_at.items():
        p, r = world_poses(mocap, f)[exported.foot_contact.body]
        position, rotation = Z_UP_TO_Y_UP.T @ p, Z_UP_TO_Y_UP.T @ r @ Z_UP_TO_Y_UP
        # six decimals in the file (1e-6 m, 1e-6 degree), summed down the chain
        assert np.allclose(exported.foot_from(position, rotation), expected, atol=3e-6), f


def _set_coordinates(mj, model, q: np.ndarray):
    from legdsl.export.mjreplay import qpos_map

    data = mujoco.MjData(mj)
    data.qpos[qpos_map(model, mj)] = q
    mujoco.mj_kinematics(mj, data)
    return data


@pytest.mark.parametrize("fmt", ["mjcf", "urdf"])
def test_mujoco_loads_the_model_and_puts_the_foot_where_the_run_had_it(
    exported: Exported, fmt: str
) -> None:
    mj = mujoco.MjModel.from_xml_path(str(exported.files[fmt]))
    bodies = {mj.body(i).name for i in range(mj.nbody)}
    assert set(exported.body_names) <= bodies
    joints = {mj.joint(i).name for i in range(mj.njnt)}
    coordinates = {d.name for d in exported.model.dofs}  # a 3D free root's 7: one joint 'root'
    assert len(coordinates) == exported.model.nq - (7 if exported.model.joints[0].is_free_3d else 0)
    assert coordinates <= joints
    assert ("root" in joints) == exported.model.joints[0].is_free_3d
    if fmt == "mjcf":  # the contact is a site; URDF's contact links are merged by MuJoCo
        for f, expected in exported.foot_at.items():
            data = _set_coordinates(mj, exported.model, exported.q[exported.samples[f]])
            site = mj.site(exported.foot_contact.name).id
            assert np.allclose(data.site_xpos[site], expected, atol=1e-9), f


def test_mujoco_replay_has_the_runs_frames_and_foot(exported: Exported) -> None:
    from legdsl.export.mjreplay import replay_frames

    mj, data, _, times, qpos = replay_frames(exported.run_dir, FPS, exported.source)
    assert len(times) == exported.frames
    site = mj.site(exported.foot_contact.name).id
    for f, expected in exported.foot_at.items():
        data.qpos[:] = qpos[f]
        mujoco.mj_kinematics(mj, data)
        assert np.allclose(data.site_xpos[site], expected, atol=1e-9), f
