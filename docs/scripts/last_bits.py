"""How much each shipped gait depends on the last bits of its numbers: copies nudged by ulps.

    python docs/scripts/last_bits.py                 # every run below, 32 copies each
    python docs/scripts/last_bits.py --copies 64 --runs quadruped:gallop:5

A change to the numerics (another order of the same sums, a solve done another way) moves
every result by an ulp or so, and a legged run is chaotic: the difference grows until the two
runs step differently. Whether the gait still holds its speed, or falls, is the question such
a change raises. Here each run goes as a batch (``legdsl.pipeline.batch``) of copies that
start with the root's height moved by 0, 1, 2, ... ulps (about 1e-16 m); reported per run:
the copies that did not fall, the speed each settled at (from 3 s to the end) against the
command, and how long the copies stay within 1 mm of the unmoved one (the run's horizon).
Writes the table to stdout and the speeds to ``docs/img/last-bits.png``.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "src"))

from legdsl.pipeline.batch import Batch  # noqa: E402
from legdsl.pipeline.session import RunSession  # noqa: E402
from legdsl.sim.run_loop import RunOptions  # noqa: E402

# (creature, controller, commanded m/s, run seconds): the shipped gaits at speeds their tests
# and docs hold them to
RUNS = [
    ("hopper", "hop", 1.0, 10.0),
    ("kangaroo", "hop", 3.0, 10.0),
    ("biped", "run", 1.5, 10.0),
    ("biped", "gallop", 1.5, 10.0),
    ("quadruped", "trot", 1.0, 10.0),
    ("quadruped", "pace", 1.0, 10.0),
    ("quadruped", "bound", 2.8, 20.0),
    ("quadruped", "gallop", 3.0, 10.0),
    ("quadruped", "gallop", 5.0, 20.0),
]
SETTLED = 3.0  # s: the speed is measured from here to the end
APART = 1e-3  # m: copies this far apart (the centre of mass) have parted
WHAT = {"start": "the root's start height", "speed": "the commanded speed"}


def nudged(session: RunSession, controller: str, copies: int) -> np.ndarray:
    """The run's start, copy k's root height moved up by k ulps."""
    start = np.array(session.prepare(controller).sim.q, dtype=float)
    q0 = np.tile(start, (copies, 1))
    z = session.model.q_names.index("z")
    q0[:, z] = start[z] + np.arange(copies) * np.spacing(start[z])  # k ulps, exactly
    return q0


def measure(
    creature: str, controller: str, speed: float, seconds: float, copies: int, nudge: str
) -> dict:
    session = RunSession.from_file(ROOT / "creatures" / f"{creature}.leg",
                                   generated=ROOT / "generated")  # fmt: skip
    opts = RunOptions(duration=seconds)
    if nudge == "start":
        batch = Batch(session, copies, controller, settings=[f"speed={speed}m/s"],
                      q0=nudged(session, controller, copies), options=opts)  # fmt: skip
    else:  # the command, k ulps faster: a difference the controller feeds in at every tick
        speeds = speed + np.arange(copies) * np.spacing(speed)
        batch = Batch(session, copies, controller, vary={"speed": (speeds, "m/s")}, options=opts)
    done = batch.run(threads=2)
    errors, horizons, distinct = [], [], set()
    first = done.trajectory(0)
    for k in range(copies):
        tr = done.trajectory(k)
        distinct.add(tr.q.tobytes())
        later = tr.t >= SETTLED
        if done.status[k] != "ok" or not later.any():
            errors.append(np.nan)
        else:
            x, t = tr.com[later, 0], tr.t[later]
            errors.append(((x[-1] - x[0]) / (t[-1] - t[0]) - speed) / speed)
        if k:
            n = min(len(tr), len(first))
            gap = np.linalg.norm(tr.com[:n] - first.com[:n], axis=1)
            apart = np.flatnonzero(gap > APART)
            horizons.append(tr.t[apart[0]] if len(apart) else tr.t[n - 1])
    return {"label": f"{creature} {controller} {speed:g} m/s, {seconds:g} s", "nudge": nudge,
            "errors": np.array(errors), "horizon": float(np.median(horizons)),
            "held": int(np.count_nonzero(done.status == "ok")), "copies": copies,
            "distinct": len(distinct)}  # fmt: skip


def table(rows: list[dict]) -> str:
    lines = [
        "| run | moved by k ulps | runs that differ | copies that hold | speed error, unmoved | "
        "speed error over the copies: median (lowest to highest) | copies within 1 mm until "
        "(median) |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        e = r["errors"] * 100
        ok = e[np.isfinite(e)]
        spread = f"{np.median(ok):+.1f}% ({ok.min():+.1f}% to {ok.max():+.1f}%)" if len(ok) else "-"
        lines.append(
            f"| {r['label']} | {WHAT[r['nudge']]} | {r['distinct']} | {r['held']} of {r['copies']} | "
            f"{e[0]:+.1f}% | "
            f"{spread} | "
            f"{r['horizon']:.2f} s |"
        )
    return "\n".join(lines)


def plot(rows: list[dict], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(9, 4.4))
    rng = np.random.default_rng(0)
    labels = list(dict.fromkeys(r["label"].split(",")[0] for r in rows))
    colours = {"start": "tab:blue", "speed": "tab:orange"}
    for r in rows:
        i = labels.index(r["label"].split(",")[0]) + (-0.2 if r["nudge"] == "start" else 0.2)
        e = r["errors"] * 100
        ok = np.isfinite(e)
        jitter = rng.uniform(-0.12, 0.12, len(e))
        ax.scatter(i + jitter[ok], e[ok], s=9, color=colours[r["nudge"]], alpha=0.6,
                   label=f"{WHAT[r['nudge']]} moved by 0, 1, 2, ... ulps")  # fmt: skip
        ax.scatter([i], [e[0]], s=70, marker="_", color="black", linewidths=2)
        if not ok.all():
            ax.annotate(f"{int(np.count_nonzero(~ok))} fell", (i, -10), ha="center", color="red")
    handles, names = ax.get_legend_handles_labels()
    keep = dict(zip(names, handles, strict=True))
    ax.legend(keep.values(), keep.keys(), fontsize=8, loc="upper left")
    ax.axhline(0, color="grey", lw=0.8)
    ax.set_xticks(range(len(labels)), labels, rotation=20, ha="right", fontsize=8)
    ax.set_ylabel("settled speed - command (%)")
    ax.set_ylim(-12, 12)
    ax.set_title(f"{rows[0]['copies']} copies of each run (black: unmoved); every copy's run "
                 "differs from the others in its bits", fontsize=10)  # fmt: skip
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--copies", type=int, default=32)
    parser.add_argument("--runs", nargs="*", help="CREATURE:CONTROLLER:M/S[:SECONDS] ...")
    parser.add_argument("--png", type=Path, default=ROOT / "docs" / "img" / "last-bits.png")
    args = parser.parse_args()
    runs = RUNS
    if args.runs:
        runs = [(c, k, float(v), float(rest[0]) if rest else 10.0)
                for c, k, v, *rest in (r.split(":") for r in args.runs)]  # fmt: skip
    rows, start = [], time.perf_counter()
    todo = [(run, nudge) for run in runs for nudge in ("start", "speed")]
    for i, (run, nudge) in enumerate(todo):
        rows.append(measure(*run, copies=args.copies, nudge=nudge))
        spent = time.perf_counter() - start
        left = spent / (i + 1) * (len(todo) - i - 1)
        print(f"{rows[-1]['label']}: done ({spent:.0f} s, about {left:.0f} s left)",
              file=sys.stderr, flush=True)  # fmt: skip
    print(table(rows))
    plot(rows, args.png)
    print(f"wrote {args.png}", file=sys.stderr)


if __name__ == "__main__":
    main()
