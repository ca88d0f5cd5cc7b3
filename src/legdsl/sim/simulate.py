"""Integrate a compiled creature with its actuators and ground contact, and record it.

The generated dynamics module (``generated/NAME/dynamics.py``) supplies the
equations of motion and the kinematics; this module adds the forces of the
actuators and the ground, steps time (semi-implicit Euler at the paper's
0.0004 s by default, or RK4), calls the controller every control interval,
samples the motion at the recording rate, and watches for divergence and falls.
A run that stops early keeps everything it recorded up to then.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from types import ModuleType
from typing import Any, Protocol

from legdsl.ir.model import Model
from legdsl.lang.units import apart
from legdsl.sim.actuators import ActuatorBank
from legdsl.sim.causes import cause_at
from legdsl.sim.contact import ContactEvent, GroundContact
from legdsl.sim.energy_check import own_speed, told
from legdsl.sim.reachable import reachable_speed
from legdsl.sim.recorder import Divergence, TooFast, empty_trajectory, record_row
from legdsl.sim.run_loop import (
    CHECK_INTERVAL,
    INITIAL_ROWS,
    ControlFault,
    Interrupted,
    RunLoop,
    RunOptions,
    RunResult,
    grow_recording,
    run_samples,
    signal_of,
    steps_per_check,
    steps_per_control,
    steps_per_sample,
)
from legdsl.sim.sizes import too_fast
from legdsl.sim.trajectory import Trajectory

Vec = tuple[float, float, float]


class Controller(Protocol):
    """What the simulation needs from a controller (the state machine of a later stage)."""

    state_names: tuple[str, ...]

    @property
    def state_index(self) -> int: ...

    def __call__(self, sim: Simulation) -> None: ...

    def speed_command(self, t: float) -> float: ...


class Simulation:
    # the fall and divergence rules' longest wait; a --scale L run divides it by sqrt(L), so
    # that it looks when the scaled file's run would (legdsl.pipeline.scaled)
    check_interval = CHECK_INTERVAL

    def __init__(
        self,
        model: Model,
        dynamics: ModuleType,
        options: RunOptions,
        controller: Controller | None = None,
    ):
        if options.integrator not in ("euler", "rk4"):
            raise ValueError(f"unknown integrator {options.integrator!r}: use euler or rk4")
        self.model = model
        self.dyn = dynamics
        self.options = options
        self.controller = controller
        self.actuators = ActuatorBank(model)
        self.contact_names = tuple(c.name for c in model.contacts)
        self.ground = (
            GroundContact(model.ground, self.contact_names, model.planar) if model.ground else None
        )
        self.free3d = model.joints[0].is_free_3d
        self.t = 0.0
        self.steps_taken = 0  # time is steps * dt: no drift from adding dt up
        self._torsion = bool(
            self.ground is not None and self.ground.ground.torsion is not None and not model.planar
        )
        self._kinematics: tuple[Any, Any] | None = None
        self.q = [float(x) for x in model.q0]
        self.v = [float(x) for x in model.v0]
        # the divergence limit's size: a --scale L run sets L and each velocity's Table 1 factor
        self.size_scale, self.v_factors = 1.0, (1.0,) * len(self.v)
        # its messages advise --dt and --integrator (a sweep's or a tune's runs: the file's step)
        self.step_flags = True
        self.q_factors = (1.0,) * len(self.q)  # a --scale L run's Table 1 factors, for messages
        self.events: list[ContactEvent] = []
        self.contact_force: list[Vec] = [(0.0, 0.0, 0.0)] * len(self.contact_names)
        self._contact_body = [model.bodies.index(model.body(c.body)) for c in model.contacts]
        self._hips = [model.leg_hip(leg) for leg in model.legs]
        self._foot = [self.contact_names.index(leg.foot) for leg in model.legs]
        self._leg_springs = [self._springs_of(leg.joints) for leg in model.legs]
        self._stops = model.stops
        self.stop_time = {st.dof: 0.0 for st in self._stops}  # s spent past each stop
        if options.drop is not None:
            self._lift_to(options.drop)

    # ------------------------------------------------------------ setup
    def _springs_of(self, joints: tuple[str, ...]) -> tuple[str, ...]:
        dofs = {d.name for d in self.model.dofs if d.joint in joints}
        return tuple(a.name for a in self.model.actuators if a.kind == "spring" and a.dof in dofs)

    def contact_heights(self) -> list[tuple[str, float]]:
        """Each contact's height above the ground under it now (negative: under the ground)."""
        positions = self.dyn.contact_positions(self.q) if self.contact_names else []
        return [
            (name, p[2] - (self.ground.height(p[0], p[1]) if self.ground else 0.0))
            for name, p in zip(self.contact_names, positions, strict=True)
        ]

    def _lift_to(self, height: float) -> None:
        """Move the root vertically so the lowest contact is ``height`` above the ground."""
        if not self.contact_names:
            return
        lowest = min(
            p[2] - (self.ground.height(p[0], p[1]) if self.ground else 0.0)
            for p in self.dyn.contact_positions(self.q)
        )
        z_index = self.model.q_names.index("z")
        self.q[z_index] += height - lowest

    # ------------------------------------------------------------ forces
    def generalized_forces(
        self, q: list[float], v: list[float], record: bool = False
    ) -> list[float]:
        tau = [0.0] * self.dyn.NV
        self.actuators.apply(q, v, tau)
        for st in self._stops:  # one-sided spring-dampers at the joint limits
            x = q[st.q_index]
            if x < st.low:
                push = st.k * (st.low - x) - st.b * v[st.v_index]
                if push > 0:  # a stop pushes, never pulls
                    tau[st.v_index] += push
            elif x > st.high:
                push = st.k * (st.high - x) - st.b * v[st.v_index]
                if push < 0:
                    tau[st.v_index] += push
        ground = self.ground
        if ground is not None and any(ground.touching):
            pos, vel, yaws = self._contact_kinematics(q, v)
            jac = self.dyn.contact_jacobians(q)
            for i, touching in enumerate(ground.touching):
                if not touching:
                    if record:  # a lifted foot pushes no more, while another still touches
                        self.contact_force[i] = (0.0, 0.0, 0.0)
                    continue
                f = ground.force(i, pos[i], vel[i])
                if record:
                    self.contact_force[i] = f
                jx, jy, jz = jac[i]
                fx, fy, fz = f
                for k in range(len(tau)):
                    tau[k] += jx[k] * fx + jy[k] * fy + jz[k] * fz
            if yaws is not None:
                self._add_torsion(q, v, yaws, tau)
        elif record:
            self.contact_force = [(0.0, 0.0, 0.0)] * len(self.contact_names)
        return tau

    def _add_torsion(
        self, q: list[float], v: list[float], yaws: list[float], tau: list[float]
    ) -> None:
        assert self.ground is not None
        jac_w = self.dyn.contact_angular_jacobians(q)
        for i, touching in enumerate(self.ground.touching):
            if not touching:
                continue
            jn = self.ground.about_normal(jac_w[i])
            rate = sum(jn[k] * v[k] for k in range(len(v)))
            torque = self.ground.torsion(i, yaws[i], rate)
            for k in range(len(tau)):
                tau[k] += jn[k] * torque

    def _contact_kinematics(
        self, q: list[float], v: list[float]
    ) -> tuple[list[Vec], list[Vec], list[float] | None]:
        """Contact positions, velocities and body yaws (3D with torsion) at (q, v).

        Computed once per state: the values found at the end of a step serve the events
        there and the forces at the start of the next step (the same q and v). While every
        foot is in the air and above the ground, velocities and yaws serve no one (the
        forces, slip and touchdowns read them only for a foot at or under the ground), so
        they are zeros then, not computed (about a quarter of a 3D step's work).
        """
        key = (tuple(q), tuple(v))
        cached = self._kinematics
        if cached is not None and cached[0] == key:
            return cached[1]
        assert self.ground is not None
        positions = self.dyn.contact_positions(q)
        if not self.ground.near(positions):
            n = len(positions)
            found = (positions, [(0.0, 0.0, 0.0)] * n, [0.0] * n if self._torsion else None)
        else:
            yaws = None
            if self._torsion:
                poses = self.dyn.body_poses(q)
                yaws = [self.ground.yaw(poses[b][1]) for b in self._contact_body]
            found = (positions, self.dyn.contact_velocities(q, v), yaws)
        self._kinematics = (key, found)
        return found

    # ------------------------------------------------------------ integration
    def _qdot(self, q: list[float], v: list[float]) -> list[float]:
        if not self.free3d:
            return list(v)
        qw, qx, qy, qz = q[3:7]
        wx, wy, wz = v[3:6]
        quat_dot = [
            0.5 * (-qx * wx - qy * wy - qz * wz),
            0.5 * (qw * wx + qy * wz - qz * wy),
            0.5 * (qw * wy - qx * wz + qz * wx),
            0.5 * (qw * wz + qx * wy - qy * wx),
        ]
        return [v[0], v[1], v[2], *quat_dot, *v[6:]]

    def _advance_positions(self, q: list[float], v: list[float], dt: float) -> list[float]:
        """q after moving at velocity v for dt; the quaternion turns by the exact rotation."""
        if not self.free3d:
            return [qi + dt * vi for qi, vi in zip(q, v, strict=True)]
        out = [q[0] + dt * v[0], q[1] + dt * v[1], q[2] + dt * v[2]]
        wx, wy, wz = v[3:6]
        angle = math.sqrt(wx * wx + wy * wy + wz * wz) * dt
        if angle > 1e-12:
            s = math.sin(angle / 2) / (angle / dt)
            dw, dx, dy, dz = math.cos(angle / 2), wx * s, wy * s, wz * s
        else:
            dw, dx, dy, dz = 1.0, wx * dt / 2, wy * dt / 2, wz * dt / 2
        qw, qx, qy, qz = q[3:7]
        quat = [
            qw * dw - qx * dx - qy * dy - qz * dz,
            qw * dx + qx * dw + qy * dz - qz * dy,
            qw * dy - qx * dz + qy * dw + qz * dx,
            qw * dz + qx * dy - qy * dx + qz * dw,
        ]
        norm = math.sqrt(sum(c * c for c in quat))
        out += [c / norm for c in quat]
        out += [qi + dt * vi for qi, vi in zip(q[7:], v[6:], strict=True)]
        return out

    def _normalise(self, q: list[float]) -> None:
        if self.free3d:
            norm = math.sqrt(q[3] * q[3] + q[4] * q[4] + q[5] * q[5] + q[6] * q[6])
            for i in range(3, 7):
                q[i] /= norm

    def _accel(self, q: list[float], v: list[float], record: bool = False) -> list[float]:
        return self.dyn.forward_dynamics(q, v, self.generalized_forces(q, v, record))

    def step(self) -> None:
        """One integration step; the actuators' work over it is added up (``ActuatorBank``):
        for Euler, the force held over the step times the mean of the rates at its two ends
        (the rule by which the step's change of kinetic energy is the forces' work); for RK4,
        the stages' powers with RK4's weights."""
        dt = self.options.dt
        q, v = self.q, self.v
        bank = self.actuators
        if self.options.integrator == "euler":
            a = self._accel(q, v, record=True)
            v = [vi + dt * ai for vi, ai in zip(v, a, strict=True)]
            q = self._advance_positions(q, v, dt)
            power = bank.power([0.5 * (x + y) for x, y in zip(self.v, v, strict=True)])
        else:
            k1q, k1v = self._qdot(q, v), self._accel(q, v, record=True)
            p1 = bank.power(v)
            q2 = [x + 0.5 * dt * d for x, d in zip(q, k1q, strict=True)]
            v2 = [x + 0.5 * dt * d for x, d in zip(v, k1v, strict=True)]
            k2q, k2v = self._qdot(q2, v2), self._accel(q2, v2)
            p2 = bank.power(v2)
            q3 = [x + 0.5 * dt * d for x, d in zip(q, k2q, strict=True)]
            v3 = [x + 0.5 * dt * d for x, d in zip(v, k2v, strict=True)]
            k3q, k3v = self._qdot(q3, v3), self._accel(q3, v3)
            p3 = bank.power(v3)
            q4 = [x + dt * d for x, d in zip(q, k3q, strict=True)]
            v4 = [x + dt * d for x, d in zip(v, k3v, strict=True)]
            k4q, k4v = self._qdot(q4, v4), self._accel(q4, v4)
            p4 = bank.power(v4)
            power = [(a + 2 * b + 2 * c + d) / 6 for a, b, c, d in zip(p1, p2, p3, p4, strict=True)]
            q = [
                x + dt / 6 * (a + 2 * b + 2 * c + d)
                for x, a, b, c, d in zip(q, k1q, k2q, k3q, k4q, strict=True)
            ]
            v = [
                x + dt / 6 * (a + 2 * b + 2 * c + d)
                for x, a, b, c, d in zip(v, k1v, k2v, k3v, k4v, strict=True)
            ]
            self._normalise(q)
        self.q, self.v = q, v
        bank.add_work(power, dt)
        self.steps_taken += 1
        for st in self._stops:
            if not st.low <= q[st.q_index] <= st.high:
                self.stop_time[st.dof] += dt
        self.t = self.steps_taken * dt
        if self.ground is not None:
            self.events += self.ground.update(self.t, *self._contact_kinematics(q, v))

    # ------------------------------------------------------------ energy
    def energy(self) -> tuple[float, float, float]:
        """Kinetic, gravitational and elastic (actuator and ground springs) energy now."""
        elastic = self.actuators.elastic_energy(self.q)
        for st in self._stops:
            x = self.q[st.q_index]
            past = st.low - x if x < st.low else x - st.high if x > st.high else 0.0
            elastic += 0.5 * st.k * past * past
        if self.ground is not None:
            elastic += self.ground.elastic_energy(self.dyn.contact_positions(self.q))
        return (
            self.dyn.kinetic_energy(self.q, self.v),
            self.dyn.potential_energy(self.q),
            elastic,
        )

    # ------------------------------------------------------------ checks
    def _root_pose(self) -> tuple[Vec, tuple[float, ...]]:
        pos, rot = self.dyn.body_poses(self.q)[0]
        return pos, rot

    def standing_height(self, q: Sequence[float] | None = None) -> float:
        """How far the root stands above its lowest foot at the start, or in the pose ``q``
        (its own height if footless); 0, no fall limit, for a root welded to the world,
        which cannot fall."""
        if self.model.joints[0].kind == "fixed":
            return 0.0
        q = self.q if q is None else q
        root = self.dyn.body_poses(q)[0][0]
        if not self.contact_names:
            return root[2] - self._ground_under(root)
        return root[2] - min(p[2] for p in self.dyn.contact_positions(q))

    def _ground_under(self, point: Vec) -> float:
        return self.ground.height(point[0], point[1]) if self.ground is not None else 0.0

    def _check(self, start_height: float) -> str | None:
        """None while healthy; otherwise 'fell' (with self.message) or raises Divergence."""
        if not all(math.isfinite(x) for x in self.v) or not all(math.isfinite(x) for x in self.q):
            raise Divergence("the state is no longer finite (NaN or infinity)")
        fast = too_fast(self.v, start_height, self.size_scale, self.v_factors)
        if fast is not None:
            k, speed, most = fast
            unit = "rad/s" if self.model.v_angular[k] else "m/s"
            name, by = self.model.v_names[k], self.v_factors[k]  # the scaled creature's numbers
            raise TooFast(
                f"a velocity reached {speed * by:.3g} {unit} ({name}; the limit is "
                f"{most * by:.3g} {unit})",
                k, speed, most,
            )  # fmt: skip
        pos, rot = self._root_pose()
        tilt = math.acos(max(-1.0, min(1.0, rot[8])))
        limit = self.options.fall_height
        # No limit for a root that starts at its feet's level (a sled), nor for "off" (C: -inf)
        height = limit if limit is not None else 0.3 * start_height if start_height > 0 else None
        above = pos[2] - self._ground_under(pos)
        if isinstance(height, float | int) and above < height:
            shown, least = apart(above, height)
            self.message = f"the root fell to {shown} m above the ground (the limit is {least} m)"
            return "fell"
        if tilt > self.options.fall_tilt:
            self.message = (
                f"the root tilted {math.degrees(tilt):.1f} deg from upright "
                f"(limit {math.degrees(self.options.fall_tilt):g} deg)"
            )
            return "fell"
        return None

    def likely_cause(self, err: BaseException | None = None, run: Trajectory | None = None) -> str:
        """Why a run diverged now, by what ``run`` recorded (``cause_at``, ``reachable_speed``)."""
        otherwise = reachable_speed(self, err, run) or own_speed(self, err, run)
        return cause_at(self, self.q, err, run, otherwise=otherwise)

    # ------------------------------------------------------------ running
    def run(
        self,
        progress: Callable[[float, float], None] | None = None,
        stop: Callable[[], str] | None = None,
    ) -> RunResult:
        """The run, to its end, a fall, a divergence or a signal; ``progress(t, duration)``
        is called as it goes, and ``stop()`` as often: a signal's name there stops it as the
        signal does (another thread's Ctrl-C, ``legdsl.pipeline.backend.iter_batch``)."""
        opts = self.options
        loop = self.new_loop(INITIAL_ROWS)
        self.message = ""
        cause, fault_span = "", None
        wall0 = time.perf_counter()
        report = progress if stop is None else _stopping(progress, stop)
        self._begin()
        try:
            if report is not None:  # at the start: the time left is told from the pace since
                report(self.t, opts.duration)
            self._loop(loop, report)
        except ControlFault as fault:
            loop.status = "diverged"
            cause = str(fault)
            self.message = cause  # it names the time
            fault_span = fault.span
        except (Divergence, OverflowError, ZeroDivisionError, ValueError) as err:
            loop.status = "diverged"
            cause = self.diverged(err, loop.traj.head(loop.recorded))
        except (KeyboardInterrupt, Interrupted) as sig:
            loop.status = "interrupted"
            cause = signal_of(sig)
            self.message = (
                f"interrupted by {cause} at t = {self.t:.4f} s of {opts.duration:g} s; "
                "what was recorded up to then is kept"
            )
        finally:
            self._end()
        if loop.status == "fell":
            cause = self.message
        wall = time.perf_counter() - wall0
        if progress is not None:
            progress(self.t, opts.duration)
        result = RunResult(
            trajectory=loop.traj.head(loop.recorded),
            events=self._all_events(),
            status=loop.status,
            message=self.message,
            steps=loop.steps,
            wall_time=wall,
            sim_time=self.t,
            cause=cause,
            stop_time={k: round(v, 9) for k, v in self.stop_time.items()},
            fault_span=fault_span,
        )
        return told(self, result)  # an energy rise without a source is a divergence

    def new_loop(self, rows: int) -> RunLoop:
        """The loop of a run from now, its recording ``rows`` long at first (at most the run's
        samples; it doubles when full: a long run starts at once, memory follows the samples)."""
        opts = self.options
        n_steps, record_every = int(round(opts.duration / opts.dt)), steps_per_sample(opts)
        capacity = run_samples(opts)
        control_every = steps_per_control(opts)
        return RunLoop(
            n_steps=n_steps,
            record_every=record_every,
            capacity=capacity,
            traj=empty_trajectory(self, min(capacity, rows)),
            control_every=control_every,
            check_every=steps_per_check(opts, control_every, self.check_interval),
            start_height=self.standing_height(),
        )

    def diverged(self, err: BaseException, traj: Trajectory | None = None) -> str:
        """The cause of a divergence ``err`` at the state now, with what ``traj`` recorded up to
        it; sets the run's message."""
        state = ", ".join(f"{n}={x * by:.4g}" for n, x, by
                          in zip(self.model.q_names, self.q, self.q_factors, strict=True))  # fmt: skip
        cause = f"{err}. Likely cause: {self.likely_cause(err, traj)}"
        self.message = f"the simulation diverged at t = {self.t:.4f} s: {cause}. State: {state}"
        return cause

    def _begin(self) -> None:
        """The ground's first look at the contacts, before the first step."""
        if self.ground is not None:
            self.events += self.ground.update(0.0, *self._contact_kinematics(self.q, self.v))

    def _end(self) -> None:
        """After the loop, however it ended (the C backend copies its state back here)."""

    def _loop(self, loop: RunLoop, progress: Callable[[float, float], None] | None) -> None:
        """Control, record, check and step until the run ends (``loop`` says how far it got)."""
        opts = self.options
        control_every = loop.control_every
        last_report = time.perf_counter()
        for steps in range(loop.n_steps + 1):
            loop.steps = steps
            if steps % control_every == 0 and self.controller is not None:
                self.controller(self)
            if steps % loop.record_every == 0:
                if loop.recorded == len(loop.traj):
                    grow_recording(loop)
                self.generalized_forces(self.q, self.v, record=True)
                record_row(self, loop.traj, loop.recorded)
                loop.recorded += 1
            if steps % loop.check_every == 0 or steps == loop.n_steps:
                fell = self._check(loop.start_height)
                if fell:
                    loop.status = fell
                    return
            if steps == loop.n_steps:
                return
            self.step()
            if progress is not None and steps % 500 == 0:
                now = time.perf_counter()
                if now - last_report > 0.2:
                    progress(self.t, opts.duration)
                    last_report = now

    def _all_events(self) -> list[dict[str, Any]]:
        """Contact events and the controller's state changes, in time order."""
        events = [{"t": round(e.t, 9), "kind": e.kind, "contact": e.contact} for e in self.events]
        events += list(getattr(self.controller, "events", []))
        return sorted(events, key=lambda e: e["t"])


def _stopping(
    progress: Callable[[float, float], None] | None, stop: Callable[[], str]
) -> Callable[[float, float], None]:
    """``progress``, after ``stop()`` is asked whether the run must end (a signal's name)."""

    def report(t: float, duration: float) -> None:
        signal = stop()
        if signal:
            raise Interrupted(signal)
        if progress is not None:
            progress(t, duration)

    return report
