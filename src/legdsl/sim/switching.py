"""A run whose controller changes at given times (``legdsl run --switch 6s=gallop``).

``SwitchingMachine`` holds one ``StateMachine`` at a time. At each switch the next
controller's machine is made and takes over:

* at the first control tick at or after the switch's time at which a foot has just lifted
  off and one of its states knows that foot up and every other foot as it is, no role of it
  partly down (``legdsl.sim.handover.on_liftoff``: the start of a flight or of that leg's
  swing), or
  ``HANDOVER_WAIT`` after the switch's time if none comes, or at once if its table has no
  liftoff event. For ``FLIGHT_WAIT`` after the switch's time only a liftoff that starts a
  flight will do, the centre of mass rising and the trunk turning slower than
  ``FLIGHT_TURN_MOST``: the new controller then places its own feet before any lands,
  instead of taking over a stance the old gait began (the quadruped's trot taking over from
  the gallop in the gallop's rear stance fell within 0.4 s: docs/quadruped.md, "Changing
  gait). The four constants are for a creature standing ``REFERENCE_HEIGHT``; times scale
  with the creature's natural time, rates with its inverse (``natural_scale``: docs/scaling.md);
* it starts in the (binding, state) that matches which feet are down (``legdsl.sim.handover``),
  entering it as if its event had just held (its entry records are computed);
* its records start from the old controller's where the names match (0 otherwise, and 0 for
  those it declares ``own``: a trim learned with its own gains), its
  inputs from the latest command given for each (``--set NAME=V`` or ``NAME=V@T``, also one
  given while a controller without that input ran), else from its own defaults (or those
  given as ``--set CONTROLLER.NAME=V``); parameters given with ``--set NAME=V`` apply to
  every controller that has them, ``--set CONTROLLER.NAME=V`` to that one only;
* ``integral(INPUT)`` carries on for an input both controllers have (else it counts from
  the takeover);
* the sensors' contact clocks (last stance and flight times) carry on, and so does the
  tracker of a path that both controllers follow.

The trajectory's states are named ``CONTROLLER.STATE`` over every controller of the run.
A run without switches uses a bare ``StateMachine``: nothing here touches it.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, replace
from types import ModuleType
from typing import Any

from legdsl.ir.model import Model
from legdsl.ir.paths import PathSpec
from legdsl.sim.handover import Clock, Pair, cycle, lifts_off, on_liftoff
from legdsl.sim.machine import InputChange, Integral, StateMachine, resolve_paths
from legdsl.sim.path_tracking import lookahead_note

# The four numbers below are for a creature standing REFERENCE_HEIGHT over its lowest foot at
# the start (the quadruped 0.81 m, the biped 0.83 m); a creature standing h waits and falls
# in times sqrt(h / REFERENCE_HEIGHT) as long and turns at rates as much slower
# (``natural_scale``), as Table 1 scales its motion, so that a creature scaled by L (``legdsl
# scale``) changes gait at the moments the original does, times sqrt(L) (docs/scaling.md).
REFERENCE_HEIGHT = 0.81  # m: the quadruped's, whose gait changes are the most sensitive
# How long a switch waits at most for a liftoff to take over at: a stride of the slowest
# shipped gait (the quadruped's trot steps every 0.4 s, the biped's run every 0.45 s).
HANDOVER_WAIT = 1.0  # s
# How long it waits at first for a liftoff into a flight, the centre of mass rising: more
# than a stride of the shipped running gaits, less than HANDOVER_WAIT.
FLIGHT_WAIT = 0.5  # s
# ...and the trunk turning slower than this about the horizontal: no controller can change
# that turning before a foot lands (the quadruped's gallop leaves its rear pair pitching
# nose down at about 3.5 rad/s, for its own front pair to catch; the trot fell on it).
FLIGHT_TURN_MOST = 2.5  # rad/s
# ...and every foot that did not just lift off at least this long a free fall from the
# ground, or one the new controller lands on next: a foot about to land is one the old gait
# aimed (the outside knee quadruped's bound and gallop leave the rear pair with the front pair
# 0 to 100 ms from the ground, their front pair with the rear one 75 ms or more, the shipped
# gaits' flights 145 ms or more; the trot taking over with the front pair about to land fell).
FLIGHT_FALL_LEAST = 0.12  # s


def natural_scale(sim: Any) -> float:
    """sqrt(h / ``REFERENCE_HEIGHT``), h the height of the root over its lowest foot in the
    creature's start pose (``Model.q0``: as ``legdsl scale`` scales it, L times as high; a
    ``--drop`` lifts the feet with it): the factor on the handover's times (and 1 over it on its
    rates). 1 for a creature without feet or with its root welded to the world."""
    if not sim.contact_names:
        return 1.0
    height = sim.standing_height(sim.model.q0)  # 0 for a root welded to the world
    return math.sqrt(height / REFERENCE_HEIGHT) if height > 0.0 else 1.0


@dataclass(frozen=True)
class Switch:
    """From time ``t`` on, the run is driven by ``controller``."""

    t: float
    controller: str


def starting_values(
    input_names: Iterable[str],
    param_names: Iterable[str],
    own: Mapping[str, float],
    inputs: Mapping[str, float],
    params: Mapping[str, float],
) -> tuple[dict[str, float], dict[str, float]]:
    """The inputs and parameters a controller starts with, of those it has: its own values
    (``--set CONTROLLER.NAME=V``) over the run's parameters and under the run's commands."""
    has_input, has_param = set(input_names), set(param_names)
    start_inputs = {k: v for k, v in own.items() if k in has_input}
    start_inputs |= {k: v for k, v in inputs.items() if k in has_input}
    start_params = {k: v for k, v in params.items() if k in has_param}
    start_params |= {k: v for k, v in own.items() if k in has_param}
    return start_inputs, start_params


def paths_for(model: Model, controller: str, given: Sequence[PathSpec]) -> list[PathSpec]:
    """The ``--path`` specs that concern one controller of a switching run: those naming one
    of its paths, and a nameless one when it has exactly one path."""
    return resolve_paths(model, controller, [s for s in given if _fits(model, controller, s)])


def check_switch_paths(model: Model, controllers: Sequence[str], given: Sequence[PathSpec]) -> None:
    """Each ``--path`` must concern some controller of the run (else the first one's error)."""
    for spec in given:
        if not any(_fits(model, name, spec) for name in dict.fromkeys(controllers)):
            resolve_paths(model, controllers[0], [spec])  # raises the UsageError saying why


def path_notes(
    model: Model, controls: Mapping[str, ModuleType], first: str, switches: Sequence[Switch],
    given: Sequence[PathSpec], commanded: Iterable[str],
) -> list[str]:  # fmt: skip
    """Notes on the paths of a run of ``controls`` (by name; ``first`` starts it, ``switches``
    change it, ``given`` the ``--path`` specs, ``commanded`` the inputs given a value):
    a lookahead too long for its path's turns (``lookahead_note``; once each, for a path a
    controller steers by the look-ahead of, reading an ``ahead_`` member), and a switch
    from a controller that follows a path to one that follows none: from there the new one
    steers as its inputs say, and a ``heading`` nobody commanded is its default, which may
    lie behind the creature (the biped's gallop after a circle turned back to 0 deg at once,
    spun and fell)."""
    notes: list[str] = []
    for name, module in controls.items():
        for spec in paths_for(model, name, given):
            reads = any(key.startswith(f"path.{spec.name}.ahead_") for key in module.SENSORS)
            note = lookahead_note(spec) if reads else None
            if note is not None and note not in notes:
                notes.append(note)

    def follows(name: str) -> bool:
        return any(p.shape != "none" for p in paths_for(model, name, given))

    running, told = first, set(commanded)
    for w in sorted(switches, key=lambda w: w.t):
        if follows(running) and not follows(w.controller):
            inputs = {c.name: c.value for c in model.controller(w.controller).inputs}
            aim = (
                f"; its heading is its default, {math.degrees(inputs['heading']):g} deg, "
                f"whichever way the path left the creature: give the way it will be going, as "
                f"with --set heading=ANGLE@{w.t:g}s"
                if "heading" in inputs and "heading" not in told
                else ""
            )
            notes.append(
                f"the switch to {w.controller} at {w.t:g} s leaves {running}'s path: "
                f"{w.controller} follows no path and steers as its inputs say{aim}"
            )
        running = w.controller
    return notes


def _fits(model: Model, controller: str, spec: PathSpec) -> bool:
    declared = [p.name for p in model.controller(controller).paths]
    return spec.name in declared or (not spec.name and len(declared) == 1)


def _calm_flight(sim: Any, feet: Mapping[str, Clock], unit: float) -> frozenset[str] | None:
    """If every foot is up, the centre of mass moves up and the root body turns about the
    horizontal slower than ``FLIGHT_TURN_MOST``, the feet that will land soon: those that did
    not just lift off and would fall to the ground within ``FLIGHT_FALL_LEAST`` as they move
    now (a leg's soles count as its foot); else None. Both for the creature's size: times
    ``unit`` (``natural_scale``) as long, rates as much slower."""
    if any(clock.down for clock in feet.values()):
        return None
    w = sim.dyn.body_velocities(sim.q, sim.v)[0][1]  # the root's world angular velocity
    if math.hypot(float(w[0]), float(w[1])) > FLIGHT_TURN_MOST / unit:
        return None
    if float(sim.dyn.center_of_mass_velocity(sim.q, sim.v)[2]) <= 0.0:
        return None
    g = math.sqrt(sum(float(x) ** 2 for x in sim.model.gravity))
    foot = {sole: leg.foot for leg in sim.model.legs for sole in leg.soles}
    soon: set[str] = set()
    for contact, p, v in zip(
        sim.contact_names,
        sim.dyn.contact_positions(sim.q),
        sim.dyn.contact_velocities(sim.q, sim.v),
        strict=True,
    ):
        name = foot.get(contact, contact)
        if name in feet and feet[name].liftoff == sim.t:
            continue  # it leaves the ground now
        h = max(float(p[2]) - sim.ground.height(float(p[0]), float(p[1])), 0.0)
        vz = float(v[2])
        if (vz + math.sqrt(vz * vz + 2.0 * g * h)) / g < FLIGHT_FALL_LEAST * unit:
            soon.add(name)
    return frozenset(soon)


class SwitchingMachine:
    """The controller of a run with switches: the simulation sees one controller."""

    def __init__(
        self,
        model: Model,
        modules: Mapping[str, ModuleType],
        first: str,
        switches: Sequence[Switch],
        inputs: Mapping[str, float],
        params: Mapping[str, float],
        schedule: Sequence[InputChange],
        paths: Sequence[PathSpec] = (),
        by_controller: Mapping[str, Mapping[str, float]] | None = None,
    ):
        self.model = model
        self.modules = dict(modules)
        self.switches = sorted(switches, key=lambda s: s.t)
        order = list(dict.fromkeys([first, *(s.controller for s in self.switches)]))
        self._offset: dict[str, int] = {}
        names: list[str] = []
        for name in order:
            self._offset[name] = len(names)
            names += [f"{name}.{state}" for state in self.modules[name].STATE_NAMES]
        self.state_names = tuple(names)
        self.params_given = dict(params)
        self.by_controller = {k: dict(v) for k, v in (by_controller or {}).items()}
        self.commanded = dict(inputs)  # the latest command of every input, by name
        self._commanded_at: dict[str, float] = {}  # the time each was commanded for (@T)
        self._pending = sorted(schedule, key=lambda c: c.t)
        self._paths = list(paths)  # as given; each controller takes those that concern it
        self._waiting = list(self.switches)
        self.made: list[Switch] = []  # the switches that took over, in order
        # a switch still waiting for a liftoff when the next came due, with the one that did
        self.superseded: list[tuple[Switch, Switch]] = []
        self._pairs: dict[str, list[Pair]] = {}  # each controller's cycle, for the handover
        self.finished: list[tuple[str, StateMachine]] = []
        self.name = first
        self.unit: float | None = None  # natural_scale, from the first tick this machine takes
        self.current = self._machine(first, 0.0)
        self.segments: list[dict[str, Any]] = [self._segment(0.0)]

    # ------------------------------------------------------------ machines
    def _machine(self, name: str, t: float) -> StateMachine:
        module = self.modules[name]
        own = module.INPUTS
        inputs, params = starting_values(
            own, module.PARAMS, self.by_controller.get(name, {}), self.commanded, self.params_given
        )
        # the first machine applies the whole schedule itself; a later one what is still to come
        later = [
            c
            for c in self._pending
            if c.name in own and (t == 0.0 or c.t > t + 1e-12) and not self._with_switch(c)
        ]
        paths = paths_for(self.model, name, self._paths)
        return StateMachine(self.model, module, inputs, params, later, paths)

    def _segment(self, t: float) -> dict[str, Any]:
        m = self.current
        return {
            "controller": self.name,
            "from": round(t, 9),
            "inputs": dict(zip(m.input_names, m.inputs, strict=True)),
            "params": dict(zip(m.param_names, m.params, strict=True)),
        }

    def _ready(self, switch: Switch, sim: Any) -> bool:
        """Whether the controller of a due ``switch`` takes over now (``HANDOVER_WAIT``)."""
        t, unit = sim.t, self._unit(sim)
        if t >= switch.t + HANDOVER_WAIT * unit - 1e-12 or sim.ground is None:
            return True
        pairs = self._cycle(switch.controller)
        if not lifts_off(pairs):
            return True
        self.current.sensors.observe(
            t, sim.ground.touching
        )  # this tick's contacts (it is idempotent)
        feet = self.current.feet()
        if t >= switch.t + FLIGHT_WAIT * unit - 1e-12:
            return on_liftoff(pairs, feet, t)
        soon = _calm_flight(sim, feet, unit)
        return soon is not None and on_liftoff(pairs, feet, t, soon)

    def _unit(self, sim: Any) -> float:
        if self.unit is None:
            self.unit = natural_scale(sim)
        return self.unit

    def _cycle(self, controller: str) -> list[Pair]:
        if controller not in self._pairs:
            self._pairs[controller] = cycle(self.model, self.model.controller(controller))
        return self._pairs[controller]

    def _switch(self, to: str, t: float) -> None:
        old = self.current
        new = self._machine(to, t)
        # an input nobody commanded keeps the new controller's own default: the gallop's
        # apex `height` is its 0.681 m, not the 0.64 m the trot's default was
        values = [
            float(self.commanded.get(n, v))
            for n, v in zip(new.input_names, new.inputs, strict=True)
        ]
        new.start_inputs(values, t)
        # integral(INPUT) goes on from the old controller's for an input both have (a turn
        # keeps its heading), else from the takeover
        for i, name in enumerate(new.input_names):
            if name in old.input_names:
                j = old.input_names.index(name)
                new.integrals[i] = replace(old.integrals[j])
                new.integrals[i].change(old.inputs[j], new.inputs[i], t)
            else:
                new.integrals[i] = Integral(since=t)
        own = set(self.model.controller(to).own)  # learned with its own gains: from 0
        records = {
            n: r for n, r in zip(old.module.RECORDS, old.records, strict=True) if n not in own
        }
        new.records = [float(records.get(n, 0.0)) for n in new.module.RECORDS]
        carried = {n: records[n] for n in new.module.RECORDS if n in records}
        new.sensors.clocks = old.sensors.clocks
        new.sensors.leg_clocks = old.sensors.leg_clocks
        for path, tracker in old.sensors.paths.items():
            mine = next((p for p in new.paths if p.name == path), None)
            if mine is not None and mine == tracker.spec:
                new.sensors.paths[path] = tracker
        new.taking_over = True
        self.finished.append((self.name, old))
        self.segments[-1]["to"] = round(t, 9)
        self.current, self.name = new, to
        self.segments.append(self._segment(t) | {"records_carried": carried})

    def _with_switch(self, change: InputChange) -> bool:
        """Whether a command is given at the time of a switch still to come: it goes with the
        new controller, when that takes over (``--switch 6s=bound --set speed=2.8m/s@6s``)."""
        return any(abs(w.t - change.t) < 1e-9 for w in self._waiting)

    def _command(self, t: float, switch: Switch | None = None) -> None:
        """The commands due at ``t`` (those of ``switch`` too) into ``commanded``."""
        for change in [c for c in self._pending if c.t <= t + 1e-12]:
            if not self._with_switch(change) or (switch is not None and change.t == switch.t):
                self._pending.remove(change)
                # a switch's command, held until it takes over, loses to one for a later time
                if change.t >= self._commanded_at.get(change.name, -math.inf):
                    self.commanded[change.name] = change.value
                    self._commanded_at[change.name] = change.t

    def __call__(self, sim: Any) -> None:
        t = sim.t
        self._unit(sim)
        self._command(t)
        # a switch still waiting when the next comes due never takes over: the later one asked
        # for is the one wanted now (else the run would change twice on one tick)
        while len(self._waiting) > 1 and self._waiting[1].t <= t + 1e-12:
            gone = self._waiting.pop(0)
            self.superseded.append((gone, self._waiting[0]))
        while (
            self._waiting and self._waiting[0].t <= t + 1e-12 and self._ready(self._waiting[0], sim)
        ):
            switch = self._waiting[0]
            self._command(t, switch)
            self.made.append(self._waiting.pop(0))
            self._switch(switch.controller, t)
            if abs(t - switch.t) > 1e-9:
                self.segments[-1]["asked"] = switch.t
        self.current(sim)

    def segment_info(self, end: float) -> list[dict[str, Any]]:
        """One entry per controller segment for run.json: its controller, its time range, the
        inputs and parameters it started with, and the state it started in."""
        machines = [m for _, m in self.finished] + [self.current]
        out = []
        for k, (seg, machine) in enumerate(zip(self.segments, machines, strict=True)):
            first = next((e for e in machine.events if e.get("kind") == "state"), None)
            entry = dict(seg, to=seg.get("to", round(end, 9)))
            entry["state"] = first["state"] if first is not None else None
            if k > 0:
                roles = self.model.controller(seg["controller"]).bindings[machine.binding_at_start]
                entry["roles"] = {role: list(legs) for role, legs in roles}
            out.append(entry)
        return out

    @property
    def state_offset(self) -> int:
        """Where the current controller's states start in the run's numbering."""
        return self._offset[self.name]

    def own_ticks(self, has_ground: bool) -> tuple[float, float, float]:
        """Which ticks this machine must take itself, the current controller's machine taking
        the others alone (in C: ``switching_tick`` in step.c): those from the next command's
        time on (or the time of the switch after the next, which supersedes it if it still
        waits); from the next switch's time, those at a foot's liftoff until the third time
        (``_ready`` waits for one), then all."""
        commands = [c.t for c in self._pending if not self._with_switch(c)]
        command_at = min([*commands, *(w.t for w in self._waiting[1:2])], default=math.inf)
        if not self._waiting:
            return command_at, math.inf, math.inf
        switch = self._waiting[0]
        waits = has_ground and lifts_off(self._cycle(switch.controller))
        if not waits or self.unit is None:  # (before its first tick: every tick from switch.t)
            return command_at, switch.t, switch.t
        return command_at, switch.t, switch.t + HANDOVER_WAIT * self.unit

    @property
    def first(self) -> StateMachine:
        """The machine of the controller the run started with."""
        return self.finished[0][1] if self.finished else self.current

    # ------------------------------------------------------------ what the simulation reads
    @property
    def state_index(self) -> int:
        return self.state_offset + self.current.state_index

    def speed_command(self, t: float) -> float:
        return self.current.speed_command(t)

    @property
    def events(self) -> list[dict[str, Any]]:
        out: list[dict[str, Any]] = []
        for name, machine in [*self.finished, (self.name, self.current)]:
            out += [dict(e, controller=name) for e in machine.events]
        for seg in self.segments[1:]:
            out.append({"t": seg["from"], "kind": "switch", "controller": seg["controller"]})
        return out

    @property
    def paths(self) -> list[PathSpec]:
        """Every path a controller of the run followed (by name, the first of each)."""
        seen: dict[str, PathSpec] = {}
        for _name, machine in [*self.finished, (self.name, self.current)]:
            for p in machine.paths:
                seen.setdefault(p.name, p)
        return list(seen.values())


def running_at_end(machine: StateMachine | SwitchingMachine) -> tuple[StateMachine, float]:
    """The machine that drives a run at its end, and when its inputs last changed: its
    takeover or its start, or a command given after it (``--set NAME=V@T``)."""
    last = machine.current if isinstance(machine, SwitchingMachine) else machine
    return last, last._history[-1][0]
