"""Notes on an ``ok`` run that visibly did not do what was asked (``legdsl run``: after its table).

A run that ends ``ok`` has only not fallen: a controller whose table waited in one state for an
event that never came (a longer leg never reaching the length its table waits for) stood still
to the end, and a speed command the controller could not follow (a gallop told to run backwards)
ran another speed, both with the same quiet ``ok``. Two checks read what the run recorded (its
events and its trajectory), whatever the creature:

* **stuck**: the controller entered its last state (or took over) ``STUCK`` s or more before the
  end, and a quarter of the run or more: the note names the state, since when, and the event it
  waits for (the next row's, as the table is written);
* **speed**: the forward speed (the centre of mass's along the heading) averaged from ``SETTLE``
  after the last change of the speed command or of the controller to the end (a window of
  ``SHORTEST`` or more: ``legdsl.analysis.segments``) differs from the command by more than
  ``SPEED_SHARE`` of it and more than ``SPEED_MARGIN``; only where the controller has a
  ``speed`` input. Where the speed still changes toward the command at the end (a straight
  line fitted to the window rises toward it by more than ``SPEED_MARGIN`` and a quarter of the
  miss: a kangaroo 3 s into a hop from standing), the note says so and to run longer, not that
  the controller did not follow;
* **turn**: where the controller running at the end has a ``turn_rate`` input and follows no
  path, the heading rate (a straight line fitted to the trunk's yaw, unwrapped) from ``SETTLE``
  after the last change of its inputs or of the controller to the end (a window of
  ``SHORTEST`` or more) differs from the commanded ``turn_rate`` by more than ``TURN_SHARE``
  of it and more than ``TURN_MARGIN`` (a gait that spins, or turns the other way). This one
  is told on a run that fell too, measured to the fall: a controller that cannot turn may
  fall for it (the quadruped's bound: docs/quadruped.md, "Turning");
* **path**: a path the run followed, its lateral deviation RMS (its path report's, from the
  report's start) more than ``PATH_MARGIN`` or half the path's spread, whichever is less (the
  report's ``note``: ``legdsl.analysis.path_report.off_path_limit``).

The times, ``SPEED_MARGIN``, ``TURN_MARGIN`` and ``PATH_MARGIN`` (the path report's) are for a
creature standing 0.81 m, and follow the run's size (its ``time_unit``, √(height / 0.81 m): a
speed scales as a time does, a rate as its inverse, a length as its square, Table 1).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from legdsl.analysis.segments import SETTLE, SHORTEST, segment_report
from legdsl.analysis.strides import EPS_T
from legdsl.lang.scaling import factor
from legdsl.lang.units import KINDS
from legdsl.sim.switching import running_at_end

STUCK = 2.0  # s: a gait's states last tenths of a second; a state held this long is waiting
STUCK_SHARE = 0.25  # ... and for this share of the run or more (a short run is told nothing)
SPEED_SHARE = 0.25  # the measured speed off the command by more than this share of it
SPEED_MARGIN = 0.5  # m/s, and by more than this (a command of 0 has no share)
TURN_SHARE = 0.25  # the measured heading rate off the command by more than this share of it
TURN_MARGIN = 3.0  # deg/s, and by more than this (the shipped gaits that turn: within 1)


def run_notes(run: Any) -> list[str]:
    """The notes on ``run`` (a ``legdsl.pipeline.session.Run``): none unless it ended ``ok``,
    but for the turn note of one that fell."""
    result = run.result
    if result.status not in ("ok", "fell") or not len(result.trajectory):
        return []
    unit = float(run.time_unit or 1.0)
    if result.status == "fell":
        return [n for n in [_off_turn(run, unit)] if n]
    notes = [
        _stuck(run, unit),
        _off_speed(run, unit),
        _off_turn(run, unit),
        *(_off_path(r, unit) for r in run.path_reports),
    ]
    return [n for n in notes if n]


def _controller_at_end(run: Any) -> str | None:
    switched = [e["controller"] for e in run.result.events if e["kind"] == "switch"]
    return switched[-1] if switched else run.controller


def _stuck(run: Any, unit: float) -> str:
    events = run.result.events
    entered = [e for e in events if e["kind"] == "state"]
    if not entered:
        return ""  # a passive run, or no table
    marks = [e["t"] for e in events if e["kind"] in ("state", "switch")]
    since, end = max(marks), run.result.sim_time
    held = end - since
    if held < STUCK * unit - 1e-9 or held < STUCK_SHARE * end:
        return ""
    state = entered[-1]["state"]
    return (
        f"the controller sat in {state} from {since:.3f} s to the end of the run "
        f"({held:.3f} s, {100 * held / end:.0f}% of it){_waiting_for(run, state)}: the run is "
        "ok only in not having fallen; the table's event never came (see the state and the "
        "signals it reads in trajectory.csv, and the table's numbers against this creature's)"
    )


def _waiting_for(run: Any, state: str) -> str:
    """The event the table waits for in ``state`` (its next row's), as a clause, else ""."""
    name = _controller_at_end(run)
    table = next((c for c in run.model.controllers if c.name == name), None)
    names = [s.name for s in table.states] if table is not None else []
    if table is None or state not in names or len(names) < 2:
        return ""
    nxt = table.states[(names.index(state) + 1) % len(names)]
    return f", waiting for the event of its next row, {nxt.name}'s '{nxt.event_text}'"


def _off_speed(run: Any, unit: float) -> str:
    tr = run.result.trajectory
    command = tr.speed_command
    if not np.isfinite(command).any():
        return ""  # the controller has no speed input (or there is none)
    same = (command[1:] == command[:-1]) | (np.isnan(command[1:]) & np.isnan(command[:-1]))
    changed = [float(tr.t[i + 1]) for i in np.flatnonzero(~same)]
    switched = [e["t"] for e in run.result.events if e["kind"] == "switch"]
    start = max([float(tr.t[0]), *changed, *switched])
    report = segment_report(tr, [{"from": start, "to": run.result.sim_time}], unit)[0]
    speed, asked = report["speed"], report["command"]
    if speed is None or asked is None:
        return ""  # too short a window since the last change, or no command in it
    off = abs(speed - asked)
    if off <= SPEED_SHARE * abs(asked) or off <= SPEED_MARGIN * unit:
        return ""
    way = ", the other way" if speed * asked < 0 and abs(speed) > SPEED_MARGIN * unit else ""
    since = report["measured_from"]
    told = (
        f"the speed command was {_speed(asked)} m/s and the forward speed {_speed(speed)} m/s "
        f"(mean from {since:g} s to the end){way}"
    )
    rise = _rise(tr, since, run.result.sim_time)
    if rise * (asked - speed) > 0 and abs(rise) > max(SPEED_MARGIN * unit, off / 4):
        how = "speeding up" if abs(speed + rise / 2) > abs(speed - rise / 2) else "slowing down"
        return (
            f"{told}, still {how} toward it at the end ({_speed(rise)} m/s over that time): "
            "the run ended before the speed settled; run longer to see whether the controller "
            "reaches the command"
        )
    return (
        f"{told}: the run is ok only in not having fallen; the controller did not follow this "
        "command (try another command, or another controller)"
    )


def _off_turn(run: Any, unit: float) -> str:
    """The turn note: the heading rate measured against the ``turn_rate`` commanded."""
    if getattr(run, "machine", None) is None:
        return ""
    machine, since = running_at_end(run.machine)
    if "turn_rate" not in machine.input_names or any(p.shape != "none" for p in machine.paths):
        return ""  # no turn command, or a path steers it (the path note tells that)
    asked = machine.inputs[machine.input_names.index("turn_rate")]
    if run.scale is not None:  # the machine ran the file's creature: into the scaled one's
        asked *= factor(KINDS["angular velocity"][0], run.scale)
        since *= factor(KINDS["time"][0], run.scale)
    tr, end = run.result.trajectory, run.result.sim_time
    start = since + SETTLE * unit
    window = (tr.t >= start - EPS_T) & (tr.t < end - EPS_T)
    t = np.asarray(tr.t[window], dtype=float)
    if end - start < SHORTEST * unit - EPS_T or len(t) < 3 or t[-1] <= t[0]:
        return ""
    yaw = np.unwrap(np.asarray(tr.root_rpy[window, 2], dtype=float))
    rate = float(np.polyfit(t - t[0], yaw, 1)[0])
    off, margin = abs(rate - asked), np.radians(TURN_MARGIN) / unit
    if not np.isfinite(rate) or off <= TURN_SHARE * abs(asked) or off <= margin:
        return ""
    way = ", the other way" if rate * asked < 0 and abs(rate) > margin else ""
    ended = "the fall" if run.result.status == "fell" else "the end"
    told = (
        f"the turn_rate command was {_speed(np.degrees(asked))} deg/s and the heading turned at "
        f"{_speed(np.degrees(rate))} deg/s (from {start:g} s to {ended}){way}"
    )
    if run.result.status == "fell":
        return f"{told}: this controller did not follow the turn command before it fell"
    return (
        f"{told}: the run is ok only in not having fallen; the controller did not follow this "
        "command (try another turn_rate, or another controller)"
    )


def _rise(tr: Any, start: float, end: float) -> float:
    """How much the forward speed changed over [start, end): a straight line's, fitted to the
    samples (a hop's rise and fall within a stride is noise about it), 0 with too few."""
    window = (tr.t >= start - 1e-9) & (tr.t < end - 1e-9)
    t = np.asarray(tr.t[window], dtype=float)
    if len(t) < 3 or t[-1] <= t[0]:
        return 0.0
    yaw = tr.root_rpy[window, 2]
    forward = tr.com_vel[window, 0] * np.cos(yaw) + tr.com_vel[window, 1] * np.sin(yaw)
    slope = np.polyfit(t - t[0], forward, 1)[0]
    return float(slope * (t[-1] - t[0])) if np.isfinite(slope) else 0.0


def _speed(x: float) -> str:
    if abs(x) >= 1e6:  # a command of 1e308 m/s is not told in 309 digits
        return f"{x:.3g}"
    return f"{round(x, 2) + 0.0:.2f}"  # -2e-19 (standing still) is 0.00


def _off_path(report: dict[str, Any], unit: float) -> str:
    """The path report's note on a path the run kept off (it measured with ``unit``)."""
    note = report.get("note")
    return f"{note}; the run is ok only in not having fallen" if note else ""
