"""The quadruped's transition run (docs/quadruped.md, "Changing gait"), its schedule shifted.

    python docs/scripts/quadruped_transition.py                       # the four shifted runs
    python docs/scripts/quadruped_transition.py --more                # and eleven more takeovers
    python docs/scripts/quadruped_transition.py --set trot.decel=2m/s^2 --more

The issue's run is the trot at 2 m/s, the bound at 2.8 m/s from 6 s, the gallop at 4 m/s from
12 s and the trot at 2 m/s from 18 s, for 24 s, each speed commanded with its switch. Shifted
by d, every switch and its command move by d (the first switch at 5.8, 6.0, 6.3 and 6.6 s);
``--more`` also moves the last switch alone by e, for takeovers by the last trot at other
moments of the gallop's stride (eleven more, each taking over at a different time). Each
segment's speed is the root's along x from 3 s after it took over (the first from 3 s) to the
next takeover (the last to the end of the run), against its command. The runs go through the
API in two threads on the C backend.
"""

from __future__ import annotations

import argparse
import tempfile

import numpy as np

import legdsl

GAITS = (("trot", 2.0), ("bound", 2.8), ("gallop", 4.0), ("trot", 2.0))  # from 0, 6, 12, 18 s
SHIFTED = [(d, 0.0) for d in (-0.2, 0.0, 0.3, 0.6)]  # (d, e): the first switch at 6 + d s
MORE = [(-0.2, -0.25), (-0.2, 0.3), (-0.2, 0.6), (0.0, 0.2), (0.0, 0.45), (0.0, 0.6),
        (0.3, -0.25), (0.3, 0.2), (0.3, 0.6), (0.6, -0.25), (0.6, 0.45)]  # fmt: skip
DURATION = 24.0  # s


def plan(d: float, e: float, extra: dict[str, str]) -> dict:
    """The run's arguments for ``Creature.run``: the issue's schedule shifted by d, its last
    switch by e more."""
    sets = {"speed": f"{GAITS[0][1]} m/s"}
    switch = {}
    for k, (name, speed) in enumerate(GAITS[1:], start=1):
        t = round(6 * k + d + (e if k == len(GAITS) - 1 else 0.0), 6)
        switch[f"{t} s"] = name
        sets[f"speed@{t}s"] = f"{speed} m/s"
    return {"controller": GAITS[0][0], "set": sets | extra, "switch": switch, "time": DURATION}


def errors(run: legdsl.Run) -> list[tuple[float, float]]:
    """Each segment's takeover time and relative speed error (NaN past a fall)."""
    t, x = run.samples["t"], run.samples["q.x"]
    segments = run.info["segments"]
    out = []
    for k, seg in enumerate(segments):
        start = seg["from"] + 3.0 if k else 3.0
        end = segments[k + 1]["from"] if k + 1 < len(segments) else DURATION
        i, j = int(np.searchsorted(t, start)), int(np.searchsorted(t, end)) - 1
        ok = run.status == "ok" or k + 1 < len(segments)
        speed = (x[j] - x[i]) / (t[j] - t[i]) if ok and j > i else float("nan")
        out.append((seg["from"], speed / GAITS[k][1] - 1.0))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--file", default="creatures/quadruped.leg")
    parser.add_argument("--set", action="append", default=[], help="NAME=VALUE, as legdsl run")
    parser.add_argument("--more", action="store_true", help="eleven more takeovers")
    args = parser.parse_args()
    extra = dict(s.split("=", 1) for s in args.set)
    creature = legdsl.load(args.file, generated=tempfile.mkdtemp(prefix="quadruped-transition-"))
    schedules = SHIFTED + (MORE if args.more else [])
    results = dict(creature.run_many([plan(d, e, extra) for d, e in schedules], threads=2))
    print("first switch  last switch  outcome         " + "  ".join(
        f"{name:>16s}" for name, _ in GAITS))  # fmt: skip
    last = []
    for n, (d, e) in enumerate(schedules):
        run = results[n]
        outcome = "holds" if run.status == "ok" else f"falls at {run.info['sim_time']:.2f} s"
        cells = "  ".join(f"{t:7.3f} s {err * 100:+5.1f}%" for t, err in errors(run))
        print(f"{6 + d:10.1f} s  {18 + d + e:9.2f} s  {outcome:15s} {cells}")
        last.append(errors(run)[-1][1] if len(run.info["segments"]) == len(GAITS) else np.nan)
    held = np.array([err for err in last if not np.isnan(err)])
    print(f"last trot: {len(last) - len(held)} of {len(last)} fall; of those that hold, "
          f"{int(np.sum(np.abs(held) > 0.05))} are off by more than 5%, "
          f"mean |error| {np.mean(np.abs(held)) * 100:.1f}%")  # fmt: skip


if __name__ == "__main__":
    main()
