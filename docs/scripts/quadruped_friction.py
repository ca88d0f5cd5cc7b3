"""The friction each of the quadruped's gaits needs: each gait run 20 s from standing on ground
of Coulomb friction MU (a copy of creatures/quadruped.leg with `friction MU` in place of the
paper's `friction none`, no slip), its outcome and its mean speed from 3 s against the
command (docs/quadruped.md, "Friction").

    nice python docs/scripts/quadruped_friction.py
    nice python docs/scripts/quadruped_friction.py --mu 0.4,0.5 --runs trot:2.3,bound:2.8

Each coefficient is its own creature, compiled once into a temporary directory (about 10 s);
the runs go through the Python API on the default backend.
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

import numpy as np

import legdsl

SOURCE = Path(__file__).resolve().parents[2] / "creatures" / "quadruped.leg"
MUS = "0.3,0.4,0.5,0.6,0.8,1,1.5,2,3,5"
RUNS = "trot:1,trot:2.3,pace:1.5,bound:2,bound:2.8,gallop:3,gallop:4"
DURATION = 20.0


def with_friction(mu: float, folder: Path) -> Path:
    """A copy of the quadruped whose ground has Coulomb friction ``mu``."""
    text = SOURCE.read_text()
    if text.count("    friction none\n") != 1:
        raise ValueError("expected the quadruped's ground to say 'friction none' once")
    leg = folder / "quadruped.leg"
    leg.write_text(text.replace("    friction none\n", f"    friction {mu:g}\n"))
    return leg


def measure(creature: legdsl.Creature, gait: str, speed: float) -> str:
    """'20 s, +0.5%' or 'fell at 3.2 s'."""
    run = creature.run(controller=gait, set={"speed": f"{speed} m/s"}, time=DURATION)
    times, x = run.samples["t"], run.samples["q.x"]
    if run.status != "ok":
        return f"{run.status} at {times[-1]:.1f} s"
    i = int(np.searchsorted(times, 3.0))
    mean = (x[-1] - x[i]) / (times[-1] - times[i])
    return f"20 s, {100 * (mean - speed) / speed:+.1f}%"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mu", default=MUS, help=f"friction coefficients (default {MUS})")
    parser.add_argument("--runs", default=RUNS, help=f"gait:speed in m/s (default {RUNS})")
    args = parser.parse_args()
    runs = [(g, float(v)) for g, v in (r.split(":") for r in args.runs.split(","))]
    print("| μ | " + " | ".join(f"{g} {v:g} m/s" for g, v in runs) + " |")
    print("|---|" + "---|" * len(runs))
    for mu in (float(m) for m in args.mu.split(",")):
        with tempfile.TemporaryDirectory() as tmp:
            folder = Path(tmp)
            creature = legdsl.load(with_friction(mu, folder), generated=folder / "generated")
            cells = [measure(creature, g, v) for g, v in runs]
        print(f"| {mu:g} | " + " | ".join(cells) + " |", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
