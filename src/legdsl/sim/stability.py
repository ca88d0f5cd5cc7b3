"""Actuators too stiff for the integration step, found before a run starts.

An explicit integrator is stable on a spring only while the step resolves its
oscillation. For one coordinate of effective mass ``m`` (the inverse of the
diagonal entry of M(q)^-1 at the start: the coordinate with every other one free,
its lightest and so fastest case) under a spring ``k`` with damping ``b``, write
``w^2 = k / m`` and ``c = b / m``. Semi-implicit Euler advances

    v+ = (1 - c h) v - w^2 h x,    x+ = x + h v+

whose matrix has trace ``2 - w^2 h^2 - c h`` and determinant ``1 - c h``; by
Jury's test it is stable if and only if ``c h < 2`` and ``w^2 h^2 + 2 c h < 4``.
RK4 is stable on the undamped spring for ``w h < 2.83`` and on pure damping for
``c h < 2.78``. A run past these bounds is certain to diverge, so it is refused
with the bound and what to change instead of diverging after a few steps. Those that pass
alone are checked together, on the whole of M^-1 (``legdsl.sim.coupled``): two on
coordinates that share a light mode (a ball joint near gimbal lock) can each pass and
together diverge.

A run that diverges all the same is told its likely cause (``likely_cause``): a ground too
stiff for the step, an actuator at the gains the controller set or a joint stop too stiff for
it (``stiff_now``), or a joint far past its limits.

An actuator with a ``max`` saturates (it cannot grow without bound): past the bound it
chatters between its limits, which is worth a warning, not a refusal. A gain the controller
sets every tick is not the one in the file, and is not checked.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np

from legdsl.ir.model import Model, Pad, Stop, axes_spread, setting_kind
from legdsl.lang.scaling import SMALLEST_STEP, factor
from legdsl.lang.units import KINDS, parse_unit
from legdsl.sim.actuators import ActuatorState
from legdsl.sim.coupled import InverseInertia, Pull, coupled_too_stiff
from legdsl.sim.trajectory import Trajectory

SINGULAR = 1e12  # a mass matrix's condition number past which it is taken as singular
# A ground force of this many times the creature's weight (a hard landing's is a few) is a
# foot far under the surface: one that ran into a box's side face is put under its top at once.
PUSHED = 20.0
# What a foot under a step's or box's top is told (the side faces are not modelled).
TOPS_ONLY = (
    "the ground has their top faces only: a foot under a top's edge is under its top at once"
)
CLEAR_IT = (
    "move the terrain, or have the creature clear it (a higher or earlier jump, a slower approach)"
)
# A ball joint whose turned axes span less than this (1 at right angles; their first and last
# within about 3 deg of lining up) is near gimbal lock, where its rates grow without bound.
NEAR_LOCK = 0.05

# RK4's stability interval on the imaginary axis (undamped) and on the real axis (damped).
RK4_OSCILLATION = 2.8284271247461903
RK4_DAMPING = 2.785293563405282


@dataclass(frozen=True)
class TooStiff:
    actuator: str
    setting: str  # k or kp: the stiffness; b or kv: the damping
    value: float
    limit: float  # the largest value the step allows
    dt_limit: float  # the largest step the value allows (s, the model's)
    scale: float = 1.0  # value and limit are the creature's scaled by this (``in_unit``)
    # the actuators on coupled coordinates it diverges with (``legdsl.sim.coupled``); each
    # bound is then theirs too, at the same share of their own setting
    together: tuple[str, ...] = ()
    why: str = ""  # a pose that is the reason (a ball joint near gimbal lock)

    def with_whom(self) -> str:
        """' together with 'sz' (...)' where it diverges with others, else ''."""
        if not self.together:
            return ""
        them = " and ".join(f"'{n}'" for n in self.together)
        return (f" together with {them} (their coordinates share a mode lighter than any of "
                "them alone)")  # fmt: skip

    def lowered(self) -> str:
        """How far the others' setting goes down with it."""
        them = " and ".join(f"'{n}'" for n in self.together)
        return f" (and the {self.setting} of {them} by as much)" if self.together else ""

    def message(self, dt: float, unit: str, saturating: bool = False, flags: bool = True) -> str:
        """Told with the model's step ``dt`` (s), as the creature of ``scale``'s, to a command
        that takes ``--dt`` if ``flags`` (``smaller_step``)."""
        what = "stiff" if self.setting in ("k", "kp") else "damped"
        outcome = ("only its 'max' holds it: it will chatter between -max and max every step"
                   if saturating else "diverges at once")  # fmt: skip
        fix = "" if saturating else "a 'max' for it in the .leg file (--set cannot give one)"
        return (
            f"actuator '{self.actuator}' is too {what} for the integration step"
            f"{self.with_whom()}: {self.setting} = {self.value:.4g} {unit} with dt = "
            f"{dt * math.sqrt(self.scale) * 1e3:.4g} ms {outcome}; use "
            f"{self.remedies(unit, flags, fix)}{f'; {self.why}' if self.why else ''}"
        )

    def lower(self, unit: str) -> str:
        """'kv below 0.43 N*m*s/rad' (the others' by as much, where it has others); ''
        where no value of it alone is stable."""
        if not self.limit > 0:
            return ""
        return f"{self.setting} below {below(self.limit)} {unit}{self.lowered()}"

    def remedies(self, unit: str, flags: bool, *more: str) -> str:
        """'k below 7.27e+06 N/m, or a step below 0.0341 ms (--dt, ...)' and ``more``: the
        ways out that exist (a stiffness of 1e308 N/m has no step; it was told 'below nan ms')."""
        ways = [self.lower(unit), smaller_step(self.dt_limit, self.scale, flags), *more]
        return ", or ".join(w for w in ways if w) or f"a smaller {self.setting}"


def in_unit(f: TooStiff, unit: str, scale: float = 1.0) -> TooStiff:
    """``f`` (in SI, for the model run) told in ``unit`` for the creature scaled by ``scale``
    (a ``--scale L`` run, whose user writes the scaled creature's numbers: 1e7 N/m given at
    L = 0.1 was told as the model's 1e9, with a bound 100 times off for ``--set``): its value
    and bound times their Table 1 factor, its step (``smaller_step``) by sqrt(L) when told."""
    one, dim = parse_unit(unit)
    by = factor(dim, scale) / one
    return dataclasses.replace(f, value=f.value * by, limit=f.limit * by, scale=scale)


def on_the_line(found: TooStiff, unit: str, scale: float) -> str:
    """What the file's line holds of a value told as the ``--scale`` creature's (the line is
    the unscaled creature's): nothing in a run without ``--scale``."""
    if scale == 1.0:
        return ""
    f = in_unit(found, unit)
    return (
        f" (told at --scale {scale:g}; this line is the unscaled creature's: {f.setting} = "
        f"{f.value:.4g} {unit} there, to stay below {below(f.limit)} {unit})"
    )


def setting_unit(setting: str, rotary: bool) -> str:
    """The SI unit of an actuator's setting (k, b, kp, kv) on a rotary or sliding joint."""
    return KINDS[setting_kind(setting, rotary)][1]


def smaller_step(dt_limit: float, scale: float = 1.0, flags: bool = True) -> str:
    """The advice of a step under ``dt_limit`` seconds of the model's, as the command can take
    it ('' where no step from ``SMALLEST_STEP`` up would do, or the limit is nan): ``flags``,
    it takes --dt (``legdsl run``, the API); else, as a sweep or a tune, only the file's step
    (told '--dt', the user of a sweep met 'unrecognized arguments'). In a ``--scale L`` run
    ``--dt`` is the scaled creature's, sqrt(L) times the model's, and the file's block is the
    model's: each is told its own (the model's alone told L = 0.01 to step 0.5 ms, and --dt
    0.5ms at that scale diverged again with the same advice)."""
    if not dt_limit * math.sqrt(scale) >= SMALLEST_STEP:
        return ""
    told = below(dt_limit * math.sqrt(scale) * 1e3)
    where = where_step(f"below {below(dt_limit * 1e3)} ms", scale, flags)
    return f"a step below {told} ms {where}"


def where_step(model: str = "", scale: float = 1.0, flags: bool = True, step: str = "--dt") -> str:
    """Where a step is given: ``step`` (``--dt``, or the API's ``dt=``; the scaled creature's
    in a ``--scale`` run) or the file's block, where the step is the model's, ``model`` ('below
    0.5 ms'); without ``flags``, the file's block alone (a sweep or a tune has no --scale)."""
    if not flags:
        return "(dt in the file's simulation block; a sweep or a tune has no --dt)"
    if scale == 1.0:
        return f"({step}, or dt in the simulation block)"
    return f"({step}; the file's simulation block is the unscaled creature's: dt {model} there)"


def below(x: float) -> str:
    """``x`` to three significant digits rounded down, a bound to stay under (rounded to
    nearest, kv = 0.5 was told to stay below 0.5)."""
    if not (math.isfinite(x) and x > 0):
        return f"{x:.3g}"
    unit = 10.0 ** (math.floor(math.log10(x)) - 2)
    return f"{math.floor(x / unit * (1 + 1e-12)) * unit:.3g}"


def too_stiff(
    actuators: Iterable[ActuatorState],
    inverse_inertia: Sequence[float],
    dt: float,
    integrator: str,
    controlled: set[tuple[str, str]],
    saturating: bool = False,
) -> list[TooStiff]:
    """The actuators whose stiffness or damping makes the run diverge with step ``dt``.
    ``inverse_inertia[i]`` is the diagonal of M(q)^-1 for velocity coordinate ``i``;
    ``controlled`` the (actuator, setting) pairs the controller writes. With ``saturating``,
    the actuators with a ``max`` instead: past the bound they do not diverge, but chatter
    between -max and max from step to step. Given the whole of M^-1 (an ``InverseInertia``),
    those that pass alone are checked together too (``legdsl.sim.coupled``), and a ball joint
    near gimbal lock is named where the pose is the reason."""
    checked = [a for a in actuators
               if a.kind != "force" and (a.limit is not None) == saturating]  # fmt: skip
    unlocked = getattr(inverse_inertia, "unlocked", {})
    found = []
    for a in checked:
        f = _alone(a, inverse_inertia[a.v_index], dt, integrator, controlled)
        if f is not None and a.v_index in unlocked:
            turned, why = unlocked[a.v_index]
            if _alone(a, float(turned[a.v_index, a.v_index]), dt, integrator, controlled) is None:
                f = dataclasses.replace(f, why=why)
        if f is not None:
            found.append(f)
    if found or saturating or not isinstance(inverse_inertia, InverseInertia):
        return found
    return _together(checked, inverse_inertia, dt, integrator, controlled)


def _settings(a: ActuatorState) -> tuple[str, str]:
    """The names of its stiffness and its damping."""
    return ("k", "b") if a.kind == "spring" else ("kp", "kv")


def _alone(
    a: ActuatorState, inv: float, dt: float, integrator: str, controlled: set[tuple[str, str]]
) -> TooStiff | None:
    """Actuator ``a`` on its coordinate's inverse inertia ``inv``, every other one free."""
    if not inv > 0:
        return None
    w2, c = a.gain * inv, a.damping * inv
    stiff, damp = _settings(a)
    if integrator == "rk4":
        damping_ok, damping_bound = c * dt < RK4_DAMPING, RK4_DAMPING
        stiff_ok = math.sqrt(max(w2, 0.0)) * dt < RK4_OSCILLATION
        gain_limit = (RK4_OSCILLATION / dt) ** 2 / inv
        dt_for_gain = RK4_OSCILLATION / math.sqrt(w2) if w2 > 0 else math.inf
    else:
        damping_ok, damping_bound = c * dt < 2.0, 2.0
        stiff_ok = w2 * dt * dt + 2.0 * c * dt < 4.0
        gain_limit = max(4.0 - 2.0 * c * dt, 0.0) / (dt * dt) / inv
        # the largest h with w^2 h^2 + 2 c h < 4
        dt_for_gain = (-c + math.sqrt(c * c + 4.0 * w2)) / w2 if w2 > 0 else math.inf
    if not damping_ok and (a.name, damp) not in controlled:
        return TooStiff(a.name, damp, a.damping, damping_bound / dt / inv, damping_bound / c)
    if not stiff_ok and (a.name, stiff) not in controlled:
        return TooStiff(a.name, stiff, a.gain, gain_limit, dt_for_gain)
    return None


def _together(
    checked: list[ActuatorState],
    inverse: InverseInertia,
    dt: float,
    integrator: str,
    controlled: set[tuple[str, str]],
) -> list[TooStiff]:
    """The actuators that pass alone but diverge together, each with the bound its setting
    (the same share of each) and the step must stay under."""
    pulls = []
    for a in checked:
        stiff, damp = _settings(a)
        pulls.append(Pull(a.v_index, 0.0 if (a.name, stiff) in controlled else a.gain,
                          0.0 if (a.name, damp) in controlled else a.damping))  # fmt: skip
    group = coupled_too_stiff(pulls, inverse, dt, integrator)
    if group is None:
        return []
    names = [checked[i].name for i in group.members]
    found = []
    for i in group.members:
        a = checked[i]
        stiff, damp = _settings(a)
        setting, value = (damp, a.damping) if group.setting == "damping" else (stiff, a.gain)
        limit = value * group.factor if group.factor is not None else 0.0
        others = tuple(n for n in names if n != a.name)
        found.append(TooStiff(a.name, setting, value, limit, group.dt_limit, together=others,
                              why=group.why))  # fmt: skip
    return found


def inverse_inertia_diagonal(mass_matrix: Sequence[Sequence[float]]) -> list[float]:
    """The diagonal of M^-1 (0 for every coordinate if M is singular)."""
    try:
        return [float(x) for x in np.diag(np.linalg.inv(np.asarray(mass_matrix, dtype=float)))]
    except np.linalg.LinAlgError:
        return [0.0] * len(mass_matrix)


def stiff_now(
    model: Model,
    actuators: Iterable[ActuatorState],
    inverse_inertia: Sequence[float],
    dt: float,
    integrator: str,
    scale: float = 1.0,
    flags: bool = True,
) -> list[str]:
    """The actuators at their settings now (a gain the controller set is not checked before
    the run) and the model's joint stops that are too stiff or too damped for the step, as
    causes of a divergence: an actuator's values in SI units, a stop's in those written on
    its line, both for the creature scaled by ``scale`` (``in_unit``), told as a command takes
    a step (``flags``: ``smaller_step``)."""
    rotary = {a.name: a.rotary for a in model.actuators}
    causes = []
    for found in too_stiff(actuators, inverse_inertia, dt, integrator, set()):
        unit = setting_unit(found.setting, rotary.get(found.actuator, False))
        f = in_unit(found, unit, scale)
        causes.append(
            f"actuator '{f.actuator}' has {f.setting} = {f.value:.4g} {unit} now, too "
            f"{'stiff' if f.setting in ('k', 'kp') else 'damped'} for the step{f.with_whom()}: "
            f"use {f.remedies(unit, flags)}{f'; {f.why}' if f.why else ''}"
        )
    stops = model.stops
    return causes + [
        stop_message(f, stops, scale, flags)
        for f in stops_too_stiff(stops, inverse_inertia, dt, integrator)
    ]


def stops_too_stiff(
    stops: Iterable[Stop], inverse_inertia: Sequence[float], dt: float, integrator: str
) -> list[TooStiff]:
    """The joint stops too stiff or too damped for the step (``TooStiff.actuator`` is the
    stop's coordinate): a stop pushes like a spring while its coordinate is past the limit."""
    pushing = [ActuatorState(st.dof, "spring", st.q_index, st.v_index, st.k, st.b, 0.0, 0.0, None)
               for st in stops]  # fmt: skip
    return too_stiff(pushing, inverse_inertia, dt, integrator, set())


def stop_message(
    found: TooStiff, stops: Iterable[Stop], scale: float = 1.0, flags: bool = True
) -> str:
    """A stop of ``stops`` too stiff or too damped, told in the unit written on its line (a
    stop in kN*m/rad was told bare SI numbers, 1000 times its unit) for the creature scaled by
    ``scale``."""
    stop = next(st for st in stops if st.dof == found.actuator)
    unit = stop.units[0 if found.setting == "k" else 1]
    f = in_unit(found, unit, scale)
    return (
        f"the stop of joint coordinate {f.actuator} is too "
        f"{'stiff' if f.setting == 'k' else 'damped'} for the step ({f.setting} = "
        f"{f.value:.4g} {unit}): use {f.remedies(unit, flags)}"
    )


def likely_cause(
    model: Model,
    dt: float,
    integrator: str,
    q: Sequence[float],
    mass_matrix: Sequence[Sequence[float]] | None = None,
    stiff: Sequence[str] = (),
    recorded: Trajectory | None = None,
    contacts: Sequence[tuple[float, float]] | None = None,
    found: Sequence[str] = (),
    scale: float = 1.0,
    otherwise: str | None = None,
    flags: bool = True,
) -> str:
    """Why a run diverged, from the contact stiffness, the step and the joint limits at ``q``,
    the mass matrix there (where the dynamics could compute it), the actuators and stops
    too stiff for the step (``stiff``: ``stiff_now``), what the run ``recorded`` up to it and
    each contact's inverse effective masses there (``contacts``: ``ground_too_stiff``), with
    the causes ``found`` already (a foot pushed under a step's edge: ``legdsl.sim.causes``);
    told in the numbers of the creature scaled by ``scale`` (a ``--scale L`` run's); with none
    of them, ``otherwise`` (a speed nothing grew to) or that the state grew without bound;
    a step advised as a command takes it (``flags``: ``smaller_step``)."""
    causes = [*found, *stiff]
    ground = ground_too_stiff(model, dt, integrator, contacts, scale, flags)
    # A contact too stiff for the step pushes hard at its first sample down on any landing:
    # the push then says nothing of how deep the foot came down.
    if ground is None and recorded is not None and (pushed := _pushed_deep(model, recorded, scale)):
        causes.append(pushed)
    if mass_matrix is not None:
        m = np.asarray(mass_matrix, dtype=float)
        condition = np.linalg.cond(m) if np.all(np.isfinite(m)) else math.inf
        if not condition < SINGULAR:
            causes.append(
                f"the mass matrix is singular here (condition number {condition:.2g}): a joint "
                "is at a singular configuration, such as a ball joint whose first and last axes "
                "line up (gimbal lock); give that joint other axes or keep it away from there"
            )
    for joint in model.joints:
        angles = [q[d.q_index] for d in joint.dofs]
        if joint.kind != "ball" or not all(map(math.isfinite, angles)):
            continue
        spread = axes_spread([d.axis for d in joint.dofs], angles)
        if spread < NEAR_LOCK:  # the middle angle alone decides it (the first turns all three)
            middle = joint.dofs[1]
            causes.append(
                f"ball joint '{joint.name}' is {'in' if spread < 1e-6 else 'near'} gimbal lock: "
                f"at {middle.name} = {math.degrees(angles[1]):.3g} deg its axes lie within "
                f"{math.degrees(math.asin(min(spread, 1.0))):.2g} deg of one plane, where its rates "
                f"grow without bound; give it axes that this motion keeps away from that, or "
                f"limits on {middle.name} with a stop short of it"
            )
    if ground is not None:
        causes.append(ground)
    for d in model.dofs:
        if d.limits is None:
            continue
        lo, hi = d.limits
        value = q[d.q_index]
        span = hi - lo
        if value < lo - 0.1 * span or value > hi + 0.1 * span:
            by = 1.0 if d.motion == "hinge" else scale  # an angle, or a length
            causes.append(
                f"joint coordinate {d.name} = {value * by:.3g} is past its limits "
                f"[{lo * by:.3g}, {hi * by:.3g}]"
            )
    if not causes:
        causes.append(
            otherwise
            or f"the state grew without bound; try a smaller step {where_step(flags=flags)}"
            + (" or --integrator rk4" if flags else "")
        )
    return "; ".join(causes)


# The ground's bound is told past this share of it: a contact's effective mass changes as the
# creature moves, and the pad of eq. (6) stiffens as it compresses.
GROUND_MARGIN = 0.5


def ground_too_stiff(
    model: Model,
    dt: float,
    integrator: str,
    contacts: Sequence[tuple[float, float]] | None = None,
    scale: float = 1.0,
    flags: bool = True,
) -> str | None:
    """The ground's springs too stiff or too damped for the step, as a cause of a divergence
    (told in the numbers of the creature scaled by ``scale``, to a command that takes --dt and
    --integrator if ``flags``);
    None if the step is within ``GROUND_MARGIN`` of every bound. A contact's normal and tangent
    springs act on its effective mass in their direction (``contacts[i]``: the inverse of each,
    1/kg, from J M^-1 J^T where the dynamics gave it; else the lightest contact body's mass,
    which a light leg's tip, turning about the leg's centre of mass, can be far under) as an
    actuator on a coordinate does: ``too_stiff``'s bounds (Jury's test) are theirs."""
    g = model.ground
    if g is None or not model.contacts:
        return None
    if contacts is None:
        lightest = 1.0 / min(model.body(c.body).mass for c in model.contacts)
        contacts = [(lightest, lightest)] * len(model.contacts)
    # The pad of eq. (6) starts at slope k / thickness and stiffens as it compresses.
    normal = g.normal.k / g.normal.thickness if isinstance(g.normal, Pad) else g.normal.k
    springs: list[ActuatorState] = []
    inverse: list[float] = []
    for contact, masses in zip(model.contacts, contacts, strict=True):
        for direction, k, b, inv in (("normal", normal, g.normal.b, masses[0]),
                                     ("tangent", g.tangent.k, g.tangent.b, masses[1])):  # fmt: skip
            springs.append(ActuatorState(f"{direction} spring on contact '{contact.name}'",
                                         "spring", 0, len(inverse), k, b, 0.0, 0.0, None))  # fmt: skip
            inverse.append(inv)
    found = too_stiff(springs, inverse, dt / GROUND_MARGIN, integrator, set())
    if not found:
        return None
    worst = min(found, key=lambda f: f.dt_limit)
    spring = springs[[s.name for s in springs].index(worst.actuator)]
    mass, limit = 1.0 / inverse[spring.v_index], worst.dt_limit
    rk4 = (
        flags
        and integrator != "rk4"
        and not too_stiff(springs, inverse, dt / GROUND_MARGIN, "rk4", set())
    )

    def by(kind: str) -> float:
        return factor(KINDS[kind][0], scale)

    tick = by("time")
    step = (
        f"try a step of {limit * tick / 4 * 1e3:.1g} ms "
        f"{where_step(f'of {limit / 4 * 1e3:.1g} ms', scale, flags)}"
        f"{' or --integrator rk4' if rk4 else ''}"
        if limit * tick / 4 >= SMALLEST_STEP
        else "no step legdsl takes is that small: lower the ground's k and b"
    )
    return (
        f"the step {dt * tick * 1e3:.3g} ms is too large for the contact stiffness: the ground's "
        f"{worst.actuator} (k = {spring.gain * by('linear stiffness'):.4g} N/m, b = "
        f"{spring.damping * by('linear damping'):.4g} N*s/m) acts on an effective mass of "
        f"{mass * by('mass'):.3g} kg there, and explicit stability needs dt < "
        f"{below(limit * tick * 1e3)} ms; {step}"
    )


def _pushed_deep(model: Model, run: Trajectory, scale: float = 1.0) -> str | None:
    """A foot that touched down far under the surface (pushed past ``PUSHED`` weights at
    its first sample down) among the last samples recorded before a divergence, as its
    cause; None if there was none. (A run blowing up pushes hard too, but on feet that were
    down already.)"""
    t, contact, force = run.t, run.contact, run.force
    weight = model.total_mass * abs(model.gravity[2])
    finite = np.flatnonzero(np.all(np.isfinite(force.reshape(len(force), -1)), axis=1))[-3:]
    if weight <= 0 or not len(finite) or not force.shape[1]:
        return None
    push = np.linalg.norm(force[finite], axis=2)  # (samples, contacts)
    before = np.maximum(finite - 1, 0)
    push[(contact[before] != 0) | (before == finite)[:, None]] = 0.0  # only first samples down
    row, foot = np.unravel_index(int(np.argmax(push)), push.shape)
    if not push[row, foot] > PUSHED * weight:
        return None
    said = (
        f"contact '{model.contacts[foot].name}' touched down far under the surface: the ground "
        f"pushed it with {push[row, foot] * scale**3:.3g} N at t = "
        f"{t[finite[row]] * math.sqrt(scale):.4f} s, "
        f"{push[row, foot] / weight:.0f} times the creature's weight"
    )
    terrain = model.ground.terrain if model.ground is not None else ()
    if any(f.kind in ("step", "box") for f in terrain):
        return f"{said}, as a foot that runs into the side of a step or box does ({TOPS_ONLY}); {CLEAR_IT}"
    return f"{said}; land softer (a slower approach, a softer leg) or give the ground a pad"
