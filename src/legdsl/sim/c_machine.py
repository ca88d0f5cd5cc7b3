"""A state machine's state as the C runtime keeps it (``legdsl_sim.h``'s ``ctl_*`` fields and
arrays) and back: the single run's hand-overs (``legdsl.sim.c_backend``) and a batch's copy at
its end (``legdsl.pipeline.batch``) read and write it the same way.

``keep`` is the struct's arrays by field name (a single run's, or one copy's rows of a batch's),
``schedule`` the machine's whole input schedule, of which C keeps its place (``sched_pos``).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from legdsl.ir.paths import MEMBERS
from legdsl.sim.machine import InputChange, Integral, StateMachine


def push_machine(
    m: StateMachine, c: Any, keep: Mapping[str, np.ndarray], schedule: Sequence[InputChange]
) -> None:
    """The machine's state into the struct ``c`` and its arrays, for C to go on from."""
    c.ctl_started, c.ctl_state, c.ctl_binding = int(m.started), m.state_index, m.binding
    c.ctl_entered_at = m.entered_at
    keep["ctl_records"][: len(m.records)] = m.records
    keep["ctl_inputs"][: len(m.inputs)] = m.inputs
    keep["ctl_integral"][: 2 * len(m.inputs)] = m.integral_state()
    c.sched_pos = len(schedule) - len(m.schedule)
    for k, tracker in enumerate(m.sensors.paths.values()):
        values = [tracker.values[name] for name in MEMBERS]
        keep["path_state"][12 * k : 12 * k + 12] = [tracker.progress, tracker._last_s, *values]
    for i, clock in enumerate(_clocks(m)):
        keep["clocks"][5 * i : 5 * i + 5] = [float(clock.touching), clock.touchdown,
                                             clock.liftoff, clock.stance, clock.flight]  # fmt: skip


def pull_machine(
    m: StateMachine, c: Any, keep: Mapping[str, np.ndarray], schedule: Sequence[InputChange]
) -> None:
    """The machine as C left it: its state, records, inputs, integrals, schedule, path
    trackers and clocks, with the input history and state events C gathered since the last
    pull appended (the caller empties C's, ``n_hist`` and ``n_ctl_events``, if C goes on)."""
    m.started, m.state_index = bool(c.ctl_started), int(c.ctl_state)
    m.binding = int(c.ctl_binding)
    m.entered_at = float(c.ctl_entered_at)
    m.records = keep["ctl_records"][: len(m.records)].tolist()
    m.inputs = keep["ctl_inputs"][: len(m.inputs)].tolist()
    state = keep["ctl_integral"].tolist()
    m.integrals = [Integral(*state[2 * i : 2 * i + 2]) for i in range(len(m.inputs))]
    m.schedule = list(schedule[int(c.sched_pos) :])
    for k, tracker in enumerate(m.sensors.paths.values()):
        state = keep["path_state"][12 * k : 12 * k + 12].tolist()
        tracker.progress, tracker._last_s = state[0], state[1]
        if tracker.geometry is not None:
            tracker.values = dict(zip(MEMBERS, state[2:], strict=True))
    for i, clock in enumerate(_clocks(m)):
        touching, *times = keep["clocks"][5 * i : 5 * i + 5].tolist()
        clock.touchdown, clock.liftoff, clock.stance, clock.flight = times
        clock.touching = touching != 0.0
    ni = len(m.inputs)
    for k in range(int(c.n_hist)):
        values = keep["hist_inputs"][k * ni : (k + 1) * ni].tolist()
        m._history.append((float(keep["hist_t"][k]), values))
    n = int(c.n_ctl_events)
    m.events += state_events(keep["ctl_event_t"][:n], keep["ctl_event_state"][:n], m.state_names)


def state_events(
    times: np.ndarray, states: np.ndarray, names: Sequence[str]
) -> list[dict[str, Any]]:
    """The state events C recorded (the times, the indices of the states entered), as the
    Python state machine writes them."""
    return [{"t": round(float(t), 9), "kind": "state", "state": names[int(s)]}
            for t, s in zip(times, states, strict=True)]  # fmt: skip


def _clocks(m: StateMachine) -> list[Any]:
    """The contacts' clocks, then the legs', in the order of the struct's ``clocks``."""
    return [*m.sensors.clocks.values(), *m.sensors.leg_clocks.values()]
