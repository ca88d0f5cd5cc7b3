"""Dynamic scaling, both ways, measured: the numbers of docs/scaling.md.

    python docs/scripts/scaling_demo.py --out /tmp/scaling      # about 4 minutes on one core

For the kangaroo's hop and the biped's run, at their files' own commands (5 m/s, 1.5 m/s):
the unscaled run (T s), then for L = 2 and 0.5 the file ``legdsl scale --by L`` writes run for
T sqrt(L) s, and ``legdsl run --scale L`` of the unscaled file. It prints the largest difference
of the two scaled runs, sample by sample over every recorded channel relative to the channel's
magnitude, how long it stays below 1e-9, and the ratios of
``legdsl metrics --from F sqrt(L)`` of each scaled run to the unscaled one's ``--from F``. Every
command it runs is printed first. Scaled generated code goes to OUT/generated.
"""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np

from legdsl.sim.trajectory import ARRAYS, Trajectory

CASES = {"kangaroo": ("hop", 10.0, 5.0), "biped": ("run", 10.0, 5.0)}  # controller, T, --from
SCALES = (2.0, 0.5)
ROWS = {
    "apex_height": ("apex height of the centre of mass", 1.0),
    "apex_foot_clearance": ("clearance at the apex", 1.0),
    "running_speed": ("running speed", 0.5),
    "stride_duration": ("stride duration", 0.5),
    "stride_length": ("stride length", 1.0),
    "stance_duration": ("stance duration", 0.5),
}


REUSE = False  # --reuse: keep run directories already there


def legdsl(*argv: str) -> str:
    if REUSE and argv[0] == "run" and Path(argv[argv.index("--out") + 1], "run.json").is_file():
        return ""
    print("    legdsl " + " ".join(argv), flush=True)
    done = subprocess.run(["legdsl", *argv], capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"failed ({done.returncode}): {done.stderr}")
    return done.stdout


def agreement(a: Trajectory, b: Trajectory) -> np.ndarray:
    """Per sample, the largest |a - b| over every recorded channel (each column of every array),
    relative to that channel's magnitude (its largest |a| over the run): a relative measure
    that stays meaningful where a value crosses zero."""
    assert len(a) == len(b)
    worst = np.zeros(len(a))
    for name in ARRAYS:
        x = getattr(a, name).astype(float).reshape(len(a), -1)
        y = getattr(b, name).astype(float).reshape(len(b), -1)
        ok = np.isfinite(x) & np.isfinite(y)
        size = np.where(ok, np.abs(x), 0.0).max(axis=0)
        rel = np.where(ok, np.abs(x - y), 0.0) / np.where(size > 0, size, 1.0)
        worst = np.maximum(worst, rel.max(axis=1))
    return worst


def metrics(run: Path, t_from: float, generated: Path) -> dict[str, float]:
    argv = ["metrics", str(run), "--from", repr(t_from), "--generated", str(generated)]
    data = json.loads(legdsl(*argv, "--json"))
    return {k: data["summary"][k]["value"] for k in ROWS}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", required=True, help="a directory for the runs")
    parser.add_argument("--reuse", action="store_true", help="keep the runs already in --out")
    args = parser.parse_args()
    global REUSE
    REUSE = args.reuse
    out = Path(args.out)
    gen = out / "generated"
    lines = []
    for name, (controller, duration, t_from) in CASES.items():
        source = f"creatures/{name}.leg"
        base = out / name
        legdsl(
            "run", source, "--controller", controller, "--time", repr(duration), "--out", str(base)
        )
        ref = metrics(base, t_from, Path("generated"))
        for scale in SCALES:
            tick = math.sqrt(scale)
            tag = f"{name}_x{scale:g}".replace(".", "_")
            scaled = out / f"{tag}.leg"
            legdsl("scale", source, "--by", repr(scale), "-o", str(scaled))
            common = [
                "--controller",
                controller,
                "--time",
                repr(duration * tick),
                "--generated",
                str(gen),
            ]
            legdsl("run", str(scaled), *common, "--out", str(out / f"{tag}-file"))
            legdsl("run", source, *common, "--scale", repr(scale), "--out", str(out / f"{tag}-run"))
            a = Trajectory.load(out / f"{tag}-file")
            b = Trajectory.load(out / f"{tag}-run")
            rel = agreement(a, b)
            over = np.flatnonzero(rel > 1e-9)
            short = float(rel[a.t <= 2.0 * tick].max())
            until = f"{a.t[over[0]]:.2f} s" if over.size else "the end"
            m = metrics(out / f"{tag}-file", t_from * tick, gen)
            ratios = ", ".join(
                f"{label} {m[key] / ref[key]:.4f} (L^{power:g} = {scale**power:.4f})"
                for key, (label, power) in ROWS.items()
            )
            lines.append(
                f"{name} {controller}, L = {scale:g}: {len(a)} samples; max relative difference "
                f"{short:.2e} over the first {2 * tick:.3f} s (2 s unscaled), below 1e-9 until "
                f"{until}, {rel.max():.2e} over the whole run; ratios to L = 1: {ratios}"
            )
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
