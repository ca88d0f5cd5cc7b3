"""The kangaroo's jump over a box (issue 17): run it, check the body against the box, measure.

    PYTHONPATH=src python docs/scripts/kangaroo_jump.py --speed 4 --height 0.3 --out runs/jump4
    PYTHONPATH=src python docs/scripts/kangaroo_jump.py --speed 4 --tallest   # the tallest box

The box goes into a copy of creatures/kangaroo.leg (its ground gains
``terrain box(x0 = AT, x1 = AT + DEPTH, height = H)``), written next to the run, so the run,
`legdsl metrics`, `legdsl plot` and the player all see it; the copy has the shipped
creature's dynamics and controllers, so the shipped generated code runs it. The check
(``legdsl.analysis.clearance``) is made against the recorded body poses: the least margin
between the creature's shapes and the box (negative: they overlap). Then: did it land, the
speed of the strides after the landing, and did it hop to the end without falling.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "src"))

from legdsl.analysis.clearance import terrain_contacts  # noqa: E402
from legdsl.check.source import check_model  # noqa: E402
from legdsl.pipeline.generated import load_controller, load_dynamics  # noqa: E402
from legdsl.sim.machine import StateMachine  # noqa: E402
from legdsl.sim.run_loop import RunOptions  # noqa: E402
from legdsl.sim.simulate import Simulation  # noqa: E402

KANGAROO = ROOT / "creatures" / "kangaroo.leg"
GROUND = "    friction none\n  }"


def box_file(out: Path, at: float, depth: float, height: float) -> Path:
    """creatures/kangaroo.leg with a box in its ground, as OUT/kangaroo_box.leg."""
    text = KANGAROO.read_text(encoding="utf-8")
    assert text.count(GROUND) == 1, "the kangaroo's ground block changed: update GROUND"
    box = f"    terrain box(x0 = {at} m, x1 = {at + depth} m, height = {height} m)\n"
    out.mkdir(parents=True, exist_ok=True)
    path = out / "kangaroo_box.leg"
    path.write_text(text.replace(GROUND, GROUND[:-3] + box + "  }"), encoding="utf-8")
    return path


def jump(source: Path, speed: float, time: float, generated: Path, **settings: float):  # type: ignore[no-untyped-def]
    """Run `jump`; returns (model, dynamics module, run result)."""
    model = check_model(source)
    dyn = load_dynamics(model, source, generated)
    control = load_controller(model, "jump", source, generated)
    inputs = {"speed": speed, **{k: v for k, v in settings.items() if k in control.INPUTS}}
    params = {k: v for k, v in settings.items() if k in control.PARAMS}
    machine = StateMachine(model, control, inputs, params)
    return model, dyn, Simulation(model, dyn, RunOptions(duration=time), machine).run()


def report(model, dyn, run, speed: float) -> dict:  # type: ignore[no-untyped-def]
    """The margin to the box, the landing and the strides after it."""
    tr = run.trajectory
    poses = [dyn.body_poses([float(x) for x in q]) for q in tr.q]
    (box,) = terrain_contacts(model.bodies, model.ground.terrain, tr.t, poses, model.planar)
    x1 = next(t.get("x1") for t in model.ground.terrain if t.kind == "box")
    toe = tr.contact[:, tr.contact_names.index("toe")] > 0
    downs = np.flatnonzero(np.diff(toe.astype(int)) == 1) + 1
    after = [k for k in downs if tr.com[k, 0] > x1]
    landed = float(tr.t[after[0]]) if after else None
    lifts = np.flatnonzero(np.diff(toe.astype(int)) == -1) + 1
    before = [k for k in lifts if after and k < after[0]]
    x0 = next(t.get("x0") for t in model.ground.terrain if t.kind == "box")
    takeoff_to_middle = float((x0 + x1) / 2 - tr.com[before[-1], 0]) if before else None
    strides = [
        float((tr.com[b, 0] - tr.com[a, 0]) / (tr.t[b] - tr.t[a]))
        for a, b in zip(after, after[1:], strict=False)
    ]
    within = next(
        (
            i + 1
            for i, v in enumerate(strides)
            if all(abs(w / speed - 1) < 0.05 for w in strides[i : i + 3])
        ),
        None,
    )
    return {
        "status": run.status,
        "end_time": float(tr.t[-1]),
        "margin_m": box.margin,
        "closest_body": box.body,
        "closest_t": box.t,
        "overlap_samples": len(box.overlapping),
        "landed_t": landed,
        "liftoff_to_box_middle_m": takeoff_to_middle,
        "strides_after_landing_m_s": [round(v, 3) for v in strides[:6]],
        "first_stride_of_three_within_5pct": within,
        "apex_m": float(tr.com[:, 2].max()),
    }


def main() -> None:
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--speed", type=float, default=4.0)
    ap.add_argument("--height", type=float, default=0.3)
    ap.add_argument("--depth", type=float, default=0.3)
    ap.add_argument("--at", type=float, default=10.0)
    ap.add_argument("--time", type=float, default=20.0)
    ap.add_argument("--out", type=Path, default=Path("runs/jump"))
    ap.add_argument("--generated", type=Path, default=ROOT / "generated")
    ap.add_argument(
        "--tallest",
        action="store_true",
        help="from --height, raise the box by 5 cm until it is not cleared (or it falls)",
    )
    ap.add_argument("--set", action="append", default=[], metavar="NAME=SI")
    args = ap.parse_args()
    settings = {k: float(v) for k, v in (s.split("=") for s in args.set)}
    heights = (
        [args.height] if not args.tallest else [round(args.height + 0.05 * i, 2) for i in range(15)]
    )
    for h in heights:
        source = box_file(args.out / f"h{h:.2f}", args.at, args.depth, h)
        model, dyn, run = jump(source, args.speed, args.time, args.generated, **settings)
        r = report(model, dyn, run, args.speed)
        print(json.dumps({"height": h, **r}))
        ok = r["status"] == "ok" and r["margin_m"] > 0 and r["landed_t"] is not None
        if args.tallest and not ok:
            break


if __name__ == "__main__":
    main()
