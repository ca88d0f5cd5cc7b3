"""Run a generated control module: the state machine of a controller, called every control tick.

The generated module (``generated/NAME/control_CONTROLLER.py``) holds the
lowered math as plain functions and tables (see ``legdsl.codegen.python.dynamics.python.dynamics.python.control``):

    STATE_NAMES, START, SENSORS, INPUTS, PARAMS, RECORDS
    AFTER_ENTRY[(binding, state)] -> binding
    EVENTS[(binding, state)](s, u, p, r, tis) -> bool      the condition to enter ``state``
    ENTRIES[(binding, state)](s, u, p, r, tis) -> list      new values of RECORDS
    SETTINGS[(binding, state)] -> ((actuator, key), ...)
    PLACES[(binding, state)] -> ((leg, axes, servos), ...)   kinematic solves (``place``)
    ACTIONS[(binding, state)](s, u, p, r, tis) -> list       one value per SETTINGS entry,
                                                             then the goals of the PLACES

where ``s`` are the sensor values in SENSORS order, ``u`` the inputs, ``p``
the parameters, ``r`` the records and ``tis`` the time in the current state.
This class keeps the machine's state, reads the sensors, and applies the
settings to the simulation's actuators.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from types import ModuleType
from typing import Any

from legdsl.ir.model import NON_NEGATIVE, Model, setting_kind
from legdsl.ir.paths import PathSpec
from legdsl.lang.errors import UsageError
from legdsl.lang.scaling import factor
from legdsl.lang.units import KINDS
from legdsl.signals import import_held
from legdsl.sim.handover import Clock, Pair, cycle, take_over
from legdsl.sim.kinematics import FootPlacer
from legdsl.sim.run_loop import ControlFault
from legdsl.sim.sensors import Sensors


@dataclass(frozen=True)
class InputChange:
    """``--set speed=5m/s@4s``: from time ``t`` on, the input has this value."""

    t: float
    name: str
    value: float


@dataclass
class Integral:
    """``integral(INPUT)``: an input's commands integrated over the run's time. They are
    constant between changes, so it is exact: ``total`` up to the last change at ``since``,
    plus the value now times the time since. Without a change it is ``value * time`` to the
    last bit, as a controller's own ``INPUT * time`` would be."""

    total: float = 0.0
    since: float = 0.0

    def value(self, now: float, t: float) -> float:
        return self.total + now * (t - self.since)

    def change(self, old: float, new: float, t: float) -> None:
        """The input goes from ``old`` to ``new`` at ``t`` (nothing to do if it stays)."""
        if new != old:
            self.total += old * (t - self.since)
            self.since = t


def resolve_paths(model: Model, controller: str, given: list[PathSpec]) -> list[PathSpec]:
    """The controller's declared paths with those of ``--path`` in their place (by name).

    A ``--path`` without a name (its name is empty) replaces the controller's only path.
    """
    declared = {p.name: p for p in model.controller(controller).paths}
    replaced: set[str] = set()
    for spec in given:
        name = spec.name
        if not name:
            if len(declared) != 1:
                raise UsageError(
                    f"--path: controller {controller} has "
                    + (
                        f"the paths {', '.join(declared)}: say which, as in --path {next(iter(declared))}=circle(...)"
                        if declared
                        else "no path; declare one in it with 'path NAME' (or 'path NAME = SHAPE')"
                    )
                )
            name = next(iter(declared))
        elif name not in declared:
            raise UsageError(
                f"--path {name}=...: controller {controller} has no path {name!r} "
                f"(it has {', '.join(declared) or 'none'})"
            )
        if name in replaced:  # the later would win silently, as two --set of one name would
            raise UsageError(
                f"--path: path {name} of controller {controller} is given twice; keep one"
            )
        replaced.add(name)
        declared[name] = replace(spec, name=name)
    return list(declared.values())


class StateMachine:
    def __init__(
        self,
        model: Model,
        module: ModuleType,
        inputs: dict[str, float] | None = None,
        params: dict[str, float] | None = None,
        schedule: list[InputChange] | None = None,
        paths: list[PathSpec] | None = None,
    ):
        self.module = module
        self.model = model
        self.sensors = Sensors(model)
        self.paths = resolve_paths(model, module.CONTROLLER, paths or [])
        self.sensors.follow(self.paths)
        self.placer = FootPlacer(model)
        self.state_names: tuple[str, ...] = module.STATE_NAMES
        self.input_names = tuple(module.INPUTS)
        self.param_names = tuple(module.PARAMS)
        for name in [*(inputs or {}), *(c.name for c in schedule or [])]:
            if name not in module.INPUTS:
                raise UsageError(
                    f"--set {name}: controller has no input {name!r} (inputs: {', '.join(module.INPUTS) or 'none'})"
                )
        for name in params or {}:
            if name not in module.PARAMS:
                raise UsageError(f"--set {name}: controller has no parameter {name!r}")
        self.inputs = [float((inputs or {}).get(n, v)) for n, v in module.INPUTS.items()]
        self.params = tuple(float((params or {}).get(n, v)) for n, v in module.PARAMS.items())
        self.schedule = sorted(schedule or [], key=lambda c: c.t)
        self.records = [0.0] * len(module.RECORDS)  # a record is 0 until first recorded
        self.integrals = [Integral() for _ in self.input_names]
        self.sensors.integral = self._integral
        self.state_index = module.START
        self.binding = 0
        self.entered_at = 0.0
        self.started = False
        # a controller that takes over mid-run (``legdsl.sim.switching``) starts in the state
        # that matches the contacts, not in START (``legdsl.sim.handover``)
        self.taking_over = False
        self.binding_at_start = 0
        self.events: list[dict[str, Any]] = []
        self._sane = True  # the simulation's state is finite (set at each call)
        self._scale = 1.0  # a --scale L run's L: a fault is told in that creature's numbers
        self._history: list[tuple[float, list[float]]] = [(0.0, list(self.inputs))]

    @property
    def initial_inputs(self) -> dict[str, float]:
        """The inputs at t = 0 (before any scheduled change)."""
        return dict(zip(self.input_names, self._history[0][1], strict=True))

    def start_inputs(self, values: list[float], t: float) -> None:
        """The inputs this machine starts with at time ``t`` (a controller taking over)."""
        self.inputs = list(values)
        self._history = [(t, list(values))]

    def speed_command(self, t: float) -> float:
        if "speed" not in self.input_names:
            return math.nan
        i = self.input_names.index("speed")
        value = self._history[0][1][i]
        for when, values in self._history:
            if when <= t + 1e-12:
                value = values[i]
        return value

    def _apply_schedule(self, t: float) -> None:
        changed = False
        while self.schedule and self.schedule[0].t <= t + 1e-12:
            change = self.schedule.pop(0)
            i = self.input_names.index(change.name)
            self.integrals[i].change(self.inputs[i], change.value, t)
            self.inputs[i] = change.value
            changed = True
        if changed:
            self._history.append((t, list(self.inputs)))

    def integral_state(self) -> list[float]:
        """Each input's integral as machine.c keeps it: its total, then since."""
        return [x for i in self.integrals for x in (i.total, i.since)]

    def _integral(self, name: str, t: float) -> float:
        i = self.input_names.index(name)
        return self.integrals[i].value(self.inputs[i], t)

    def _call(self, kind: str, table: dict[Any, Any], key: tuple[int, int], args: tuple[Any, ...],
              t: float, state: int) -> Any:  # fmt: skip
        """A generated function of the control module; a failure, or an output that is not
        finite, becomes a ``ControlFault`` naming the .leg statement."""
        # A state that is no longer finite is the simulation's divergence, not the control
        # law's fault: let it through to the divergence check. (Sensors may be NaN on
        # purpose: a stance time before the first stance.)
        sane = self._sane
        try:
            out = table[key](*args)
        except (ValueError, ZeroDivisionError, OverflowError, TypeError) as err:
            # (a TypeError: a comparison with the complex number a fractional power of a
            # negative number gives in Python)
            if not sane:  # the simulation's divergence: the run loop reports it as such
                raise ValueError(f"{type(err).__name__}: {err}") from None
            raise self._fault(kind, key, args, t, state, f"{type(err).__name__}: {err}") from None
        if kind != "event" and sane:
            for i, x in enumerate(out):
                if isinstance(x, complex) or not math.isfinite(x):
                    raise self._fault(kind, key, args, t, state, f"an output is {x}", i)
        return out

    def _fault(self, kind: str, key: tuple[int, int], args: tuple[Any, ...], t: float,
               state: int, error: str, index: int | None = None) -> ControlFault:  # fmt: skip
        # sympy (some 0.4 s to import) lowers the controller again: only once a law has failed
        explain = import_held("legdsl.sim.control_faults").explain
        return explain(self.model, self.module, kind, key, args, t, self.state_names[state],
                       error, index, self._scale)  # fmt: skip

    def _negative(self, actuator: str, setting: str, value: float) -> str:
        """Why a negative stiffness or damping stops the run (the C machine hands the tick to
        Python where one is set, so that both say this)."""
        rotary = next(a.rotary for a in self.model.actuators if a.name == actuator)
        dim, unit = KINDS[setting_kind(setting, rotary)]
        what = "stiffness" if setting in ("k", "kp") else "damping"
        value *= factor(dim, self._scale)
        return (
            f"it sets {actuator}.{setting} = {value:.4g} {unit}, and {setting} must not be "
            f"negative (a negative {what} feeds energy in, and the run would diverge); keep it "
            f"at 0 or more, as with max(0 {unit}, ...)"
        )

    def _enter(self, state: int, t: float, s: tuple[float, ...]) -> None:
        self.state_index = state
        self.entered_at = t
        key = (self.binding, state)
        args = (s, self.inputs, self.params, self.records, 0.0)
        self.records = list(self._call("entry", self.module.ENTRIES, key, args, t, state))
        self.events.append({"t": round(t, 9), "kind": "state", "state": self.state_names[state]})

    def feet(self) -> dict[str, Clock]:
        """Each foot now, as the handover reads it: down or not, its last touchdown and liftoff.
        A leg's foot contact stands for the leg (``touchdown(leg)`` watches it): a leg with
        several soles is down while any of them is, as its own clock says."""
        clocks = dict(self.sensors.clocks)
        for leg in self.model.legs:
            if leg.more_soles:
                clocks[leg.foot] = self.sensors.leg_clocks[leg.name]
        return {n: Clock(c.touching, c.touchdown, c.liftoff) for n, c in clocks.items()}

    def _take_over(self, t: float, s: tuple[float, ...]) -> None:
        """Enter the (binding, state) that matches which feet are down now."""
        pairs = cycle(self.model, self.model.controller(self.module.CONTROLLER))
        feet = self.feet()

        def holds(pair: Pair) -> bool:
            key = (pair.waited, pair.state)
            args = (s, self.inputs, self.params, self.records, 0.0)
            return bool(self._call("event", self.module.EVENTS, key, args, t, pair.state))

        chosen = take_over(pairs, feet, holds)
        self.binding = self.binding_at_start = chosen.binding
        self._enter(chosen.state, t, s)

    def __call__(self, sim: Any) -> None:
        t = sim.t
        self._sane = all(math.isfinite(x) for x in sim.q) and all(math.isfinite(x) for x in sim.v)
        self._scale = getattr(sim, "size_scale", 1.0)
        self._apply_schedule(t)
        touching = (
            sim.ground.touching if sim.ground is not None else [False] * len(self.sensors.clocks)
        )
        self.sensors.observe(t, touching)
        values = self.sensors.read(sim, self.module.SENSORS)
        s = tuple(values[k] for k in self.module.SENSORS)
        m = self.module
        if not self.started:
            self.started = True
            if self.taking_over:
                self._take_over(t, s)
            else:
                self._enter(self.state_index, t, s)
        else:
            nxt = (self.state_index + 1) % len(self.state_names)
            args = (s, self.inputs, self.params, self.records, t - self.entered_at)
            if self._call("event", m.EVENTS, (self.binding, nxt), args, t, self.state_index):
                self.binding = m.AFTER_ENTRY[(self.binding, nxt)]
                self._enter(nxt, t, s)
        key = (self.binding, self.state_index)
        args = (s, self.inputs, self.params, self.records, t - self.entered_at)
        outputs = self._call("action", m.ACTIONS, key, args, t, self.state_index)
        targets = m.SETTINGS[key]
        for i, ((actuator, setting), value) in enumerate(zip(targets, outputs, strict=False)):
            if value < 0 and setting in NON_NEGATIVE and self._sane:
                error = self._negative(actuator, setting, value)
                raise self._fault("action", key, args, t, self.state_index, error, i)
            sim.actuators.by_name[actuator].set(setting, value)
        goals = iter(outputs[len(targets) :])
        for i, (leg, axes, servos) in enumerate(m.PLACES.get(key, ())):
            wanted = [next(goals) for _ in axes]
            try:
                solved = self.placer.solve(sim, leg, axes, wanted, servos)
            except (ValueError, ZeroDivisionError, OverflowError) as err:
                error = f"{type(err).__name__}: {err}"
                raise self._fault("place", key, args, t, self.state_index, error, i) from None
            for servo, value in zip(servos, solved, strict=True):
                sim.actuators.by_name[servo].set("setpoint", value)


def settings_written(module: ModuleType) -> dict[str, list[str]]:
    """Each actuator setting a controller's actions write (``hip_servo.kp``; a ``place``'s
    servos, their setpoint), with the states that write it."""
    names, places = module.STATE_NAMES, getattr(module, "PLACES", {})
    written: dict[str, list[str]] = {}
    for key, targets in module.SETTINGS.items():
        placed = [(servo, "setpoint") for _, _, servos in places.get(key, ()) for servo in servos]
        for actuator, setting in (*targets, *placed):
            states = written.setdefault(f"{actuator}.{setting}", [])
            if names[key[1]] not in states:
                states.append(names[key[1]])
    return written


def overwritten(
    name: str, controller: str, module: ModuleType, model: Model | None = None
) -> str | None:
    """What becomes of a value given to actuator setting ``name`` (``--set``, ``--grid``) that
    the controller writes itself: none where it does not (a swept servo gain the controller
    set gave identical rows, unsaid). With the ``model``, the parameters it is set from are
    named (the note said 'give one to the parameter it sets it from', naming none)."""
    states = settings_written(module).get(name)
    if not states:
        return None
    which = f"state{'s' if len(states) > 1 else ''} {', '.join(states)}"
    if len(states) == len(module.STATE_NAMES):
        which = "every state"
    if module.STATE_NAMES[module.START] in states:  # written at the first tick: never used
        said = (f"controller '{controller}' sets {name} itself in {which}, from its first "
                "tick, so a value given has no effect; ")  # fmt: skip
        if model is None:
            return said + "give one to the parameter it sets it from"
        params = set_from(model, controller, name)
        if not params:
            return said + "it is set from no parameter: to change it, change the controller"
        many = "s" if len(params) > 1 else ""
        return said + f"give one to the parameter{many} it is set from, {', '.join(params)}"
    return (f"controller '{controller}' sets {name} itself in {which}: a value given holds "
            "only until the run first enters one")  # fmt: skip


def set_from(model: Model, controller: str, name: str) -> list[str]:
    """The parameters a controller's states set actuator setting ``name`` from (a place's
    goals for a servo's setpoint; the records it reads, and theirs), in the file's order."""
    from legdsl.lower.control import lower_controller

    control = model.controller(controller)
    lowered = lower_controller(model, control)
    actuator, _, key = name.partition(".")
    exprs = [s.value for body in lowered.bodies.values() for s in body.settings
             if (s.actuator, s.key) == (actuator, key)]  # fmt: skip
    if key == "setpoint":
        exprs += [goal for body in lowered.bodies.values() for place in body.places
                  if actuator in place.servos for goal in place.goals]  # fmt: skip
    records: dict[str, list[Any]] = {}  # a record's values, for what it is set from in turn
    for body in lowered.bodies.values():
        for record, value in body.records:
            records.setdefault(f"record_{record}", []).append(value)
    read: set[str] = set()
    while exprs:
        fresh = {str(symbol) for e in exprs for symbol in getattr(e, "free_symbols", ())} - read
        read |= fresh
        exprs = [value for symbol in fresh for value in records.get(symbol, ())]
    return [c.name for c in control.params if f"param_{c.name}" in read]
