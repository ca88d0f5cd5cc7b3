"""Footfall diagram of legged runs: one panel per run directory, a bar for each foot
while it touches the ground, double support shaded, with the trunk's pitch below.

    python docs/scripts/gallop_footfalls.py RUN_DIR [RUN_DIR ...] --from 15 --to 16.2 \
        -o docs/img/biped-gallop-footfalls.png

(RUN_DIR as written by `legdsl run ... --out RUN_DIR`.)
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from legdsl.sim.trajectory import Trajectory  # noqa: E402


def _spans(t: np.ndarray, on: np.ndarray) -> list[tuple[float, float]]:
    """(start, width) of each run of ``on``; the samples' times bound them."""
    edges = np.flatnonzero(np.diff(np.r_[0, on.astype(np.int8), 0]))
    starts, stops = edges[::2], edges[1::2]
    return [
        (float(t[a]), float(t[min(b, len(t) - 1)] - t[a]))
        for a, b in zip(starts, stops, strict=True)
    ]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("runs", nargs="+", type=Path)
    ap.add_argument("--from", dest="t_from", type=float, default=0.0)
    ap.add_argument("--to", dest="t_to", type=float, default=None)
    ap.add_argument("-o", "--output", type=Path, default=Path("footfalls.png"))
    args = ap.parse_args()

    fig, axes = plt.subplots(
        2 * len(args.runs), 1, figsize=(8, 2.6 * len(args.runs)), sharex=True,
        gridspec_kw={"height_ratios": [1, 1.3] * len(args.runs)},
    )  # fmt: skip
    for k, run in enumerate(args.runs):
        tr = Trajectory.load(run)
        t_to = float(tr.t[-1]) if args.t_to is None else args.t_to
        w = (tr.t >= args.t_from) & (tr.t <= t_to)
        t = tr.t[w]
        down = np.stack([tr.leg_touching(i)[w] for i in range(len(tr.leg_names))], axis=1)
        bars, ax_pitch = axes[2 * k], axes[2 * k + 1]
        for a, width in _spans(t, down.sum(axis=1) >= 2):
            bars.axvspan(a, a + width, color="#f0d070", lw=0)
            ax_pitch.axvspan(a, a + width, color="#f0d070", lw=0)
        for i in range(len(tr.leg_names)):
            bars.broken_barh(_spans(t, down[:, i]), (i + 0.2, 0.6), color="#304050")
        bars.set_yticks([i + 0.5 for i in range(len(tr.leg_names))], list(tr.leg_names))
        bars.set_ylim(0, len(tr.leg_names))
        bars.set_title(f"{run.name}: feet on the ground (bars), double support (shaded)")
        ax_pitch.plot(t, np.degrees(tr.root_rpy[w, 1]), color="k")
        ax_pitch.set_ylabel("pitch (deg)")
    pitch_axes = axes[1::2]
    low = min(a.get_ylim()[0] for a in pitch_axes)
    high = max(a.get_ylim()[1] for a in pitch_axes)
    for a in pitch_axes:  # one scale, so that the runs' pitching compares at a glance
        a.set_ylim(low, high)
    axes[-1].set_xlabel("time (s)")
    fig.tight_layout()
    fig.savefig(args.output, dpi=100)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
