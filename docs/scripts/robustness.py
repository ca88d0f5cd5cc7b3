"""How robust the shipped gaits are to the small changes a user makes without thinking.

    nice -n 10 python docs/scripts/robustness.py              # the table and picture: 45 s
    nice -n 10 python docs/scripts/robustness.py --dense 101  # 101 commands over +-1%: 2.5 min
    python docs/scripts/robustness.py --runs quadruped:gallop:4 --threads 2

(Times on one core of the 2-core machine these were measured on; from the repo's root,
with its generated/.) Each shipped gait, at a speed its docs quote, is run for 20 s from
standing as it ships (the reference) and then 21 times more, each with one small change:
the commanded speed moved by +-0.25, 0.5, 0.75 and 1% (8 runs); the start 1 mm higher
(`--drop` the lowest foot's start height + 1 mm), at the command and at +-1% (3); the
integration step 0.39 ms instead of 0.4 ms (`--dt 0.39ms`), and the control interval
1.6 ms instead of 2 ms (`--control-dt 1.6ms`), each at the command and at +-0.5 and +-1%
(5 + 5). (`--control-dt 1.9ms` is the same run as 2 ms, byte for byte: the interval is
rounded to whole steps, 5 of 0.4 ms; 1.6 ms is the nearest other, 4 steps.) Every run goes
on the C backend in a batch (``legdsl.pipeline.batch``): the same doubles as the single
run `legdsl run` makes with those options. Reported per gait: falls (and when), and the
mean speed from 3 s to the end against the command (its error, in percent), for the
reference and over the changed runs. Writes the table to stdout, a `legdsl run` line for
every fall to stderr, and the speed errors to ``docs/img/robustness.png``. With
``--dense N``: instead, N commands spread evenly over +-1% of each gait's, their falls
(with a `legdsl run` line each) and the spread of their speeds.
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

# (creature, controller, commanded m/s, extra --set): the shipped gaits at the speeds their
# docs quote; the kangaroo's jump controller makes one animator's jump at 5 s
GAITS = [
    ("hopper", "hop", 1.0, ()),
    ("kangaroo", "hop", 3.0, ()),
    ("kangaroo", "hop", 5.0, ()),
    ("kangaroo", "jump", 4.0, ("jump_time=5s",)),
    ("biped", "run", 1.5, ()),
    ("biped", "gallop", 1.5, ()),
    ("quadruped", "trot", 1.0, ()),
    ("quadruped", "trot", 3.0, ()),
    ("quadruped", "pace", 1.0, ()),
    ("quadruped", "bound", 2.8, ()),
    ("quadruped", "gallop", 3.0, ()),
    ("quadruped", "gallop", 4.0, ()),
    ("quadruped", "gallop", 5.0, ()),
]
SECONDS = 20.0
SETTLED = 3.0  # s: the speed is measured from here to the end
SPEED_STEPS = (-1.0, -0.75, -0.5, -0.25, 0.25, 0.5, 0.75, 1.0)  # % of the command
# (kind, RunOptions changes, speeds in % of the command); kind "" is the plain run
GROUPS = [
    ("speed", {}, (0.0,) + SPEED_STEPS),
    ("start +1 mm", {"drop": 0.001}, (0.0, -1.0, 1.0)),
    ("dt 0.39 ms", {"dt": 0.00039}, (0.0, -1.0, -0.5, 0.5, 1.0)),
    ("control-dt 1.6 ms", {"control_dt": 0.0016}, (0.0, -1.0, -0.5, 0.5, 1.0)),
]


def lowest_foot(session: RunSession, controller: str, settings: list[str]) -> float:
    """The lowest contact's height at the start the creature ships with (--drop's H)."""
    sim = session.prepare(controller, settings).sim
    return min(p[2] for p in sim.dyn.contact_positions(list(sim.q)))


def cli(creature: str, controller: str, speed: float, extra: tuple, opts: dict) -> str:
    """The `legdsl run` line that makes this run alone."""
    line = f"legdsl run creatures/{creature}.leg --controller {controller} --time {SECONDS:g}"
    line += "".join(f" --set {s}" for s in (f"speed={speed!r}m/s", *extra))
    if "drop" in opts:
        line += f" --drop {opts['drop']!r}"
    if "dt" in opts:
        line += f" --dt {opts['dt']!r}"
    if "control_dt" in opts:
        line += f" --control-dt {opts['control_dt']!r}"
    return line


def measure(creature: str, controller: str, speed: float, extra: tuple, threads: int) -> dict:
    session = RunSession.from_file(ROOT / "creatures" / f"{creature}.leg",
                                   generated=ROOT / "generated")  # fmt: skip
    settings = [f"speed={speed}m/s", *extra]
    runs = []  # (kind, % moved, error or nan, fall time or None, cli line)
    for kind, changes, steps in GROUPS:
        opts = dict(changes)
        if "drop" in opts:
            opts["drop"] = lowest_foot(session, controller, settings) + changes["drop"]
        speeds = np.array([speed * (1 + s / 100) for s in steps])
        batch = Batch(session, len(steps), controller, settings=settings,
                      vary={"speed": (speeds, "m/s")},
                      options=RunOptions(duration=SECONDS, **opts))  # fmt: skip
        done = batch.run(threads=threads)
        for k, step in enumerate(steps):
            tr = done.trajectory(k)
            later = tr.t >= SETTLED
            fell = None if done.status[k] == "ok" else float(done.sim_time[k])
            error = np.nan
            if fell is None and later.any():
                x, t = tr.com[later, 0], tr.t[later]
                error = ((x[-1] - x[0]) / (t[-1] - t[0]) - speeds[k]) / speeds[k] * 100
            line = cli(creature, controller, float(speeds[k]), extra, opts)
            runs.append((kind, step, error, fell, line, str(done.status[k])))
    label = f"{creature} {controller} {speed:g} m/s" + (" (jump at 5 s)" if extra else "")
    return {"label": label, "runs": runs}


def dense(creature: str, controller: str, speed: float, extra: tuple, n: int, threads: int) -> str:
    """n commands spread evenly over the command +-1%: how many fall, when, and the speeds."""
    session = RunSession.from_file(ROOT / "creatures" / f"{creature}.leg",
                                   generated=ROOT / "generated")  # fmt: skip
    speeds = speed * np.linspace(0.99, 1.01, n)
    batch = Batch(session, n, controller, settings=[f"speed={speed}m/s", *extra],
                  vary={"speed": (speeds, "m/s")}, options=RunOptions(duration=SECONDS))  # fmt: skip
    done = batch.run(threads=threads)
    errors, falls = [], []
    for k in range(n):
        if done.status[k] != "ok":
            falls.append(
                f"{done.sim_time[k]:.1f} s ({cli(creature, controller, float(speeds[k]), extra, {})})"
            )
            continue
        tr = done.trajectory(k)
        x, t = tr.com[tr.t >= SETTLED, 0], tr.t[tr.t >= SETTLED]
        errors.append(((x[-1] - x[0]) / (t[-1] - t[0]) - speeds[k]) / speeds[k] * 100)
    e = np.array(errors)
    return (
        f"{creature} {controller} {speed:g} m/s, {n} commands over +-1%: {len(falls)} fell"
        + "".join(f"\n  fell at {f}" for f in falls)
        + f"\n  speed error: median {np.median(e):+.1f}%, {e.min():+.1f}% to {e.max():+.1f}%"
        + f", 10th to 90th percentile {np.percentile(e, 10):+.1f}% to {np.percentile(e, 90):+.1f}%"
    )


def table(rows: list[dict]) -> str:
    lines = [
        "| gait (20 s) | runs | falls (when) | speed error, reference | speed error, changed runs: "
        "median (lowest to highest) | the same, each change: speed / start / dt / control-dt |",
        "|---|---|---|---|---|---|",
    ]
    for r in rows:
        ref = r["runs"][0][2]
        changed = r["runs"][1:]
        errors = np.array([e for _, _, e, *_ in changed])
        ok = errors[np.isfinite(errors)]
        falls = [f"{kind} {step:+g}%: {t:.1f} s" for kind, step, _, t, *_ in changed if t]
        spread = f"{np.median(ok):+.1f}% ({ok.min():+.1f}% to {ok.max():+.1f}%)" if len(ok) else "-"
        each = []
        for kind, *_ in GROUPS:
            e = np.array([e for k, _, e, *_ in changed if k == kind])
            e = e[np.isfinite(e)]
            each.append(f"{e.min():+.1f}..{e.max():+.1f}" if len(e) else "-")
        lines.append(
            f"| {r['label']} | {len(changed)} | {len(falls)}"
            + (f" ({'; '.join(falls)})" if falls else "")
            + f" | {ref:+.1f}% | {spread} | {' / '.join(each)} |"
        )
    return "\n".join(lines)


def plot(rows: list[dict], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(10, 4.8))
    colours = {"speed": "tab:blue", "start +1 mm": "tab:green", "dt 0.39 ms": "tab:orange",
               "control-dt 1.6 ms": "tab:purple"}  # fmt: skip
    offsets = {"speed": -0.27, "start +1 mm": -0.09, "dt 0.39 ms": 0.09, "control-dt 1.6 ms": 0.27}
    for i, r in enumerate(rows):
        ax.scatter([i], [r["runs"][0][2]], s=120, marker="_", color="black", linewidths=2,
                   label="as shipped", zorder=3)  # fmt: skip
        fell = 0
        for kind, step, error, when, *_ in r["runs"][1:]:
            if when is not None:
                fell += 1
                continue
            moved = ", ".join(f"{m:+g}" for m in next(g[2] for g in GROUPS if g[0] == kind))
            label = {"speed": "command moved by up to 1%"}.get(kind, f"{kind} (command {moved}%)")
            ax.scatter(i + offsets[kind] + step * 0.02, error, s=14, color=colours[kind],
                       alpha=0.8, label=label)  # fmt: skip
        if fell:
            ax.annotate(f"{fell} of {len(r['runs']) - 1} fell", (i, -13), ha="center",
                        color="red", fontsize=8)  # fmt: skip
    handles, names = ax.get_legend_handles_labels()
    keep = dict(zip(names, handles, strict=True))
    ax.legend(keep.values(), keep.keys(), fontsize=8, loc="upper left", ncol=2)
    ax.axhline(0, color="grey", lw=0.8)
    ax.set_xticks(range(len(rows)), [r["label"] for r in rows], rotation=25, ha="right",
                  fontsize=8)  # fmt: skip
    ax.set_ylabel("mean speed from 3 s - command (%)")
    ax.set_ylim(-14, 20)
    ax.set_title("Each shipped gait, 20 s: as shipped, and 21 runs each with one small change",
                 fontsize=10)  # fmt: skip
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", nargs="*", help="CREATURE:CONTROLLER:M/S ...")
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--dense", type=int, metavar="N",
                        help="instead: N commands spread over +-1%% for each gait, falls and speeds")  # fmt: skip
    parser.add_argument("--png", type=Path, default=ROOT / "docs" / "img" / "robustness.png")
    args = parser.parse_args()
    gaits = GAITS
    if args.runs:
        gaits = [g for g in GAITS if f"{g[0]}:{g[1]}:{g[2]:g}" in args.runs]
    if args.dense:
        for gait in gaits:
            print(dense(*gait, n=args.dense, threads=args.threads), flush=True)
        return
    rows, start = [], time.perf_counter()
    for i, gait in enumerate(gaits):
        rows.append(measure(*gait, threads=args.threads))
        for _, _, _, when, line, status in rows[-1]["runs"]:
            if when is not None:
                print(f"  {status} at {when:.2f} s: {line}", file=sys.stderr)
        spent = time.perf_counter() - start
        left = spent / (i + 1) * (len(gaits) - i - 1)
        print(f"{rows[-1]['label']}: done ({spent:.0f} s, about {left:.0f} s left)",
              file=sys.stderr, flush=True)  # fmt: skip
    print(table(rows))
    plot(rows, args.png)
    print(f"wrote {args.png}", file=sys.stderr)


if __name__ == "__main__":
    main()
