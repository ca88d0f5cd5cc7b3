"""Actuator forces: the spring-damper of eq. (1), the servo of eq. (5), plain forces.

This is a small runtime layer rather than generated code: each actuator is a
scalar law on one coordinate, and its inputs (rest value, setpoint, gains,
force) are changed by the controller while the simulation runs, so a table of
settings read by one short loop is both the clearest and the fastest form.

Sign convention: a spring pulls its coordinate towards ``rest``::

    tau = -(k (q - rest) + b qd)            # eq. (1): f = k (x - x_r) + b xd acts against x
    tau = -kp (q - setpoint) - kv qd         # eq. (5)
    tau = force                              # a plain force or torque

clipped to ``[-max, max]`` when the .leg file gives ``max`` (the torque the
actuator can deliver). What a spring or servo holds (``elastic_energy``, the run's
``elastic``) is the potential of its spring force as clipped (``stored``): ``1/2 k d^2`` up
to the stretch where ``k d`` reaches ``max``, and ``max`` more per unit of stretch beyond.

Work: each actuator's mechanical power is its force or torque times its coordinate's rate,
``tau * qd`` (W), integrated at every integration step with the integrator's own weights
(``Simulation.step``); the positive and the negative parts are summed apart
(``positive_work``, ``negative_work``, J since the start), so the work between two
instants is a difference of two recorded values.
"""

from __future__ import annotations

from dataclasses import dataclass

from legdsl.ir.model import Actuator, Model


@dataclass
class ActuatorState:
    """One actuator's live settings and the coordinate it drives."""

    name: str
    kind: str
    q_index: int
    v_index: int
    gain: float  # k or kp
    damping: float  # b or kv
    target: float  # rest or setpoint
    force: float  # commanded force (kind 'force')
    limit: float | None
    last_force: float = 0.0

    def set(self, key: str, value: float) -> None:
        if key in ("k", "kp"):
            self.gain = value
        elif key in ("b", "kv"):
            self.damping = value
        elif key in ("rest", "setpoint"):
            self.target = value
        elif key == "force":
            self.force = value
        else:
            raise KeyError(f"{self.kind} actuator {self.name} has no setting {key!r}")

    def get(self, key: str) -> float:
        return {
            "k": self.gain, "kp": self.gain, "b": self.damping, "kv": self.damping,
            "rest": self.target, "setpoint": self.target, "force": self.last_force,
        }[key]  # fmt: skip


class ActuatorBank:
    """All actuators of a model; ``apply`` adds their generalized forces to ``tau``."""

    def __init__(self, model: Model):
        dofs = {d.name: d for d in model.dofs}
        self.states = [
            self._state(a, dofs[a.dof].q_index, dofs[a.dof].v_index) for a in model.actuators
        ]
        self.by_name = {s.name: s for s in self.states}
        self.positive_work = [0.0] * len(self.states)  # J: the sums of max(0, tau qd) dt
        self.negative_work = [0.0] * len(self.states)  # J: of min(0, tau qd) dt

    @staticmethod
    def _state(a: Actuator, qi: int, vi: int) -> ActuatorState:
        p = dict(a.params)
        if a.kind == "force":
            return ActuatorState(a.name, a.kind, qi, vi, 0.0, 0.0, 0.0, p.get("value", 0.0), a.max)
        gain, damping, target = (
            (p["k"], p["b"], p["rest"]) if a.kind == "spring" else (p["kp"], p["kv"], p["setpoint"])
        )
        return ActuatorState(a.name, a.kind, qi, vi, gain, damping, target, 0.0, a.max)

    def apply(self, q: list[float], v: list[float], tau: list[float]) -> None:
        for s in self.states:
            if s.kind == "force":
                f = s.force
            else:
                f = -s.gain * (q[s.q_index] - s.target) - s.damping * v[s.v_index]
            if s.limit is not None:
                f = max(-s.limit, min(s.limit, f))
            s.last_force = f
            tau[s.v_index] += f

    def power(self, v: list[float]) -> list[float]:
        """Each actuator's power (W): the force ``apply`` found last times its rate in ``v``."""
        return [s.last_force * v[s.v_index] for s in self.states]

    def add_work(self, power: list[float], dt: float) -> None:
        """One step's work at ``power``: the positive part to one sum, the rest to the other."""
        for i, p in enumerate(power):
            if p > 0.0:
                self.positive_work[i] += p * dt
            else:
                self.negative_work[i] += p * dt

    def elastic_energy(self, q: list[float], names: tuple[str, ...] | None = None) -> float:
        """What the springs and servos hold (a servo is a spring with a setpoint), each by
        ``stored``: the potential of its spring force as ``apply`` clips it."""
        total = 0.0
        for s in self.states:
            if s.kind != "force" and (names is None or s.name in names):
                total += stored(s.gain, q[s.q_index] - s.target, s.limit)
        return total


def stored(gain: float, stretch: float, limit: float | None) -> float:
    """J: the energy a spring of stiffness ``gain`` holds ``stretch`` from its rest, its force
    clipped to ``limit`` (``max``, or None): the potential of ``clip(-gain stretch, -limit,
    limit)``, ``1/2 gain stretch^2`` while the spring's force is within the limit and growing
    by ``limit`` per unit of stretch beyond (``limit (|stretch| - limit / (2 gain))``). With a
    damper the force clipped is the sum, and what it takes from that potential's force always
    opposes the motion: the damper's share dissipates, as without a ``max``. A stiff spring
    held at 5 N*m and 90 deg from its rest holds 7.8 J, not its 1/2 k d^2 of 1234 J."""
    if limit is None or not abs(gain * stretch) > limit:  # a NaN stays in the plain form
        return 0.5 * gain * stretch * stretch
    # past the limit: |gain| > limit / |stretch| >= 0, so the division is sound
    beyond = limit * (abs(stretch) - 0.5 * limit / abs(gain))
    return beyond if gain > 0.0 else -beyond
