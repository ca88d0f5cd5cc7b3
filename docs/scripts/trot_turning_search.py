"""The search that found the trot's turning and roll gains (creatures/quadruped.leg, trot).

    nice python docs/scripts/trot_turning_search.py --start START.json --generations 20 --seed 6

CMA-ES (pycma) over eleven of the trot's gains, each scaled to [0, 1] within its bounds
(SPACE), through the Python API. A candidate runs five times: a 5 m circle and an 8 m square
at 1.5 m/s for 30 s (``--path``), and straight runs at 2.3 and 2.6 m/s for 20 s and at 1 m/s
for 10 s. A path run scores its lateral deviation (RMS, from 3 s) plus its relative speed
error along the path, a straight run its relative speed error from 3 s; a run that falls at
t of T scores 10 + (T - t) / T. The objective is 2 x circle + 0.5 x square + the straight
runs' sum (the square's corners make its deviation large whatever the gains). It prints
each generation's best and, at the end, the best values as JSON (``--start`` takes such a
file to go on from; without it the search starts from the shared part's values).
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import cma
import numpy as np

import legdsl

CIRCLE = "circle(center = (0, 5) m, radius = 5 m, turn = left)"
SQUARE = "square(corner = (0, 0) m, side = 8 m, turn = left, lookahead = 2 m)"
SPEED = 1.5  # m/s, on the paths
SPACE = {  # name: (low, high, unit)
    "kp_yaw": (2, 60, "N*m/rad"), "kv_yaw": (1, 30, "N*m*s/rad"), "k_turn": (0, 3, ""),
    "yaw_lead": (0, 0.5, "s"), "turn_most": (1, 15, "deg"), "k_path": (0.1, 2, "m^-1"),
    "turn_limit": (5, 40, "deg"), "k_aim_rate": (0, 1.5, ""), "k_side_trim": (0, 0.6, ""),
    "kp_roll": (100, 500, "N*m/rad"), "kv_roll": (5, 50, "N*m*s/rad"),
}  # fmt: skip
SHARED = {"kp_yaw": 15, "kv_yaw": 10, "k_turn": 1.5, "yaw_lead": 0.2, "turn_most": 6,
          "k_path": 1, "turn_limit": 20, "k_aim_rate": 1, "k_side_trim": 0.3, "kp_roll": 200,
          "kv_roll": 20}  # fmt: skip


def settings(values: dict[str, float], speed: float) -> dict[str, str]:
    return {"speed": f"{speed} m/s"} | {n: f"{v} {SPACE[n][2]}".strip() for n, v in values.items()}


def fell(run: legdsl.Run, duration: float) -> float | None:
    if run.status == "ok":
        return None
    return 10 + (duration - float(run.info.get("sim_time", 0.0))) / duration


def on_path(creature: legdsl.Creature, values: dict[str, float], path: str) -> float:
    run = creature.run(controller="trot", set=settings(values, SPEED), time=30.0, path=path)
    penalty = fell(run, 30.0)
    if penalty is not None:
        return penalty
    report = run.info["path_reports"][0]
    return float(report["lateral_rms"] + abs(report["path_speed"] - SPEED) / SPEED)


def straight(creature: legdsl.Creature, values: dict[str, float], speed: float, t: float) -> float:
    run = creature.run(controller="trot", set=settings(values, speed), time=t)
    penalty = fell(run, t)
    if penalty is not None:
        return penalty
    times, x = run.samples["t"], run.samples["q.x"]
    i = int(np.searchsorted(times, 3.0))
    return float(abs((x[-1] - x[i]) / (times[-1] - times[i]) - speed) / speed)


def objective(creature: legdsl.Creature, values: dict[str, float]) -> float:
    return (
        2 * on_path(creature, values, CIRCLE)
        + 0.5 * on_path(creature, values, SQUARE)
        + straight(creature, values, 2.3, 20.0)
        + straight(creature, values, 2.6, 20.0)
        + straight(creature, values, 1.0, 10.0)
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--file", default="creatures/quadruped.leg")
    parser.add_argument("--start", help="a JSON file with 'values' to start from")
    parser.add_argument("--generations", type=int, default=20)
    parser.add_argument("--seed", type=int, default=6)
    parser.add_argument("--step", type=float, default=0.12, help="CMA-ES's first step in [0, 1]")
    args = parser.parse_args()
    creature = legdsl.load(args.file)
    start = json.loads(Path(args.start).read_text())["values"] if args.start else SHARED
    scale = {n: (lo, hi) for n, (lo, hi, _) in SPACE.items()}

    def values(x: list[float]) -> dict[str, float]:
        return {
            n: lo + min(max(xi, 0.0), 1.0) * (hi - lo)
            for xi, (n, (lo, hi)) in zip(x, scale.items(), strict=True)
        }

    x0 = [(start[n] - lo) / (hi - lo) for n, (lo, hi) in scale.items()]
    print(f"start: {objective(creature, values(x0)):.3f}", flush=True)
    options = {"seed": args.seed, "popsize": 10, "bounds": [0, 1], "verbose": -9}
    search = cma.CMAEvolutionStrategy(x0, args.step, options)
    best: tuple[float, dict[str, float]] = (float("inf"), start)
    began = time.perf_counter()
    for generation in range(args.generations):
        xs = search.ask()
        scores = [objective(creature, values(x)) for x in xs]
        search.tell(xs, scores)
        i = int(np.argmin(scores))
        if scores[i] < best[0]:
            best = (scores[i], values(xs[i]))
        elapsed = time.perf_counter() - began
        left = elapsed / (generation + 1) * (args.generations - generation - 1)
        print(f"generation {generation + 1}/{args.generations}: best {scores[i]:.3f}, so far "
              f"{best[0]:.3f} ({elapsed:.0f} s, about {left:.0f} s left)", flush=True)  # fmt: skip
    print(json.dumps({"objective": best[0], "values": best[1]}, indent=1))


if __name__ == "__main__":
    main()
