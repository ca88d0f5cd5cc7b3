"""Run options from a creature's ``simulation`` block, and the second method of dynamic scaling.

Raibert & Hodgins (1991), "Dynamic scaling": a creature L times as large can be simulated by
scaling its parameters (``legdsl scale``, ``legdsl.lang.scaling``) or by running the unscaled
model with its inputs scaled by 1/L and scaling the outputs by L -- "both give identical
results". ``legdsl run FILE --scale L`` is the second: every input given for the large
creature (the duration, integration step, control interval and record rate, ``--set``
values and their times, ``--path`` shapes, ``--drop`` and ``--fall-height``) is divided by its
Table 1 factor, the unscaled model runs, and every recorded output (times, coordinates,
velocities, forces, energies, events) is multiplied by its factor before it is written.
"""

from __future__ import annotations

import argparse
import dataclasses
import decimal
import math
import re
from typing import Any, Literal

import numpy as np

from legdsl.ir.model import Model, setting_kind
from legdsl.ir.paths import DEFAULT_LOOKAHEAD, PathSpec
from legdsl.ir.scene import Scene
from legdsl.lang.errors import UsageError
from legdsl.lang.scaling import factor
from legdsl.lang.units import KINDS, Dim, apart
from legdsl.pipeline.settings import Settings, plain_number
from legdsl.sim.machine import InputChange
from legdsl.sim.run_loop import RunOptions, RunResult, default_control_dt
from legdsl.sim.simulate import Simulation
from legdsl.sim.trajectory import Trajectory

_LENGTH: Dim = KINDS["length"][0]
_TIME: Dim = KINDS["time"][0]
_SPEED: Dim = KINDS["velocity"][0]
_ANGULAR_SPEED: Dim = KINDS["angular velocity"][0]
_FORCE: Dim = KINDS["force"][0]
_ENERGY: Dim = (1, 2, -2, 0)
_INERTIA: Dim = KINDS["moment of inertia"][0]


def run_options(model: Model, scale: float | None = None, **given: Any) -> RunOptions:
    """RunOptions with the creature's ``simulation`` defaults (else the runner's) where ``given``
    has None. With ``scale``, given options are for the creature scaled by it, and the defaults
    are scaled to it (times by L^(1/2)) as ``legdsl scale`` writes them."""
    check_scale(scale)
    sim, runner = model.simulation, RunOptions()
    tick = math.sqrt(scale) if scale is not None else 1.0
    for key, per in (("dt", tick), ("control_dt", tick), ("record_rate", 1 / tick)):
        if given.get(key) is None:
            own = getattr(sim, key)
            if own is None and key == "control_dt":  # the runner's, never below the step
                own = default_control_dt(given["dt"] / per)
            given[key] = (own if own is not None else getattr(runner, key)) * per
    return RunOptions(**given)


def check_scaled_defaults(options: RunOptions, scale: float | None, given: dict[str, Any]) -> None:
    """A step or recording rate not given, scaled from the creature's by ``--scale``, that the
    run cannot use: told as what the scale made of it (the user never wrote those values)."""
    if scale is None:
        return
    tick = math.sqrt(scale)
    dt, rate, duration = options.dt, options.record_rate, options.duration
    told, need, flags = [], 0.0, []
    if given.get("dt") is None and dt > duration:
        told.append(f"its step {dt / tick:g}s becomes {dt:.3g}s, longer than the run")
        need, flags = dt, ["--dt"]
    if given.get("record_rate") is None and rate > 0 and rate * duration < 1.0 - 1e-9:
        recorded = f"{rate:.3g}Hz, which records the start alone"
        told.append(f"its recording rate {rate * tick:g}Hz becomes {recorded}")
        need, flags = max(need, 1 / rate), [*flags, "--record-rate"]
    if told:
        raise UsageError(
            f"--scale {scale:g} stretches the creature's times by sqrt(L) = {tick:.4g}: in a "
            f"run of {duration:g}s {'; '.join(told)}; give a --time of {need:.3g}s or more, or "
            f"{' and '.join(flags)}"
        )


def scale_factor(text: str) -> float:
    """``--scale L``, ``--by L`` as argparse reads it: a plain number, the length ratio; a
    length (``2m``) is told what L is, and one past a double as written (it read as 0 or inf)."""
    value = plain_number(
        text,
        "the scale factor L is a plain number, the ratio of the scaled creature's lengths to "
        "this one's (2: twice as large)",
    )
    written = decimal.Decimal(text)  # plain_number read it: it is a number
    if written.is_finite() and written != 0 and value in (0.0, math.inf, -math.inf):
        past = ("small a number: it underflows a double (nearer 0 than a double holds, "
                "5e-324)" if value == 0 else "large a number: it overflows a double")  # fmt: skip
        raise argparse.ArgumentTypeError(
            f"{text!r} is too {past} and would read as {value:g}; the scale factor is a "
            "positive, finite number not so far from 1 (L^5, an inertia's factor, and 1 / L^5 "
            "are doubles too)"
        )
    return value


def check_scale(scale: float | None) -> None:
    if scale is None:
        return
    if not 0 < scale < math.inf:
        raise UsageError(f"--scale {scale:g}: the scale factor is a positive, finite number")
    # Table 1's factors reach L^5 (an inertia): it and 1 / L^5 must both be doubles
    if not all(0 < factor(_INERTIA, f) < math.inf for f in (scale, 1 / scale)):
        raise UsageError(
            f"--scale {scale:g}: too far from 1 (L^5, the factor of an inertia, or 1 / L^5 is "
            "past a double); scale by a factor nearer 1"
        )


def scale_options(options: RunOptions, scale: float) -> RunOptions:
    """Options given for the creature scaled by ``scale``, for the unscaled model (times / sqrt L)."""
    check_scale(scale)
    tick = math.sqrt(scale)
    return dataclasses.replace(
        options,
        duration=options.duration / tick,
        dt=options.dt / tick,
        control_dt=options.control_dt / tick,
        record_rate=options.record_rate * tick,
        fall_height=_fall_height(options.fall_height, scale),
        drop=None if options.drop is None else options.drop / scale,
    )


def _fall_height(
    height: float | Literal["off"] | None, scale: float
) -> float | Literal["off"] | None:
    """A ``--fall-height`` for the unscaled model: divided by ``scale``; None and ``off`` as
    they are."""
    return height if height is None or isinstance(height, str) else height / scale


def scale_checks(sim: Simulation, scale: float) -> None:
    """Hold the unscaled model's run to the fall and divergence rules of the scaled file's: it
    looks every ``check_interval`` of its own time (at most), sqrt(L) times the model's, and
    calls a speed a divergence past the limit of a creature of its size; a divergence's cause
    is told in that creature's numbers (``legdsl.sim.stability``), as the scaled file's run
    tells it."""
    sim.check_interval = sim.check_interval / math.sqrt(scale)
    sim.size_scale, sim.v_factors = scale, tuple(float(f) for f in v_factors(sim.model, scale))
    sim.q_factors = tuple(float(f) for f in q_factors(sim.model, scale))
    check = sim._check

    def check_exact(start_height: float) -> str | None:
        """The check, a fall's heights kept unrounded (``scale_message`` rounds them scaled:
        rounded first, 0.1 and 0.101 m, they scaled by 2 to 0.2 and 0.202 m, where the
        scaled file's run tells 0.2005 and 0.2011 m)."""
        said = check(start_height)
        if said == "fell" and _FELL_TO.search(sim.message):
            pos, _ = sim._root_pose()
            given = sim.options.fall_height
            limit = given if isinstance(given, float | int) else 0.3 * start_height  # not off
            above = pos[2] - sim._ground_under(pos)
            sim.message = _FELL_TO.sub(
                _fell_to(repr(float(above)), repr(float(limit))), sim.message
            )
        return said

    sim._check = check_exact  # type: ignore[method-assign]


def scale_settings(
    settings: Settings, model: Model, controller: str | None, scale: float
) -> Settings:
    """``--set`` values (in SI) given for the scaled creature, for the unscaled model."""
    ir = model.controller(controller) if controller is not None else None
    dims = {c.name: c.dim for c in (*ir.inputs, *ir.params)} if ir is not None else {}
    rotary = {a.name: a.rotary for a in model.actuators}

    def down(name: str, value: float) -> float:
        if "." in name:
            actuator, _, key = name.partition(".")
            dim = KINDS[setting_kind(key, rotary[actuator])][0]
        else:
            dim = dims[name]
        return value / factor(dim, scale)

    tick = math.sqrt(scale)
    return Settings(
        actuators={k: down(k, v) for k, v in settings.actuators.items()},
        inputs={k: down(k, v) for k, v in settings.inputs.items()},
        params={k: down(k, v) for k, v in settings.params.items()},
        schedule=[
            InputChange(c.t / tick, c.name, down(c.name, c.value)) for c in settings.schedule
        ],
    )


def scale_scene(scene: Scene, model: Model, scale: float) -> Scene:
    """The file's scene as the scaled file's (``legdsl scale``): its values times their Table 1
    factors, its times times sqrt L, so that a ``--scale`` run of it, whose inputs are the
    scaled creature's, is the run of that file's scene."""
    tick = math.sqrt(scale)
    dims = {
        c.name: c.dim
        for name in dict.fromkeys([scene.controller, *(b.controller for b in scene.bands)])
        for c in model.controller(name).inputs
    }
    by = factor(dims[scene.band_input], scale) if scene.bands else 1.0

    def up(value: float | None, f: float) -> float | None:
        return None if value is None else value * f

    return dataclasses.replace(
        scene,
        values=tuple(
            dataclasses.replace(v, value=v.value * factor(v.dim, scale), at=up(v.at, tick))
            for v in scene.values
        ),
        switches=tuple(dataclasses.replace(w, t=w.t * tick) for w in scene.switches),
        duration=up(scene.duration, tick),
        bands=tuple(
            dataclasses.replace(b, low=up(b.low, by), high=up(b.high, by)) for b in scene.bands
        ),
    )


def scale_path(spec: PathSpec, scale: float) -> PathSpec:
    """A path given for the scaled creature, for the unscaled model (lengths / L). A lookahead
    not written is the scaled creature's default, L times ``DEFAULT_LOOKAHEAD`` (as the paths
    ``legdsl scale`` writes): for the unscaled model the default itself, exactly, so that the
    run is the original's on the original's path, scaled. The result's lookahead is written
    (``scale_path(p, 1 / L)`` gives the path as given, its lookahead L m)."""

    def point(p: tuple[float, float]) -> tuple[float, float]:
        return (p[0] / scale, p[1] / scale)

    return dataclasses.replace(
        spec,
        points=tuple(point(p) for p in spec.points),
        center=point(spec.center),
        radius=spec.radius / scale,
        lookahead=DEFAULT_LOOKAHEAD if spec.lookahead_default else spec.lookahead / scale,
        lookahead_default=False,
    )


def path_as_given(spec: PathSpec, scale: float) -> PathSpec:
    """A path given for the creature scaled by ``scale``, a lookahead not written being that
    creature's default (L m), as its notes speak of it (``scale_path`` gives the model's)."""
    if not spec.lookahead_default:
        return spec
    return dataclasses.replace(spec, lookahead=DEFAULT_LOOKAHEAD * scale, lookahead_default=False)


def _q_dims(model: Model, rate: bool) -> list[Dim | None]:
    """The dimension of each entry of q (or of v): lengths, angles (1), quaternion parts (1)."""
    if rate:
        return [_ANGULAR_SPEED if turn else _SPEED for turn in model.v_angular]
    dims: list[Dim | None] = []
    for joint in model.joints:
        if joint.is_free_3d:
            dims += [_LENGTH] * 3 + [None] * 4
        else:
            dims += [None if dof.motion == "hinge" else _LENGTH for dof in joint.dofs]
    return dims


def q_factors(model: Model, scale: float) -> np.ndarray:
    """The Table 1 factor of each entry of q."""
    return np.array([factor(d, scale) for d in _q_dims(model, False)])


def v_factors(model: Model, scale: float) -> np.ndarray:
    """The Table 1 factor of each entry of v."""
    return np.array([factor(d, scale) for d in _q_dims(model, True)])


def scale_trajectory(traj: Trajectory, model: Model, scale: float) -> Trajectory:
    """The outputs of the unscaled model as the scaled creature's (each by its Table 1 factor)."""

    def by(dim: Dim | None) -> float:
        return factor(dim, scale)

    q_f = q_factors(model, scale)
    v_f = np.array([by(d) for d in _q_dims(model, True)])
    energy = by(_ENERGY)
    return dataclasses.replace(
        traj,
        t=traj.t * by(_TIME),
        q=traj.q * q_f,
        v=traj.v * v_f,
        force=traj.force * by(_FORCE),
        com=traj.com * scale,
        com_vel=traj.com_vel * by(_SPEED),
        root_pos=traj.root_pos * scale,
        leg_length=traj.leg_length * scale,
        leg_spring_energy=traj.leg_spring_energy * energy,
        kinetic=traj.kinetic * energy,
        potential=traj.potential * energy,
        elastic=traj.elastic * energy,
        work_positive=traj.work_positive * energy,
        work_negative=traj.work_negative * energy,
        speed_command=traj.speed_command * by(_SPEED),
        total_mass=traj.total_mass * scale**3,
    )


def scale_events(events: list[dict[str, Any]], scale: float) -> list[dict[str, Any]]:
    tick = math.sqrt(scale)
    return [{**e, "t": round(e["t"] * tick, 9)} for e in events]


# the messages of ``Simulation``: a fall's heights, an interruption's times, a divergence's
_FELL_TO = re.compile(r"the root fell to (\S+) m above the ground \(the limit is (\S+) m\)")
_INTERRUPTED = re.compile(r"at t = (\S+) s of (\S+) s;")
_DIVERGED = re.compile(r"^the simulation diverged at t = (\S+) s: ")
_AFTER = re.compile(r"\. After it the run (fell|ran on to its end) at t = (\S+) s")


def _fell_to(above: str, limit: str) -> str:
    return f"the root fell to {above} m above the ground (the limit is {limit} m)"


def scale_message(message: str, scale: float) -> str:
    """The run's message with its heights and times as the scaled creature's (angles stay); a
    divergence's cause is told in them already (``scale_checks``)."""
    tick = math.sqrt(scale)
    message = _FELL_TO.sub(
        lambda m: _fell_to(*apart(float(m[1]) * scale, float(m[2]) * scale)), message
    )
    message = _INTERRUPTED.sub(
        lambda m: f"at t = {float(m[1]) * tick:.4f} s of {float(m[2]) * tick:g} s;", message
    )
    message = _AFTER.sub(
        lambda m: f". After it the run {m[1]} at t = {float(m[2]) * tick:.4f} s", message
    )
    return _DIVERGED.sub(
        lambda m: f"the simulation diverged at t = {float(m[1]) * tick:.4f} s: ", message
    )


def scale_result(result: RunResult, model: Model, scale: float) -> RunResult:
    """A run of the unscaled model, its outputs scaled as the creature scaled by ``scale``."""
    tick = math.sqrt(scale)
    return dataclasses.replace(
        result,
        trajectory=scale_trajectory(result.trajectory, model, scale),
        events=scale_events(result.events, scale),
        sim_time=result.sim_time * tick,
        message=scale_message(result.message, scale),
        cause=scale_message(result.cause, scale),
        stop_time={dof: round(t * tick, 9) for dof, t in result.stop_time.items()},
        diverged_at=None if result.diverged_at is None else result.diverged_at * tick,
    )
