"""A recorded run made ready to draw: every body's pose per frame, and the overlays.

This is what the animation exporters share (the HTML player, the video and
the glTF export). ``load_motion(DIR)`` reads a run directory (``trajectory.npz``
and ``run.json``), checks the ``.leg`` file it names, loads the creature's
generated kinematics and resamples the run to a fixed frame rate:

* ``q`` is interpolated linearly between recorded samples (a 3D root's
  quaternion is renormalised), and the generated ``body_poses`` gives every
  body's world pose at each frame, exactly on the kinematic chain;
* forces, centre of mass and speeds are interpolated; the controller state
  is the one active at the frame's time;
* footprints are the contact points' positions at each touchdown event.

Quaternions are stored (x, y, z, w) as three.js and glTF want them, with the
sign chosen so that consecutive frames of a body are in the same hemisphere.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Protocol

import numpy as np

from legdsl.analysis.plot_ending import run_ending
from legdsl.export.frames import enough_frames, frame_times, interpolate, interpolate_q
from legdsl.export.stances import recorded_every_step, stance_note
from legdsl.ir.model import Body, Model, Terrain
from legdsl.lang.errors import UsageError
from legdsl.sim.trajectory import FLOAT32_MAX, Trajectory, load_run_info

DEFAULT_FPS = 60.0


class Kinematics(Protocol):
    """What the exporters need from a creature's generated dynamics module."""

    def body_poses(self, q: Any) -> Any: ...

    def contact_positions(self, q: Any) -> Any: ...


@dataclass(frozen=True)
class Footprint:
    t: float
    contact: int  # index into Motion.contact_names
    position: tuple[float, float, float]


@dataclass
class Motion:
    creature: str
    planar: bool
    bodies: tuple[Body, ...]
    parents: tuple[int, ...]  # index of each body's parent, -1 for the root
    terrain: tuple[Terrain, ...]
    times: np.ndarray  # (F,) s, from the run's first sample
    positions: np.ndarray  # (F, B, 3) world position of each body frame
    quaternions: np.ndarray  # (F, B, 4) world orientation, (x, y, z, w)
    contact_names: tuple[str, ...]
    contact_positions: np.ndarray  # (F, C, 3)
    forces: np.ndarray  # (F, C, 3) N, ground reaction on each contact
    com: np.ndarray  # (F, 3)
    speed: np.ndarray  # (F,) m/s: horizontal speed of the mass centre along the heading
    speed_command: np.ndarray  # (F,) m/s, NaN without a command
    state: np.ndarray  # (F,) int, -1 without a controller
    state_names: tuple[str, ...]
    footprints: tuple[Footprint, ...]
    weight: float  # N: total mass times gravity, to scale force arrows
    status: str = "ok"
    message: str = ""
    ended_at: float | None = None  # s: when a run that did not end ok ended (run.json)
    cause: str = ""  # and why, as run.json says it (its message where it has no cause)
    note: str = ""  # said when the frame rate misses the stances (stances.py)
    # each body's joint: its origin in the parent frame, and whether it has a slide
    joint_origins: np.ndarray | None = None  # (B, 3)
    joint_slides: tuple[bool, ...] = ()
    # each contact's body (index into bodies) and its point in that body's frame, and per
    # frame whether it touches the ground (F, C): the animation files carry them as locators
    contact_bodies: tuple[int, ...] = ()
    contact_points: np.ndarray | None = None  # (C, 3)
    touching: np.ndarray | None = None  # (F, C) bool
    # the paths the run followed, each as points (N, 3) on the ground (closed ones end at the start)
    paths: tuple[np.ndarray, ...] = ()
    path_names: tuple[str, ...] = ()
    # for each path, per frame: the nearest path point to the mass centre (F, 3) and the
    # signed lateral error (F,), positive when the mass centre is left of the path
    path_nearest: tuple[np.ndarray, ...] = ()
    path_lateral: tuple[np.ndarray, ...] = ()
    # for each path, the spans (from, to) s of ``times`` a controller followed it in (run.json's
    # ``followed``: a run that changed controllers), None when the whole run followed it
    path_spans: tuple[tuple[tuple[float, float], ...] | None, ...] = ()
    last_sample: float | None = None  # s: the run's end, which the last frame may fall short of

    @property
    def duration(self) -> float:
        return float(self.times[-1]) if len(self.times) else 0.0

    @property
    def frames(self) -> int:
        return int(self.times.shape[0])

    def frame_at(self, t: float) -> int:
        """The last frame at or before ``t``."""
        return int(np.clip(np.searchsorted(self.times, t, side="right") - 1, 0, self.frames - 1))

    def at(self, t: float) -> Snapshot:
        """Everything drawn at time ``t``, interpolated between frames as the player does."""
        f = self.frame_at(t)
        g = min(f + 1, self.frames - 1)
        span = self.times[g] - self.times[f]
        a = float(np.clip((t - self.times[f]) / span, 0.0, 1.0)) if span > 0 else 0.0

        def mix(x: np.ndarray) -> np.ndarray:
            return np.asarray((1 - a) * x[f] + a * x[g])

        quats = mix(self.quaternions)  # normalised linear interpolation (frames are close)
        quats /= np.linalg.norm(quats, axis=1, keepdims=True)
        return Snapshot(
            t=t,
            frame=f,
            positions=mix(self.positions),
            rotations=np.array([quaternion_to_matrix(qb) for qb in quats]),
            contact_positions=mix(self.contact_positions),
            forces=mix(self.forces),
            com=mix(self.com),
            speed=float(self.speed[f]),
            speed_command=float(self.speed_command[f]),
            state=self.state_names[self.state[f]]
            if 0 <= self.state[f] < len(self.state_names)
            else None,
        )


@dataclass(frozen=True)
class Snapshot:
    t: float
    frame: int  # the last frame at or before t
    positions: np.ndarray  # (B, 3)
    rotations: np.ndarray  # (B, 3, 3) body to world
    contact_positions: np.ndarray  # (C, 3)
    forces: np.ndarray  # (C, 3)
    com: np.ndarray  # (3,)
    speed: float
    speed_command: float  # NaN without a command
    state: str | None  # None without a controller


# ---------------------------------------------------------------- loading


@dataclass
class Run:
    directory: Path
    info: dict[str, Any]
    trajectory: Trajectory
    model: Model
    source: Path


def read_run(
    directory: Path, source: Path | None = None, give: str = "--source FILE", drawn: bool = False
) -> Run:
    """The trajectory, run.json and checked model of a run directory (``source``, else the
    file run.json names; ``give`` says how the caller gives another, and ``drawn`` that it
    only draws the motion, as ``recorded_model`` has them)."""
    from legdsl.analysis.recorded import recorded_model, same_run

    if not (directory / "trajectory.npz").is_file() or not (directory / "run.json").is_file():
        raise UsageError(
            f"{directory} is not a run directory (it needs trajectory.npz and run.json); "
            "make one with: legdsl run FILE.leg --out DIR"
        )
    info = load_run_info(directory)  # not JSON, not an object...: a UsageError
    source, model = recorded_model(directory, info, source, give, drawn)
    trajectory = Trajectory.load(directory)
    if len(trajectory) == 0:
        raise UsageError(f"{directory}: the run recorded no samples")
    same_run(directory, info, trajectory, model, source, give)
    return Run(directory, info, trajectory, model, source)


def drawable(run: Run) -> Run:
    """``run``, unless it was made with ``--scale L``: it holds the scaled creature's motion but
    names the unscaled file, whose bodies would be drawn moving L times too far (``legdsl run
    --scale --animate`` is refused for this)."""
    scale = run.info.get("scale")
    if scale is not None:
        raise UsageError(
            f"{run.directory} was run with --scale {scale:g}: drawn, its creature would be "
            f"{run.source}'s unscaled bodies; write the scaled creature with 'legdsl scale "
            f"{run.source} --by {scale:g} -o OUT.leg', run OUT.leg and draw that run"
        )
    return run


def load_motion(
    directory: Path,
    fps: float = DEFAULT_FPS,
    generated: Path = Path("generated"),
    source: Path | None = None,
    kinematics: Kinematics | None = None,
    video: tuple[float, float, float] | None = None,
) -> Motion:
    """Read a run directory and resample it for drawing (see the module docstring); ``video``
    is (frames per second, slow motion, the most frames per second of its format) when it is
    drawn for a video (its note then says so)."""
    run = drawable(read_run(directory, source, drawn=True))
    t = run.trajectory.t  # read_run refuses a run of no samples
    if video is None:  # a video's own rate is checked, not the denser one its frames are read at
        enough_frames(float(t[-1] - t[0]), fps)
    else:
        enough_frames(float(t[-1] - t[0]), video[0], usual=30.0, slow=video[1], top=video[2])
    if kinematics is None:
        from legdsl.pipeline.generated import load_dynamics

        kinematics = load_dynamics(run.model, run.source, generated)
    motion = motion_from(
        run.model,
        run.trajectory,
        kinematics,
        events=run.info.get("events"),
        fps=fps,
        status=str(run.info.get("status", "ok")),
        message=str(run.info.get("message", "") or ""),
        every_step=recorded_every_step(run.info.get("steps"), run.info.get("samples")),
    )
    ending = run_ending(run.info)  # a run told diverged after it ran on: at diverged_at
    ended = ending.at if ending is not None else run.info.get("ended_at", run.info.get("sim_time"))
    motion.ended_at = float(ended) if isinstance(ended, int | float) else None
    motion.cause = str(run.info.get("cause") or motion.message)
    if video is not None:  # a video's frames are its own, not the rate they are read at
        motion.note = stance_note(run.model, run.trajectory, *video[:2])
    specs = run.info.get("paths") or []
    if specs:
        from legdsl.ir.paths import PathSpec
        from legdsl.sim.path_tracking import PathTracker

        followed = [PathSpec.from_json(p) for p in specs]
        motion.paths = tuple(path_points(p, motion.terrain) for p in followed)
        motion.path_names = tuple(p.name for p in followed)
        t0 = float(run.trajectory.t[0])
        motion.path_spans = tuple(
            tuple((float(a) - t0, float(b) - t0) for a, b in p["followed"]) if p.get("followed")
            else None for p in specs
        )  # fmt: skip
        nearest, lateral = [], []
        for spec in followed:  # tracked frame by frame, as the run's tracker went along it
            tracker = PathTracker(spec)
            hits = [tracker.update(float(x), float(y)) for x, y in motion.com[:, :2]]
            nearest.append(
                np.array([(h["x"], h["y"], terrain_height(motion.terrain, h["x"], h["y"]))
                          for h in hits])
            )  # fmt: skip
            lateral.append(np.array([h["lateral"] for h in hits]))
        motion.path_nearest, motion.path_lateral = tuple(nearest), tuple(lateral)
    return motion


def path_points(spec: Any, terrain: tuple[Terrain, ...], step: float = 0.05) -> np.ndarray:
    """A path (a ``PathSpec``) as points on the ground every ``step`` metres or so, (N, 3)."""
    from legdsl.sim.path_tracking import PathGeometry

    geometry = PathGeometry(spec)
    if spec.shape == "circle":
        n = max(16, min(5000, int(math.ceil(geometry.length / step)) + 1))
        s = np.linspace(0.0, geometry.length, n)
        xy = np.array([geometry.at(float(v))[:2] for v in s])
    else:  # the vertices themselves: corners stay sharp
        xy = np.array(spec.points, dtype=float)
    if geometry.closed and np.hypot(*(xy[-1] - xy[0])) > 1e-9:
        xy = np.vstack([xy, xy[:1]])
    z = np.array([terrain_height(terrain, float(x), float(y)) for x, y in xy])
    return np.column_stack([xy, z])


# ---------------------------------------------------------------- poses


def matrix_to_quaternion(m: np.ndarray) -> np.ndarray:
    """A rotation matrix (3, 3) as a unit quaternion (x, y, z, w)."""
    trace = m[0, 0] + m[1, 1] + m[2, 2]
    if trace > 0:
        s = 2.0 * math.sqrt(trace + 1.0)
        q = ((m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s, s / 4)
    elif m[0, 0] > m[1, 1] and m[0, 0] > m[2, 2]:
        s = 2.0 * math.sqrt(1.0 + m[0, 0] - m[1, 1] - m[2, 2])
        q = (s / 4, (m[0, 1] + m[1, 0]) / s, (m[0, 2] + m[2, 0]) / s, (m[2, 1] - m[1, 2]) / s)
    elif m[1, 1] > m[2, 2]:
        s = 2.0 * math.sqrt(1.0 + m[1, 1] - m[0, 0] - m[2, 2])
        q = ((m[0, 1] + m[1, 0]) / s, s / 4, (m[1, 2] + m[2, 1]) / s, (m[0, 2] - m[2, 0]) / s)
    else:
        s = 2.0 * math.sqrt(1.0 + m[2, 2] - m[0, 0] - m[1, 1])
        q = ((m[0, 2] + m[2, 0]) / s, (m[1, 2] + m[2, 1]) / s, s / 4, (m[1, 0] - m[0, 1]) / s)
    out = np.array(q)
    return out / np.linalg.norm(out)


def quaternion_to_matrix(q: np.ndarray) -> np.ndarray:
    """A unit quaternion (x, y, z, w) as a rotation matrix (3, 3)."""
    x, y, z, w = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def continuous(quaternions: np.ndarray) -> np.ndarray:
    """Flip signs along axis 0 so that consecutive quaternions have a non-negative dot product."""
    out = quaternions.copy()
    for k in range(1, len(out)):
        flip = np.sum(out[k] * out[k - 1], axis=-1) < 0
        out[k][flip] *= -1
    return out


def _within_float32(tr: Trajectory, status: str) -> None:
    """Positions an animation's 32-bit floats hold: a divergence's last sample can be past them
    (5 steps between its checks flung a stiff rig to 1e40 m), which would be written as inf."""
    for name in ("q", "com", "root_pos"):
        a = getattr(tr, name)
        if a.size and np.max(np.abs(a)) >= FLOAT32_MAX:  # a welded creature has no q
            at = float(tr.t[int(np.argmax(np.max(np.abs(a.reshape(len(a), -1)), axis=1)))])
            raise UsageError(
                f"the run's {name} reaches {np.max(np.abs(a)):.3g} at t = {at:.4f} s (it "
                f"{status}), past what an animation's 32-bit numbers hold: run it again with a "
                f"--time before {at:g} s"
            )


def motion_from(
    model: Model,
    trajectory: Trajectory,
    kinematics: Kinematics,
    events: list[dict[str, Any]] | None = None,
    fps: float = DEFAULT_FPS,
    status: str = "ok",
    message: str = "",
    flag: str = "--fps",
    every_step: bool = False,
) -> Motion:
    """The run's frames at ``fps`` (``flag`` names that rate in a refusal: one frame of a
    run that moves is refused here, for every player, as ``legdsl animate`` refuses it);
    ``every_step``: the run recorded every step (its note's advice then differs)."""
    tr = trajectory
    _within_float32(tr, status)
    enough_frames(float(tr.t[-1] - tr.t[0]), fps, flag=flag)
    at = frame_times(tr.t, fps)
    q = interpolate_q(model, tr.t, tr.q, at)
    nb, nc = len(model.bodies), len(model.contacts)
    positions = np.zeros((len(at), nb, 3))
    quats = np.zeros((len(at), nb, 4))
    contacts = np.zeros((len(at), nc, 3))
    for f, qf in enumerate(q):
        qf_list = [float(x) for x in qf]
        for b, (pos, rot) in enumerate(kinematics.body_poses(qf_list)):
            positions[f, b] = pos
            quats[f, b] = matrix_to_quaternion(np.asarray(rot, dtype=float).reshape(3, 3))
        if nc:
            contacts[f] = np.asarray(kinematics.contact_positions(qf_list), dtype=float)

    com_vel = interpolate(tr.t, tr.com_vel, at)
    yaw = interpolate(tr.t, np.unwrap(tr.root_rpy[:, 2]), at)
    speed = com_vel[:, 0] * np.cos(yaw) + com_vel[:, 1] * np.sin(yaw)
    index = np.clip(np.searchsorted(tr.t, at + 1e-12, side="right") - 1, 0, len(tr) - 1)
    names = [b.name for b in model.bodies]
    joints = {j.child: j for j in model.joints}
    return Motion(
        last_sample=float(tr.t[-1]),
        creature=model.name,
        planar=model.planar,
        bodies=model.bodies,
        parents=tuple(-1 if b.parent is None else names.index(b.parent) for b in model.bodies),
        terrain=model.ground.terrain if model.ground else (),
        times=at - tr.t[0],
        positions=positions,
        quaternions=continuous(quats),
        contact_names=tuple(c.name for c in model.contacts),
        contact_positions=contacts,
        forces=interpolate(tr.t, recorded_forces(tr), at),
        com=interpolate(tr.t, tr.com, at),
        speed=speed,
        speed_command=tr.speed_command[index].astype(float),
        state=tr.state[index].astype(int),
        state_names=tuple(tr.state_names),
        footprints=footprints(model, tr, kinematics, events),
        weight=model.total_mass * math.sqrt(sum(g * g for g in model.gravity)),
        status=status,
        message=message,
        joint_origins=np.array([joints[b.name].origin for b in model.bodies], dtype=float),
        joint_slides=tuple(
            any(d.motion == "slide" for d in joints[b.name].dofs) for b in model.bodies
        ),
        contact_bodies=tuple(names.index(c.body) for c in model.contacts),
        contact_points=np.array([c.point for c in model.contacts], dtype=float).reshape(-1, 3),
        touching=tr.contact[index].reshape(len(at), nc).astype(bool),
        note=stance_note(model, tr, fps, every_step=every_step),  # here, for every player
    )


def recorded_forces(tr: Trajectory) -> np.ndarray:
    """The ground forces, zero on every contact not touching the ground.

    The runtime records a contact's force only while it touches, and while another contact
    still touches it leaves a lifted one's last force in place (a stale force on a foot in
    the air); the contact flags say which samples hold a real force.
    """
    if tr.contact.shape != tr.force.shape[:2]:
        return tr.force
    return np.asarray(tr.force * (tr.contact[..., None] > 0))


def footprints(
    model: Model,
    tr: Trajectory,
    kinematics: Kinematics,
    events: list[dict[str, Any]] | None,
) -> tuple[Footprint, ...]:
    """Where each contact touched down: from the run's events, or without any from the contact flags."""
    names = [c.name for c in model.contacts]
    touchdowns: list[tuple[float, int]] = []
    if events is not None:
        touchdowns = [
            (float(e["t"]), names.index(e["contact"]))
            for e in events
            if e.get("kind") == "touchdown" and e.get("contact") in names
        ]
    elif len(tr) and tr.contact.size:
        flags = tr.contact.astype(int)
        rising = np.argwhere(np.diff(flags, axis=0, prepend=0) > 0)
        touchdowns = [(float(tr.t[i]), int(c)) for i, c in rising]
    touchdowns.sort()
    if not touchdowns:
        return ()
    # all at once: one call per touchdown went over the whole recording each time (a 30 min
    # run's 9,566 touchdowns of 346,154 samples took 7 minutes)
    qs = interpolate_q(model, tr.t, tr.q, np.array([t for t, _ in touchdowns]))
    out = []
    for (t, c), q in zip(touchdowns, qs, strict=True):
        p = kinematics.contact_positions([float(x) for x in q])[c]
        out.append(Footprint(t - float(tr.t[0]), c, (float(p[0]), float(p[1]), float(p[2]))))
    return tuple(out)


def terrain_height(terrain: tuple[Terrain, ...], x: float, y: float = 0.0) -> float:
    """The ground's height under (x, y), as ``legdsl.sim.contact`` models it."""
    h = 0.0
    for t in terrain:
        if t.kind == "slope":
            return x * math.tan(t.get("angle"))
        if t.kind == "step" and x >= t.get("x"):
            h = max(h, t.get("height"))
        if t.kind == "box" and t.get("x0") <= x <= t.get("x1") and t.get("y0") <= y <= t.get("y1"):
            h = max(h, t.get("height"))
    return h


def slope_tangent(terrain: tuple[Terrain, ...]) -> float:
    """tan(angle) of the terrain's slope, 0 without one: the plane a camera follows."""
    slope = next((t for t in terrain if t.kind == "slope"), None)
    return math.tan(slope.get("angle")) if slope is not None else 0.0


def ground_area(motion: Motion, margin: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(x, y) corners of the ground to draw: every body and contact of the run, plus ``margin``
    (a metre, or ten times a creature smaller than 10 cm: a mite's 4 mm run had a 2 m floor)."""
    points = np.concatenate(
        [motion.positions.reshape(-1, 3), motion.contact_positions.reshape(-1, 3)]
    )
    if margin is None:
        first = np.concatenate([motion.positions[0], motion.contact_positions[0]])
        margin = min(1.0, 10.0 * float(np.ptp(first, axis=0).max())) if len(first) else 1.0
    return points[:, :2].min(axis=0) - margin, points[:, :2].max(axis=0) + margin


def frame_rate(motion: Motion) -> float:
    """Frames per second of ``motion`` (its frames are evenly spaced), to 12 digits: the frame
    times' rounding would otherwise give 60.00000000000001 for 60 (written into USD and glTF)."""
    if motion.frames < 2 or not motion.duration:
        return 1.0
    return float(f"{(motion.frames - 1) / motion.duration:.12g}")


def free_name(name: str, taken: set[str]) -> str:
    """``name``, or ``name_1``, ``name_2``... if ``taken`` (the links' names) has it: an export's
    own node or prim (the ground, a link's mesh) named as a link would be confused with it
    (in USD the same prim: the floor moved with a link called ``ground``)."""
    candidate, n = name, 0
    while candidate in taken:
        n += 1
        candidate = f"{name}_{n}"
    return candidate
