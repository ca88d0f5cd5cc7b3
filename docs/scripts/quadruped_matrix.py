"""The quadruped's gaits at the issue's speeds: each run 20 s from standing, and a table of
whether it fell, its mean speed after 3 s against the command, how often the members of a
pair land within 10 ms of each other (and the median time between them), the share of a
bound's or gallop's pair stances that go single, double, then single support, and the
friction coefficient it needed.

    nice python docs/scripts/quadruped_matrix.py                 # every gait the file has
    nice python docs/scripts/quadruped_matrix.py --gait trot --speeds 1,2
    nice python docs/scripts/quadruped_matrix.py --file stocky/stocky.leg   # another quadruped

Runs go through the command line (``legdsl run``, ``legdsl metrics``) into --out.
"""

from __future__ import annotations

import argparse
import json
import re
import subprocess
from pathlib import Path

import numpy as np

MATRIX = {"trot": (1, 2, 2.3, 3), "bound": (2, 2.8, 3.5), "pace": (1, 2), "gallop": (3, 4, 5)}
PAIRS = {
    "trot": {"toe_fl": "toe_rr", "toe_rr": "toe_fl", "toe_fr": "toe_rl", "toe_rl": "toe_fr"},
    "pace": {"toe_fl": "toe_rl", "toe_rl": "toe_fl", "toe_fr": "toe_rr", "toe_rr": "toe_fr"},
    "bound": {"toe_fl": "toe_fr", "toe_fr": "toe_fl", "toe_rl": "toe_rr", "toe_rr": "toe_rl"},
}
PAIRS["gallop"] = PAIRS["bound"]
FEET = ("toe_fl", "toe_fr", "toe_rl", "toe_rr")  # the order of trajectory.contact
CREATURE = "creatures/quadruped.leg"


def pair_spreads(run: Path, gait: str, start: float = 3.0) -> list[float]:
    """At each LOADING (the first member lands), how long until its partner lands."""
    info = json.loads((run / "run.json").read_text())
    tds = [(e["t"], e["contact"]) for e in info["events"] if e["kind"] == "touchdown"]
    out = []
    for e in info["events"]:
        if e.get("state") != "LOADING" or e["t"] < start:
            continue
        first = next((x for x in tds if abs(x[0] - e["t"]) <= 0.005), None)
        if first is None or gait not in PAIRS:
            continue
        partner = PAIRS[gait][first[1]]
        lands = [t for t, c in tds if c == partner and abs(t - first[0]) <= 0.06]
        out.append(min(abs(t - first[0]) for t in lands) if lands else 1.0)
    return out


def staggered_stances(run: Path, gait: str, start: float = 3.0) -> tuple[int, int]:
    """(stances, of which single-double-single): a pair's stance, from its first foot down
    to its last foot up, counts when one member is down alone first, then both, then the
    other alone (each phase at least one sample)."""
    t = np.load(run / "trajectory.npz")
    down = t["contact"] > 0.5
    keep = t["t"] >= start
    total = sds = 0
    for a, b in ((0, 1), (2, 3)) if gait in ("bound", "gallop") else ():
        pair = (down[:, a] | down[:, b]) & keep
        edges = np.flatnonzero(np.diff(np.r_[0, pair.astype(np.int8), 0]))
        for lo, hi in zip(edges[::2], edges[1::2], strict=True):
            if lo == 0 or hi >= len(pair):
                continue
            pattern = down[lo:hi, a].astype(int) + 2 * down[lo:hi, b].astype(int)
            phases = [int(p) for k, p in enumerate(pattern) if k == 0 or p != pattern[k - 1]]
            total += 1
            sds += phases in ([1, 3, 2], [2, 3, 1])
    return total, sds


def measure(
    gait: str, speed: float, out: Path, time: float, creature: str = CREATURE
) -> dict[str, object]:
    run = out / f"q_{gait}_{speed:g}"
    cmd = ["legdsl", "run", creature, "--controller", gait, "--set", f"speed={speed:g}m/s"]
    done = subprocess.run(
        [*cmd, "--time", str(time), "--out", str(run)], capture_output=True, text=True
    )
    row: dict[str, object] = {"gait": gait, "speed": speed, "exit": done.returncode}
    info = json.loads((run / "run.json").read_text())
    row["ended"] = info.get("ended_at") or info.get("sim_time")
    t = np.load(run / "trajectory.npz")
    later = t["t"] >= 3.0
    if later.sum() > 2:
        yaw = t["root_rpy"][later, 2]
        dx = np.cos(yaw[0]) * (t["com"][later, 0][-1] - t["com"][later, 0][0])
        dy = np.sin(yaw[0]) * (t["com"][later, 1][-1] - t["com"][later, 1][0])
        row["mean_speed"] = (dx + dy) / (t["t"][later][-1] - t["t"][later][0])
    metrics = subprocess.run(
        ["legdsl", "metrics", str(run), "--from", "3"], capture_output=True, text=True
    ).stdout
    mu = [float(m) for m in re.findall(r"past first/last 10 ms \(-\)\s+([\d.]+)", metrics)]
    row["friction"] = max(mu) if mu else float("nan")
    spreads = pair_spreads(run, gait)
    row["pairs_10ms"] = float(np.mean(np.array(spreads) <= 0.010)) if spreads else float("nan")
    row["median_lag"] = float(np.median(spreads)) if spreads else float("nan")
    total, sds = staggered_stances(run, gait)
    row["single_double_single"] = sds / total if total else float("nan")
    return row


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--gait", action="append", help="a gait (repeatable); default all")
    parser.add_argument("--speeds", help="comma-separated speeds in m/s (default the issue's)")
    parser.add_argument("--time", type=float, default=20.0)
    parser.add_argument("--out", default="runs/matrix")
    parser.add_argument("--file", default=CREATURE, help="another quadruped's .leg file")
    args = parser.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    print(
        f"{'gait':7} {'cmd':>5} {'exit':>4} {'until':>6} {'speed':>6} {'err%':>6} {'pairs<10ms':>10} {'lag ms':>6} {'s-d-s':>5} {'mu':>6}"
    )
    for gait in args.gait or list(MATRIX):
        speeds = [float(v) for v in args.speeds.split(",")] if args.speeds else MATRIX[gait]
        for v in speeds:
            r = measure(gait, v, out, args.time, args.file)
            ms = float(r.get("mean_speed", float("nan")))  # type: ignore[arg-type]
            print(
                f"{gait:7} {v:5.2f} {r['exit']:>4} {float(r['ended'] or 0):6.2f} {ms:6.3f} "  # type: ignore[arg-type]
                f"{100 * (ms - v) / v if v else float('nan'):6.1f} {float(r['pairs_10ms']):10.2f} "  # type: ignore[arg-type]
                f"{1000 * float(r['median_lag']):6.1f} {float(r['single_double_single']):5.2f} "  # type: ignore[arg-type]
                f"{float(r['friction']):6.2f}",  # type: ignore[arg-type]
                flush=True,
            )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
