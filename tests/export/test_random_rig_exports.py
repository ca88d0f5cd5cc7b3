"""Random rigs (tests/random_rigs.py, the rigs of tests/sim/test_random_rigs.py) through the
animation exports: glTF (with and without ``--skin``), USD and BVH, each read back by a reader
that is not legdsl's (the GLB by hand, usd-core, the ``bvh`` package).

Each rig runs passively for 0.3 s (recorded at 100 Hz, Python backend; half of them with the
default fall rules, so some end by a fall or a divergence) and is exported at a frame rate
drawn from 25 to 100 per second. Every file's links, joints and frames are counted against the
model and the run, and EVERY contact's world position, composed from what the file says, is
the contact's position at the run's recorded coordinates (generated kinematics) at every
exported frame that is a recorded sample, within docs/export.md's tolerances (1e-6 m in
glTF's float32 keys, 1e-9 m in USD, 3e-6 m in BVH's six decimals), times the links' largest
distance from the origin in metres where that exceeds 1 m (a diverged run's last sample). A run
too short for two frames at the drawn rate must be refused in one line, and is then exported at
a rate that gives two.

``LEGDSL_RANDOM_RIG_EXPORTS=N`` checks N rigs (default ``CI_RIGS``) from seeds
``LEGDSL_RANDOM_RIG_EXPORT_SEED``, +1, ...; a failure names its seed and prints the rig's text.
"""

from __future__ import annotations

import math
import os
import re
from pathlib import Path

import numpy as np
import pytest
from anim_runs import export_animations
from runtime_helpers import legdsl_in_process
from seeded import told_with_seed
from test_bvh import world_poses
from test_gltf import accessor, read_glb

from legdsl.export.bvh import Z_UP_TO_Y_UP
from legdsl.export.motion import quaternion_to_matrix, read_run
from legdsl.pipeline.generated import load_dynamics

bvh = pytest.importorskip("bvh")
pytest.importorskip("mujoco")  # the rigs are placed on their ground by MuJoCo's kinematics
pytest.importorskip("pygltflib", reason="needs pygltflib: pip install 'legdsl[export]'")
pytest.importorskip("pxr", reason="needs usd-core: pip install 'legdsl[export]'")
from pxr import Usd, UsdGeom  # noqa: E402
from random_rigs import recorded_rig, rig_shown  # noqa: E402

CI_RIGS = 1
COUNT = int(os.environ.get("LEGDSL_RANDOM_RIG_EXPORTS", CI_RIGS))
FIRST_SEED = int(os.environ.get("LEGDSL_RANDOM_RIG_EXPORT_SEED", "0"))
DURATION, RECORD_RATE = 0.3, 100.0
FRAME_RATES = (25.0, 30.0, 50.0, 60.0, 100.0)
# docs/export.md: float32 keys; six decimals summed down the chain; doubles
TOLERANCE = {"glb": 1e-6, "skin": 1e-6, "usda": 1e-9, "bvh": 3e-6}


class Exported:
    """A rig's run, its contacts at the recorded samples, and its four animation files."""

    def __init__(self, seed: int, where: Path) -> None:
        self.source, status = recorded_rig(seed, where, DURATION, RECORD_RATE)
        generated, self.run_dir = where / "generated", where / "run"
        fps = float(np.random.default_rng([seed, 10]).choice(FRAME_RATES))
        run = read_run(self.run_dir)
        self.model, tr = run.model, run.trajectory
        self.status = status
        kinematics = load_dynamics(run.model, run.source, generated)
        t = tr.t - tr.t[0]
        span = float(t[-1])
        assert np.all(np.isfinite(tr.q)), "a recorded sample that is not finite"
        self.refused = None
        if 0 < span * fps < 1 - 1e-9:  # one frame of a run that moves: refused, saying so
            status, said = legdsl_in_process(
                ["export-motion", str(self.run_dir), "--fps", repr(fps), "-o", str(where / "x.glb")]
            )
            advice = re.search(r"two frames need --fps (\S+) or more", said)
            assert status == 2 and said.count("\n") == 1 and advice, said
            self.refused, fps = said, float(advice.group(1))  # the advice, which must work
        self.fps = fps
        # the frames: 1/fps apart unless that is as dense as the samples (then the samples)
        if len(t) > 1 and self.fps < (len(t) - 1) / span * (1 - 1e-9):
            self.times = np.arange(math.floor(span * self.fps + 1e-9) + 1) / self.fps
        else:
            self.times = t.copy()
        self.samples = {}
        for f, time in enumerate(self.times):
            i = int(np.argmin(np.abs(t - time)))
            if abs(t[i] - time) < 1e-9:
                self.samples[f] = i
        # the lengths the file's numbers carry: the links' distances from the origin, at most
        # (a diverged run's last sample is 1e7 m out)
        self.reach = {
            f: max(float(np.max(np.abs(p))) for p, _ in kinematics.body_poses(list(tr.q[i])))
            for f, i in self.samples.items()
        }
        self.contacts_at = {
            f: np.asarray(kinematics.contact_positions([float(x) for x in tr.q[i]]))
            for f, i in self.samples.items()
        }
        self.files = export_animations(self.run_dir, where / self.source.stem, self.fps, generated)

    @property
    def body_names(self) -> list[str]:
        return [b.name for b in self.model.bodies]

    def check_contacts(self, key: str, pose_of) -> None:
        """Every contact, placed from its body's pose in the file (``pose_of(frame)``: body
        name to position and rotation in legdsl's axes), where the run had it."""
        for f, expected in self.contacts_at.items():
            poses = pose_of(f)
            for c, want in zip(self.model.contacts, expected, strict=True):
                p, r = poses[c.body]
                got = p + r @ np.asarray(c.point, dtype=float)
                error = float(np.max(np.abs(got - want)))
                # the docs' precision for lengths of a metre or less, relative for longer
                reach = max(1.0, 2 * self.reach[f] + float(np.linalg.norm(c.point)))
                assert error <= TOLERANCE[key] * reach, (
                    f"{key}: contact {c.name} at frame {f} (t = {self.times[f]:g} s) is "
                    f"{error:.3g} m from the run's"
                )


def check_gltf(e: Exported, key: str) -> None:
    doc, blob = read_glb(e.files[key])
    nodes = doc["nodes"]
    index = {n.get("name"): i for i, n in enumerate(nodes)}
    assert set(e.body_names) <= set(index), f"{key}: links missing"
    (animation,) = doc["animations"]
    assert len(animation["channels"]) == 2 * len(e.body_names)
    times = accessor(doc, blob, animation["samplers"][0]["input"])
    assert np.allclose(times, e.times, atol=1e-6), f"{key}: {len(times)} keys, {len(e.times)} due"
    if key == "skin":
        (skin,) = doc["skins"]
        assert sorted(nodes[j]["name"] for j in skin["joints"]) == sorted(e.body_names)
    channels = {
        (c["target"]["node"], c["target"]["path"]): accessor(
            doc, blob, animation["samplers"][c["sampler"]]["output"]
        )
        for c in animation["channels"]
    }
    parent_of = {c: i for i, n in enumerate(nodes) for c in n.get("children", [])}
    top = index[e.model.name]
    assert "translation" not in nodes[top]
    turn = quaternion_to_matrix(np.array(nodes[top]["rotation"]))

    def poses(f: int) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        out = {}
        for name in e.body_names:
            chain = [index[name]]
            while chain[-1] != top:
                chain.append(parent_of[chain[-1]])
            p, r = np.zeros(3), turn
            for node in reversed(chain[:-1]):
                p = p + r @ channels[(node, "translation")][f].astype(float)
                r = r @ quaternion_to_matrix(channels[(node, "rotation")][f].astype(float))
            out[name] = (Z_UP_TO_Y_UP.T @ p, Z_UP_TO_Y_UP.T @ r)  # back to z-up
        return out

    e.check_contacts(key, poses)


def check_usd(e: Exported) -> None:
    stage = Usd.Stage.Open(str(e.files["usda"]))
    assert stage.GetEndTimeCode() == len(e.times) - 1
    links = {
        p.GetName(): p
        for p in stage.Traverse()
        if p.IsA(UsdGeom.Xform) and p.GetName() in e.body_names
    }
    assert sorted(links) == sorted(e.body_names)

    def poses(f: int) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        cache = UsdGeom.XformCache(Usd.TimeCode(f))
        out = {}
        for name, prim in links.items():
            m = np.array(cache.GetLocalToWorldTransform(prim)).T
            out[name] = (m[:3, 3], m[:3, :3])
        return out

    e.check_contacts("usda", poses)


def check_bvh(e: Exported) -> None:
    mocap = bvh.Bvh(e.files["bvh"].read_text())
    assert sorted(mocap.get_joints_names()) == sorted(e.body_names)
    for body in e.model.bodies:
        parent = mocap.joint_parent(body.name)
        assert (parent.name if parent is not None else None) == body.parent
    assert mocap.nframes == len(e.times)
    if len(e.times) > 1:
        assert mocap.frame_time == pytest.approx(e.times[1], rel=1e-6)

    def poses(f: int) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        return {
            name: (Z_UP_TO_Y_UP.T @ p, Z_UP_TO_Y_UP.T @ r @ Z_UP_TO_Y_UP)
            for name, (p, r) in world_poses(mocap, f).items()
        }

    e.check_contacts("bvh", poses)


def check_rig(seed: int, where: Path) -> None:
    e = Exported(seed, where)
    for key in ("glb", "skin"):
        check_gltf(e, key)
    check_usd(e)
    check_bvh(e)


SEEDS = range(FIRST_SEED, FIRST_SEED + COUNT)


@pytest.mark.parametrize("seed", SEEDS)
def test_random_rig_exports_read_back_with_every_contact_where_the_run_had_it(
    seed: int, tmp_path: Path
) -> None:
    rerun = f"LEGDSL_RANDOM_RIG_EXPORT_SEED={seed} LEGDSL_RANDOM_RIG_EXPORTS=1"
    with told_with_seed(f"random rig of seed {seed}", rerun, lambda: rig_shown(seed, tmp_path)):
        check_rig(seed, tmp_path)


def test_a_frame_a_rounding_off_a_sample_is_that_sample() -> None:
    """Seed 125's diverged run: its last step turned a hinge by 2e7 rad, and its last frame,
    1e-17 s off the last sample, weighed that step 1e-15 short of whole: 3e-8 rad off, a
    contact 0.2 m from the sample's (in USD's doubles too)."""
    from legdsl.export.frames import interpolate

    t = np.array([0.0, 0.11, 0.12])
    values = np.array([0.0, 1.0, 2.3e7])
    got = interpolate(t, values, np.array([0.11 * (1 + 1e-15), 0.12 * (1 - 1e-15)]))
    assert list(got) == [1.0, 2.3e7]
