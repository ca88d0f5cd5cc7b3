"""Creatures of unusual sizes through the exports: the insect pogo scaled by 0.01 (a 0.7 mm
mite, `legdsl scale`) and the hopper by 0.05 (a 5 cm hopper).

Each file is read back and a foot composed from it is where the run had it, to a tolerance
relative to the creature's size; what is absolute in the exports (BVH's decimals, its end
sites, MuJoCo's time step and contact spheres, the player's framing) follows the size.
"""

from __future__ import annotations

import dataclasses
import math
import shutil
import tempfile
from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT
from test_bvh import world_poses

from legdsl.cli import main
from legdsl.export.bvh import Z_UP_TO_Y_UP, bvh_text
from legdsl.export.motion import load_motion, read_run
from legdsl.pipeline.generated import load_dynamics

bvh = pytest.importorskip("bvh")

POGO = ROOT / "tests" / "good" / "outside" / "insect_pogo.leg"
HOPPER = ROOT / "creatures" / "hopper.leg"
MITE_FPS = 10000  # more than the mite's samples per second: the frames are the samples


class Scaled:
    """``source`` scaled by ``factor`` and run for ``seconds`` (its controller ``hop``)."""

    def __init__(self, source: Path, factor: float, seconds: float, where: Path) -> None:
        self.where, self.generated = where, where / "generated"
        self.leg = where / f"{source.stem}_small.leg"
        assert main(["scale", str(source), "--by", str(factor), "-o", str(self.leg)]) == 0
        self.run_dir = where / "run"
        argv = ["run", str(self.leg), "--controller", "hop", "--time", str(seconds)]
        assert main([*argv, "--out", str(self.run_dir), "--generated", str(self.generated)]) == 0
        run = read_run(self.run_dir)
        self.model, self.trajectory = run.model, run.trajectory
        self.kinematics = load_dynamics(run.model, run.source, self.generated)
        self.foot = self.model.contacts[0]

    def motion(self, fps: float):
        return load_motion(self.run_dir, fps=fps, generated=self.generated)

    def foot_at(self, i: int) -> np.ndarray:
        q = [float(x) for x in self.trajectory.q[i]]
        return np.asarray(self.kinematics.contact_positions(q))[0]


@pytest.fixture(scope="module")
def mite():
    where = Path(tempfile.mkdtemp(prefix="legdsl-sizes-mite-"))
    try:
        yield Scaled(POGO, 0.01, 0.05, where)
    finally:
        shutil.rmtree(where, ignore_errors=True)


def test_the_mite_is_the_size_the_tests_assume(mite: Scaled) -> None:
    motion = mite.motion(MITE_FPS)
    size = np.ptp(motion.positions[0], axis=0).max()
    assert 1e-4 < size < 1e-3  # a body and a leg of a few tenths of a millimetre


def test_bvh_keeps_a_mites_foot_to_a_millionth_of_its_size(mite: Scaled) -> None:
    """Six decimals of metres (1 um) put the mite's foot up to 1e-6 m off, a 700th of it."""
    out = mite.where / "mite.bvh"
    argv = ["export-motion", str(mite.run_dir), "--format", "bvh", "-o", str(out)]
    assert main([*argv, "--fps", str(MITE_FPS), "--generated", str(mite.generated)]) == 0
    mocap = bvh.Bvh(out.read_text())
    tr = mite.trajectory
    worst = 0.0
    assert mocap.nframes == len(tr.t)
    for i in range(mocap.nframes):
        p, r = world_poses(mocap, i)[mite.foot.body]
        position, rotation = Z_UP_TO_Y_UP.T @ p, Z_UP_TO_Y_UP.T @ r @ Z_UP_TO_Y_UP
        foot = position + rotation @ np.asarray(mite.foot.point, dtype=float)
        worst = max(worst, float(np.abs(foot - mite.foot_at(i)).max()))
    assert worst < 3e-9, worst  # the mite is 7e-4 m: 3e-9 is 4e-6 of it


def test_a_bvh_end_site_without_a_tip_is_smaller_than_the_mite(mite: Scaled) -> None:
    """The leaf's End Site falls back to a short stub when its link has no length: 1 cm, as
    big as an insect, was fourteen times the mite."""
    motion = mite.motion(MITE_FPS)
    leaf = len(motion.bodies) - 1
    assert leaf not in motion.parents
    bodies = list(motion.bodies)
    bodies[leaf] = dataclasses.replace(bodies[leaf], length=None)
    text = bvh_text(dataclasses.replace(motion, bodies=tuple(bodies)))
    end = text.split("End Site")[1].split("OFFSET")[1].split("\n")[0]
    stub = float(np.linalg.norm([float(x) for x in end.split()]))
    size = np.ptp(motion.positions[0], axis=0).max()
    assert 0 < stub <= 0.1 * size


def test_export_motion_names_the_rate_that_gives_a_mites_stances_keyframes(
    mite: Scaled, capsys: pytest.CaptureFixture[str]
) -> None:
    out = mite.where / "mite.glb"
    argv = ["export-motion", str(mite.run_dir), "-o", str(out), "--generated", str(mite.generated)]
    pytest.importorskip("pygltflib", reason="needs pygltflib: pip install 'legdsl[export]'")
    capsys.readouterr()
    assert main(argv) == 0
    note = capsys.readouterr().err
    assert "note: leg main's stances" in note and "at 60 per second" in note
    rate = float(note.split("--fps ")[1].split()[0])
    stances = mite.trajectory.contact[:, 0] > 0.5
    assert 100 < rate < 8000  # the mite's stances last about 5 ms
    assert main([*argv, "--fps", str(rate)]) == 0  # at that rate: no note
    assert "note" not in capsys.readouterr().err
    assert stances.any()


def test_run_with_animate_tells_the_mites_stances_as_legdsl_animate_does(
    mite: Scaled, capsys: pytest.CaptureFixture[str]
) -> None:
    """`legdsl run --animate` wrote the same player as `legdsl animate` of its run without
    the note that its stances get too few keyframes."""
    out = mite.where / "animated"
    gen = ["--generated", str(mite.generated)]
    argv = ["run", str(mite.leg), "--controller", "hop", "--time", "0.05", "--out", str(out)]
    capsys.readouterr()
    assert main([*argv, "--animate", *gen]) == 0
    during = capsys.readouterr().err
    assert main(["animate", str(out), "-o", str(mite.where / "again.html"), *gen]) == 0
    after = capsys.readouterr().err
    note = [line for line in after.splitlines() if line.startswith("legdsl: note: leg main's")]
    assert len(note) == 1 and note[0] in during.splitlines(), (during, after)


def test_a_video_of_the_mite_in_slow_motion_gives_its_stances_frames(
    mite: Scaled, capsys: pytest.CaptureFixture[str]
) -> None:
    """A video plays in real time at 30 fps: the mite's 0.05 s run was a frame or two, its
    5 ms stances none, and no note said so. --slow-motion F renders F times the frames."""
    pytest.importorskip("PIL", reason="needs Pillow: pip install 'legdsl[export]'")
    gif = mite.where / "mite.gif"
    argv = ["animate", str(mite.run_dir), "--video", str(gif), "--size", "160x90",
            "--generated", str(mite.generated)]  # fmt: skip
    capsys.readouterr()
    assert main(argv) == 0
    said = "".join(capsys.readouterr())
    assert "frames of the video at 30 fps; --slow-motion " in said, said
    slow = float(said.split("--slow-motion ")[1].split()[0])
    assert 10 < slow < 100  # the mite's stances last about 5 ms: 4 frames need 20 or so
    assert main([*argv, "--slow-motion", str(slow)]) == 0
    said = "".join(capsys.readouterr())
    assert "note" not in said and f"{slow:g} times slower" in said, said
    frames = int(said.split(" frames at 30 fps")[0].rsplit("(", 1)[1].rsplit(", ", 1)[1])
    assert frames >= slow * 30 * 0.05 - 1  # F times the real-time frames of the run


def test_the_player_frames_the_mite_and_grids_its_ground(mite: Scaled) -> None:
    """A 5 cm floor on the creature's size framed the 0.7 mm mite as a speck on a 25 cm grid."""
    from legdsl.export.player import camera_hints, grid_step, player_data

    motion = mite.motion(MITE_FPS)
    size = np.ptp(motion.positions[0], axis=0).max()
    hints = camera_hints(motion)
    assert hints["size"] < 3 * size
    grid = player_data(motion)["ground"]["grid"]
    assert size / 20 <= grid <= size
    assert (grid_step(0.9), grid_step(3.0), grid_step(24.0), grid_step(0.066)) == (
        0.25,
        1.0,
        10.0,
        0.01,
    )


def test_the_players_footprints_keep_a_millionth_of_the_mites_size(mite: Scaled) -> None:
    """Footprints were rounded to 5 decimals (10 um, 1.4% of the 0.7 mm mite) whatever the size;
    a 53 um creature's were a tenth of it off the touchdown point."""
    from legdsl.export.player import player_data

    motion = mite.motion(MITE_FPS)
    data = player_data(motion)
    assert motion.footprints and len(data["footprints"]) == len(motion.footprints)
    for row, fp in zip(data["footprints"], motion.footprints, strict=True):
        assert abs(row[0] - fp.t) <= 1e-9
        assert np.abs(np.array(row[2:]) - fp.position).max() <= 1e-6 * data["size"]


def test_the_3d_videos_near_plane_does_not_cut_a_small_creature() -> None:
    from legdsl.export.video_views import _Camera

    camera = _Camera(0.0, 0.3, 0.002, 960, 540)  # a mite's camera, 2 mm away
    assert camera.near < 0.002
    assert _Camera(0.0, 0.3, 3.0, 960, 540).near == 0.05  # the shipped creatures' as it was


def test_mjcf_refuses_a_mite_mujoco_cannot_load_and_says_why(
    mite: Scaled, capsys: pytest.CaptureFixture[str]
) -> None:
    out = mite.where / "mite.xml"
    assert main(["export", str(mite.leg), "--format", "mjcf", "-o", str(out)]) == 2
    assert "MuJoCo loads none below 1e-14" in capsys.readouterr().err
    assert not out.exists()


def test_a_5cm_hopper_exports_to_mjcf_at_its_own_step_and_hops_in_mujoco(tmp_path: Path) -> None:
    """At MuJoCo's fixed 0.4 ms the small hopper's anchor pad needed more mass than its shank
    had (an error); the step is now the creature's (0.4 ms sqrt(0.05)) and the pads' rates
    follow it."""
    mujoco = pytest.importorskip("mujoco")
    leg = tmp_path / "hopper_small.leg"
    assert main(["scale", str(HOPPER), "--by", "0.05", "-o", str(leg)]) == 0
    out = tmp_path / "hopper_small.xml"
    assert main(["export", str(leg), "--format", "mjcf", "-o", str(out)]) == 0
    mj = mujoco.MjModel.from_xml_path(str(out))
    assert mj.opt.timestep == pytest.approx(0.0004 * math.sqrt(0.05), rel=1e-12)
    sphere = mj.geom("toe")
    assert mj.geom_size[sphere.id][0] <= 0.02 * 0.05  # a fiftieth of its 5 cm leg at most
    data = mujoco.MjData(mj)
    mujoco.mj_resetDataKeyframe(mj, data, 0)
    z0 = float(data.qpos[1])
    lowest = z0
    for _ in range(round(0.3 / mj.opt.timestep)):  # it drops onto its foot and bounces
        mujoco.mj_step(mj, data)
        lowest = min(lowest, float(data.qpos[1]))
    assert np.all(np.isfinite(data.qpos))
    assert 0.3 * z0 < lowest < z0  # landed on its spring, not through the floor


def test_the_mujoco_replays_camera_frames_a_5cm_hopper(tmp_path: Path) -> None:
    """Its view had half a metre of margin on any creature: a 5 cm hopper was a speck."""
    mujoco = pytest.importorskip("mujoco")
    from legdsl.export.mjreplay import _camera, replay_frames

    small = Scaled(HOPPER, 0.05, 0.1, tmp_path)
    mj, data, model, _, qpos = replay_frames(small.run_dir, 100.0, small.leg)
    camera = _camera(mujoco, model, mj, data, qpos[0])
    # its bodies' origins and its foot (the replay's bare link tree ends at the knee)
    extent = float(np.ptp(np.vstack([data.xpos[1:], data.site_xpos]), axis=0).max())
    assert 0.02 < extent < 0.08
    assert camera.distance < 10 * extent  # the shipped creatures' 4.5 (0.8 + 0.5) / 0.8


def test_the_usd_floor_of_a_mite_is_mite_sized(mite: Scaled) -> None:
    """The floor was the run's area plus a metre: a 2 m floor around a 4 mm run."""
    pytest.importorskip("pxr", reason="needs usd-core: pip install 'legdsl[export]'")
    from pxr import Usd, UsdGeom

    out = mite.where / "mite.usda"
    argv = ["export-motion", str(mite.run_dir), "-o", str(out), "--generated", str(mite.generated)]
    assert main(argv) == 0
    stage = Usd.Stage.Open(str(out))
    floor = next(p for p in stage.Traverse() if p.GetName() == "floor")
    points = np.array(UsdGeom.Mesh(floor).GetPointsAttr().Get())
    # the run covers 4 mm; its area plus 10 mite sizes is about a centimetre each way
    assert np.ptp(points[:, :2], axis=0).max() < 0.05


def test_a_1cm_hoppers_anchor_pads_are_within_mujocos_floor(tmp_path: Path) -> None:
    """Its bodies are above MuJoCo's inertia floor, but its pad (a solid sphere of 1e-7 kg
    and a 0.2 mm radius) was written with 5.8e-16 kg m^2 and MuJoCo refused the file; a pad's
    made-up inertia is raised to the floor."""
    mujoco = pytest.importorskip("mujoco")
    out = tmp_path / "tiny.xml"
    leg = ROOT / "tests" / "good" / "outside" / "tiny_hopper.leg"
    assert main(["export", str(leg), "--format", "mjcf", "-o", str(out)]) == 0
    mj = mujoco.MjModel.from_xml_path(str(out))
    assert mj.body_inertia[mj.body("toe_pad").id].min() >= 1e-14
