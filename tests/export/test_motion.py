"""Resampling a run for drawing, on a two-link planar creature whose poses are worked out by hand."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest
from standin import ModelKinematics

from legdsl.check.source import check_model
from legdsl.export.motion import (
    frame_times,
    interpolate_q,
    load_motion,
    matrix_to_quaternion,
    motion_from,
    quaternion_to_matrix,
    terrain_height,
)
from legdsl.lang.errors import UsageError
from legdsl.sim.trajectory import empty

TWO_LINK = """
creature twolink {
  planar
  gravity 9.81 m/s^2
  body trunk free {
    mass 2 kg  inertia 0.1 kg*m^2
    shape box(0.4 m, 0.1 m)
    initial x = 0 m, z = 0.6 m, pitch = 0 deg
    color "#2060c0"
  }
  body leg on trunk via revolute hip at (0.1 m, 0 m) {
    length 0.5 m  com 0.25 m  mass 0.5 kg  inertia 0.01 kg*m^2
    shape cylinder(0.02 m)
    color "#c04020"
  }
  contact toe on leg at tip
  ground {
    normal spring(k = 1e4 N/m, b = 100 N*s/m)
    tangent spring(k = 1e4 N/m, b = 100 N*s/m)
    terrain step(x = 1 m, height = 0.1 m)
  }
}
"""


def ry(a: float) -> np.ndarray:
    return np.array([[math.cos(a), 0, math.sin(a)], [0, 1, 0], [-math.sin(a), 0, math.cos(a)]])


class HandKinematics:
    """The two-link creature's kinematics, written out: q = (x, z, pitch, hip)."""

    def body_poses(self, q: list[float]):
        x, z, pitch, hip = q
        hip_point = (x + 0.1 * math.cos(pitch), 0.0, z - 0.1 * math.sin(pitch))
        return [
            ((x, 0.0, z), tuple(ry(pitch).reshape(9))),
            (hip_point, tuple(ry(pitch + hip).reshape(9))),
        ]

    def contact_positions(self, q: list[float]):
        x, z, pitch, hip = q
        (hx, _, hz), _ = self.body_poses(q)[1]
        a = pitch + hip
        return [(hx - 0.5 * math.sin(a), 0.0, hz - 0.5 * math.cos(a))]


@pytest.fixture
def two_link(tmp_path: Path):
    source = tmp_path / "twolink.leg"
    source.write_text(TWO_LINK)
    return check_model(source), source


def q_of(t: float) -> np.ndarray:
    """A motion linear in time, so that linear interpolation between samples is exact."""
    return np.array([0.8 * t, 0.6 - 0.5 * t, 0.3 * t, -0.4 + 2.0 * t])


def recorded(model, times: np.ndarray):
    tr = empty(
        len(times), 4, 4, 1, 0, q_names=model.q_names, v_names=model.v_names,
        contact_names=("toe",), state_names=("FLIGHT", "STANCE"), total_mass=model.total_mass,
    )  # fmt: skip
    tr.t[:] = times
    tr.q[:] = np.array([q_of(t) for t in times])
    tr.com[:] = tr.q[:, [0, 2, 1]] * np.array([1, 0, 1])
    tr.com_vel[:, 0] = 0.8
    tr.state[:] = np.where(times >= 0.09, 1, 0)
    tr.contact[:, 0] = times >= 0.09
    tr.speed_command[:] = np.where(times >= 0.12, 1.5, np.nan)
    tr.force[:, 0, 2] = np.where(times >= 0.09, 10 * times, 0.0)  # while it touches
    return tr


def test_the_stand_in_kinematics_agree_with_the_hand(two_link) -> None:
    model, _ = two_link
    hand, standin = HandKinematics(), ModelKinematics(model)
    for t in (0.0, 0.37, 1.1):
        q = [float(x) for x in q_of(t)]
        for (p1, r1), (p2, r2) in zip(hand.body_poses(q), standin.body_poses(q), strict=True):
            assert np.allclose(p1, p2) and np.allclose(r1, r2)
        assert np.allclose(hand.contact_positions(q), standin.contact_positions(q))


def test_motion_resamples_poses_on_the_chain(two_link) -> None:
    model, _ = two_link
    samples = np.arange(0.0, 0.301, 0.03)  # 33.3 Hz recorded
    events = [
        {"t": 0.09, "kind": "touchdown", "contact": "toe"},
        {"t": 0.2, "kind": "liftoff", "contact": "toe"},
    ]
    motion = motion_from(model, recorded(model, samples), HandKinematics(), events, fps=25.0)

    assert np.allclose(motion.times, np.arange(0.0, 0.3001, 0.04))
    hand = HandKinematics()
    for f, t in enumerate(motion.times):
        q = q_of(t)
        for b, (pos, rot) in enumerate(hand.body_poses(list(q))):
            assert np.allclose(motion.positions[f, b], pos, atol=1e-12)
            assert np.allclose(
                quaternion_to_matrix(motion.quaternions[f, b]), np.reshape(rot, (3, 3)), atol=1e-12
            )
        # A turn about y by a is the quaternion (0, sin a/2, 0, cos a/2), up to sign.
        a = q[2] + q[3]
        expected = np.array([0.0, math.sin(a / 2), 0.0, math.cos(a / 2)])
        assert abs(np.dot(motion.quaternions[f, 1], expected)) == pytest.approx(1.0)
        assert np.allclose(motion.contact_positions[f, 0], hand.contact_positions(list(q))[0])
    # Consecutive quaternions stay in one hemisphere (the player interpolates between them).
    assert np.all(np.sum(motion.quaternions[1:] * motion.quaternions[:-1], axis=2) > 0)

    (fp,) = motion.footprints  # liftoffs leave none
    assert fp.t == 0.09 and fp.contact == 0
    assert np.allclose(fp.position, hand.contact_positions(list(q_of(0.09)))[0])

    assert motion.state_names == ("FLIGHT", "STANCE")
    assert list(motion.state) == [0, 0, 0, 1, 1, 1, 1, 1]  # frames at 0, 0.04, 0.08, 0.12, ...
    assert np.isnan(motion.speed_command[:3]).all() and (motion.speed_command[3:] == 1.5).all()
    assert np.allclose(motion.speed, 0.8)
    assert np.allclose(motion.forces[3:, 0, 2], 10 * motion.times[3:])  # in stance
    assert np.allclose(motion.forces[:2, 0, 2], 0.0)  # before the touchdown at 0.09 s
    assert motion.weight == pytest.approx(2.5 * 9.81)
    assert motion.parents == (-1, 0)
    assert [t.kind for t in motion.terrain] == ["step"]


def test_snapshot_interpolates_between_frames(two_link) -> None:
    model, _ = two_link
    motion = motion_from(
        model, recorded(model, np.arange(0.0, 0.301, 0.03)), HandKinematics(), fps=25.0
    )
    snap = motion.at(0.05)  # between frames 0.04 and 0.08
    assert snap.frame == 1
    assert np.allclose(snap.positions[0], [0.8 * 0.05, 0.0, 0.6 - 0.5 * 0.05])
    assert np.allclose(snap.rotations[0], ry(0.3 * 0.05), atol=1e-4)
    assert snap.state == "FLIGHT" and math.isnan(snap.speed_command)


def test_frames_are_never_denser_than_the_samples() -> None:
    t = np.arange(0.0, 1.0001, 0.1)
    assert np.allclose(frame_times(t, 60.0), t)
    assert np.allclose(frame_times(t, 5.0), np.arange(0.0, 1.0001, 0.2))
    assert np.allclose(frame_times(np.array([0.5]), 60.0), [0.5])


def test_quaternion_conversions_round_trip() -> None:
    rng = np.random.default_rng(7)
    for _ in range(200):
        q = rng.normal(size=4)
        q /= np.linalg.norm(q)
        m = quaternion_to_matrix(q)
        back = matrix_to_quaternion(m)
        assert abs(np.dot(q, back)) == pytest.approx(1.0)
    for m in (np.eye(3), ry(math.pi), np.diag([-1.0, -1.0, 1.0]), np.diag([1.0, -1.0, -1.0])):
        assert np.allclose(quaternion_to_matrix(matrix_to_quaternion(m)), m)


def test_a_3d_root_quaternion_is_interpolated_as_a_rotation() -> None:
    model = check_model(Path(__file__).resolve().parents[2] / "creatures" / "biped.leg")
    t = np.array([0.0, 1.0])
    q = np.tile(np.array(model.q0, dtype=float), (2, 1))
    half = math.radians(40) / 2
    q[0, 3:7] = (1.0, 0.0, 0.0, 0.0)
    q[1, 3:7] = (-math.cos(half), 0.0, 0.0, -math.sin(half))  # the same turn, other sign
    mid = interpolate_q(model, t, q, np.array([0.5]))[0]
    assert np.linalg.norm(mid[3:7]) == pytest.approx(1.0)
    angle = 2 * math.acos(min(1.0, abs(mid[3])))
    assert math.degrees(angle) == pytest.approx(20.0, abs=0.2)  # not through the long way round


def test_terrain_height_follows_the_contact_model(two_link) -> None:
    model, _ = two_link
    assert model.ground is not None
    assert terrain_height(model.ground.terrain, 0.99) == 0.0
    assert terrain_height(model.ground.terrain, 1.0) == pytest.approx(0.1)


def test_load_motion_reads_a_run_directory(two_link, tmp_path: Path) -> None:
    model, source = two_link
    run = tmp_path / "run"
    recorded(model, np.arange(0.0, 0.301, 0.03)).save(run)
    (run / "run.json").write_text(
        json.dumps({"source": str(source), "creature": "twolink", "status": "ok"})
    )
    motion = load_motion(run, fps=25.0, kinematics=HandKinematics())
    assert motion.creature == "twolink" and motion.frames == 8
    (fp,) = motion.footprints  # from the contact flags, as run.json lists no events
    assert fp.t == pytest.approx(0.09)

    (run / "run.json").write_text(
        json.dumps({"source": "elsewhere/twolink.leg", "creature": "twolink"})
    )
    with pytest.raises(UsageError, match="--source"):
        load_motion(run, kinematics=HandKinematics())
    assert load_motion(run, source=source, kinematics=HandKinematics()).frames > 1
    with pytest.raises(UsageError, match="not a run directory"):
        load_motion(tmp_path / "nothing", kinematics=HandKinematics())


def test_a_lifted_contacts_stale_force_is_not_drawn(tmp_path) -> None:
    """The kangaroo lands on toe and tail; after the tail lifts, its force is zero in the motion."""
    from anim_runs import creature_run, generated_dir

    from legdsl.export.motion import load_motion, read_run

    run_dir = creature_run("kangaroo", tmp_path / "run")
    tr = read_run(run_dir).trajectory
    lifted = tr.contact == 0
    motion = load_motion(run_dir, fps=200, generated=generated_dir())
    # at the recorded samples (200 per second, the default) the motion has the flags' forces
    at = np.searchsorted(tr.t - tr.t[0], motion.times - 1e-9)
    for f, k in enumerate(at[: len(motion.times)]):
        for c in range(tr.contact.shape[1]):
            if (
                lifted[k, c]
                and (k == 0 or lifted[k - 1, c])
                and (k + 1 >= len(tr.t) or lifted[k + 1, c])
            ):
                assert np.all(motion.forces[f, c] == 0.0)


def test_a_videos_frames_reach_the_end_of_the_run() -> None:
    """Frames 1/fps apart from the start to the end, the last kept when the recorded end lies a
    rounding error before it (as steps of dt add up); `animate --video` and `replay` both."""
    from legdsl.export.frames import every_frame

    assert len(every_frame(2.0, 30.0)) == 61
    end = sum([0.001] * 2000)  # 1.9999999999998905: 2000 steps of 1 ms
    assert end < 2.0 and every_frame(end, 30.0)[-1] == 2.0
    assert len(every_frame(1.99, 30.0)) == 60 and len(every_frame(0.0, 30.0)) == 1


@pytest.mark.parametrize("span", [0.0052, 0.198, 1 / 192.0, 0.5])
def test_the_frame_rate_a_one_frame_refusal_advises_gives_two_frames(span: float) -> None:
    # a 0.0052 s run was told "give at least 192 (two frames), e.g. --fps 60": both one frame
    from legdsl.export.frames import enough_frames, frame_times

    t = np.array([0.0, span])
    with pytest.raises(UsageError) as refused:
        enough_frames(span, 1.0)
    advice = re.search(r"two frames need --fps (\S+) or more", str(refused.value))
    assert advice, refused.value
    assert len(frame_times(t, float(advice.group(1)))) >= 2


@pytest.mark.parametrize(("span", "least"), [(0.29, "3.45"), (4.0, "0.25"), (0.0045, "223")])
def test_the_rate_a_one_frame_refusal_names_is_the_least_that_gives_two(
    span: float, least: str
) -> None:
    """It was rounded up to a whole number (4 for 3.45, 1 for 0.25), named as the least."""
    from legdsl.export.frames import enough_frames, frame_times

    with pytest.raises(UsageError, match=rf"two frames need --fps {least} or more"):
        enough_frames(span, 0.01)
    t = np.array([0.0, span])
    assert len(frame_times(t, float(least))) == 2
    assert len(frame_times(t, float(least) * 0.99)) == 1  # less than the least gives one


def test_a_video_too_short_for_two_frames_is_told_the_least_slow_motion() -> None:
    """A GIF of a 4.5 ms run was told "--fps 223 or more", a rate a GIF refuses."""
    from legdsl.export.frames import enough_frames, every_frame

    with pytest.raises(UsageError) as refused:
        enough_frames(0.0045, 30.0, usual=30.0, top=50.0)
    said = str(refused.value)
    advice = re.search(r"two frames need --slow-motion (\S+) or more \(", said)
    assert advice and "--fps 223" not in said, said
    assert len(every_frame(0.0045, 30.0 * float(advice.group(1)))) == 2
    with pytest.raises(UsageError, match=r"--slow-motion 7.41 or more, or --fps 223 or more"):
        enough_frames(0.0045, 30.0, usual=30.0, top=240.0)  # an .mp4 shows 223 a second


def test_footprints_interpolate_the_recording_once(monkeypatch: pytest.MonkeyPatch) -> None:
    """Each touchdown interpolated the whole recording again (a copy and a running product of
    every sample for a 3D root): a 30 min quadruped run's export took 7 minutes. One pass now,
    with the same footprints as one touchdown at a time."""
    from legdsl.export import motion

    model = check_model(Path(__file__).resolve().parents[2] / "creatures" / "biped.leg")
    n = 50
    tr = empty(n, model.nq, model.nv, len(model.contacts), len(model.legs))
    tr.t[:] = np.arange(n) * 0.01
    tr.q[:] = np.array(model.q0, dtype=float)
    tr.q[:, 0] = np.linspace(0.0, 1.0, n)
    events = [{"kind": "touchdown", "t": 0.005 + 0.04 * k, "contact": model.contacts[k % 2].name}
              for k in range(10)]  # fmt: skip
    kinematics = ModelKinematics(model)
    calls: list[int] = []
    real = motion.interpolate_q
    monkeypatch.setattr(motion, "interpolate_q", lambda *a: calls.append(1) or real(*a))
    prints = motion.footprints(model, tr, kinematics, events)
    assert len(calls) == 1 and len(prints) == 10
    for fp, e in zip(prints, events, strict=True):
        q = real(model, tr.t, tr.q, np.array([e["t"]]))[0]
        k = [c.name for c in model.contacts].index(e["contact"])
        assert fp.position == tuple(kinematics.contact_positions([float(x) for x in q])[k])
