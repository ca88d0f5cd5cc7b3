"""What limits the quadruped's gallop at a speed: its touchdowns, its speed trim, its hips.

    python docs/scripts/gallop_limits.py --speed 5 --time 20 --from 12

Runs the gallop once on the Python backend (bit-identical to the C one), watching the
controller at every control tick, and prints, from ``--from`` on:

* per leg, at each touchdown: the foot's speed over the ground just before it, its placement
  ahead of its hip, and the horizontal impulse of the ground in the stance's first 10 ms and
  over the whole stance (N*s; the creature weighs 20 kg, so 4 N*s is 0.2 m/s), with the pitch
  moment of that first 10 ms about the centre of mass (N*m*s; positive pitches the nose down);
* per leg, the hip servo's setpoint and angle at touchdown and its largest torque in the swing
  before it (against the servo's ``max``), and the share of the stance in which the hip's
  posture torque (``hip_S_motor``) is at its ``max``;
* the records that set the foot placement and the thrust at each liftoff (``speed_trim``,
  ``ramped_speed``, ``step_speed``, ``thrust_stroke``, ``pitch_trim``, ``pitch_mean``),
  every fourth.
"""

from __future__ import annotations

import argparse
import math
import os
import tempfile
from typing import Any

import numpy as np

import legdsl
from legdsl.sim import machine

LEGS = ("fl", "fr", "rl", "rr")  # the quadruped's legs, in the order of its contacts
SHOWN = ("step_speed", "speed_trim", "ramped_speed", "thrust_stroke", "pitch_trim", "pitch_mean")


def watch(ticks: list[dict[str, Any]]) -> None:
    """Record the controller's records and each hip's servo and motor at every tick."""
    step = machine.StateMachine.__call__

    def watched(self: machine.StateMachine, sim: Any) -> None:
        step(self, sim)
        by = sim.actuators.by_name
        row: dict[str, Any] = {"t": sim.t, "state": self.state_index}
        row["records"] = dict(zip(self.module.RECORDS, self.records, strict=True))
        for leg in LEGS:
            servo = by[f"hip_{leg}_pitch"]
            row[leg] = (servo.target, sim.q[servo.q_index], servo.last_force,
                        by[f"hip_{leg}_motor"].last_force)  # fmt: skip
        ticks.append(row)

    machine.StateMachine.__call__ = watched


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--file", default="creatures/quadruped.leg")
    parser.add_argument("--controller", default="gallop")
    parser.add_argument("--speed", type=float, default=5.0, help="m/s")
    parser.add_argument("--time", type=float, default=20.0, help="s")
    parser.add_argument("--from", dest="start", type=float, default=12.0, help="s")
    args = parser.parse_args()
    os.environ["LEGDSL_BACKEND"] = "python"
    ticks: list[dict[str, Any]] = []
    watch(ticks)
    creature = legdsl.load(args.file, generated=tempfile.mkdtemp(prefix="gallop-limits-"))
    run = creature.run(controller=args.controller, set={"speed": f"{args.speed} m/s"},
                       time=args.time, record_rate=0)  # fmt: skip
    print(f"{args.controller} at {args.speed} m/s for {args.time} s: {run.status}")
    tr, s = run.trajectory, run.samples
    dyn, model = creature.session.dynamics, creature.session.model
    hips = {leg.name: model.leg_hip(leg) for leg in model.legs}
    limits = {a.name: a.max for a in model.actuators}
    t = s["t"]
    dt = float(np.diff(t).mean())
    tick_t = np.array([row["t"] for row in ticks])
    print(f"servo max {limits['hip_fl_pitch']} N*m, motor max {limits['hip_fl_motor']} N*m")
    print("leg  touchdowns  foot speed  foot ahead of hip  impulse 10 ms  stance  pitch moment 10 ms"
          "  | hip setpoint  angle  swing peak  motor at limit")  # fmt: skip
    for c, leg in enumerate(LEGS):
        down = tr.contact[:, c] != 0
        starts = np.flatnonzero(down[1:] & ~down[:-1]) + 1
        stops = np.flatnonzero(~down[1:] & down[:-1]) + 1
        rows = []
        for a in starts:
            after = stops[stops > a]
            if t[a] < args.start or not len(after):
                continue
            b = int(after[0])
            q, v = [float(x) for x in tr.q[a - 1]], [float(x) for x in tr.v[a - 1]]
            foot = dyn.contact_positions(q)[c]
            speed = float(np.hypot(*dyn.contact_velocities(q, v)[c][:2]))
            hip = hips[leg].point(dyn.body_poses(q))[0]
            first = a + int(round(0.010 / dt))
            fx = tr.force[a:b, c, 0]
            early = float(fx[: first - a].sum() * dt)
            arm = float(foot[2] - tr.com[a - 1, 2])  # the foot below the centre of mass
            k = int(np.searchsorted(tick_t, t[a])) - 1
            lifted = stops[stops < a]
            k0 = int(np.searchsorted(tick_t, t[lifted[-1]])) if len(lifted) else k
            peak = max(abs(ticks[j][leg][2]) for j in range(k0, k + 1))
            stance = [
                abs(ticks[j][leg][3]) for j in range(k + 1, int(np.searchsorted(tick_t, t[b])))
            ]
            rows.append((speed, foot[0] - hip, early, float(fx.sum() * dt), arm * early,
                         math.degrees(ticks[k][leg][0]), math.degrees(ticks[k][leg][1]), peak,
                         float(np.mean(np.array(stance) >= limits[f"hip_{leg}_motor"] - 1e-6)) if stance else 0.0))  # fmt: skip
        m = np.array(rows).mean(axis=0)
        print(f"{leg:4} {len(rows):10d}  {m[0]:6.2f} m/s  {m[1]:+13.3f} m  {m[2]:+9.2f} N*s"
              f"  {m[3]:+6.2f}  {m[4]:+14.2f}      | {m[5]:+8.1f} deg {m[6]:+6.1f}"
              f"  {m[7]:6.0f} N*m  {m[8]:8.2f}")  # fmt: skip
    print("liftoff  " + "  ".join(f"{n:>13}" for n in SHOWN))
    entries = [
        row
        for k, row in enumerate(ticks)
        if row["state"] == 0 and (k == 0 or ticks[k - 1]["state"] != 0)
    ]
    for row in entries[::4]:
        if row["t"] >= args.start - 8:
            print(f"{row['t']:7.2f}  " + "  ".join(f"{row['records'][n]:13.3f}" for n in SHOWN))


if __name__ == "__main__":
    main()
