"""Parameter search for the kangaroo's hop controller (creatures/kangaroo.leg).

Runs the controller in-process (one simulation at a time) with parameters and
inputs set as `--set` would, and scores each setting by the time it stays up
and its mean forward speed after 3 s against the command. Usage:

    PYTHONPATH=src nice -n 10 python benchmarks/kangaroo_search.py eval speed=3,5 time=20 k_height=60 ...
    PYTHONPATH=src nice -n 10 python benchmarks/kangaroo_search.py random N seed=1 time=10 speed=3,5
    PYTHONPATH=src nice -n 10 python benchmarks/kangaroo_search.py random N score=tail speed=3,5 time=12

Values are in SI units (radians for angles). `random` perturbs the parameters
named in SPACE around the .leg's values and prints the best settings
(`score=tail`: only the tail's, scored also by its wag and anti-phase).
"""

from __future__ import annotations

import json
import math
import random
import sys
from pathlib import Path

import numpy as np

from legdsl.analysis.metrics import compute_metrics
from legdsl.pipeline.session import RunSession
from legdsl.pipeline.settings import si_unit
from legdsl.sim.run_loop import RunOptions

ROOT = Path(__file__).resolve().parents[1]
KANGAROO = ROOT / "creatures" / "kangaroo.leg"

# name: (low, high) of the random search, SI units
SPACE: dict[str, tuple[float, float]] = {
    "k_height": (0.5, 3.0),
    "height": (0.42, 0.50),
    "pitch_lead": (-0.15, 0.15),
    "kp": (30.0, 150.0),
    "kv": (3.0, 15.0),
    "k_speed": (0.01, 0.08),
    "max_trim": (0.3, 2.0),
    "k_trim": (0.1, 0.8),
    "tail_kp": (10.0, 60.0),
    "tail_kv": (1.0, 6.0),
    "reach": (0.40, 0.47),
    "tuck": (0.32, 0.42),
    "min_stroke": (-0.4, 0.0),
    "max_stroke": (0.1, 0.5),
    "tail_k": (4.0, 14.0),
    "swing_kp": (40.0, 150.0),
    "hip_kp": (200.0, 600.0),
    "stroke": (0.0, 0.2),
    "tail_stop": (0.0, 60.0),
    "accel": (0.6, 1.5),
    "tail_down": (-0.8, 0.0),
    "tail_up": (-0.3, 0.5),
    "tail_b": (0.05, 1.0),
}

_sessions: list[RunSession] = []


def _session() -> RunSession:
    if not _sessions:
        _sessions.append(RunSession.from_file(KANGAROO, generated=ROOT / "generated"))
    return _sessions[0]


def _set(session: RunSession, name: str, value: float, at: float | None = None) -> str:
    """``--set`` text for a value in SI units (``tail_kp=30.0kg*m^2/s^2/rad``)."""
    hop = session.model.controller("hop")
    dim = {c.name: c.dim for c in (*hop.inputs, *hop.params)}[name]
    return f"{name}={value!r}{si_unit(dim)}" + ("" if at is None else f"@{at!r}s")


def run(speed: float, time: float, settings: dict[str, float], later: float | None = None) -> dict:
    session = _session()
    texts = [_set(session, k, v) for k, v in {**settings, "speed": speed}.items()]
    if later is not None:
        texts.append(_set(session, "speed", later, at=5.0))
    res = session.run("hop", texts, options=RunOptions(duration=time)).result
    tr = res.trajectory
    t = tr.t
    x = tr.com[:, 0]
    up = float(t[-1]) if res.status != "ok" else time
    start = 8.0 if later is not None else 3.0
    sel = t >= start
    mean = float((x[sel][-1] - x[sel][0]) / (t[sel][-1] - t[sel][0])) if sel.sum() > 20 else 0.0
    target = later if later is not None else speed
    table2: dict[str, float] = {}
    if res.status == "ok":
        m = compute_metrics(tr, t_from=start, joint="tail_base", against="hip")
        for key, short in (
            ("stride_duration", "stride"),
            ("stance_duration", "stance_m"),
            ("peak_vertical_acceleration", "peak_g"),
            ("joint_magnitude", "tail_wag"),
            ("joint_correlation", "tail_corr"),
        ):
            table2[short] = round(m.value(key), 3)
    pitch = tr.root_rpy[:, 1]
    toe = tr.contact[:, tr.contact_names.index("toe")][sel] > 0
    edges = np.flatnonzero(np.diff(toe.astype(int)))
    dt = float(t[1] - t[0])
    runs = np.diff(edges) * dt
    first_is_stance = bool(toe[edges[0] + 1]) if len(edges) else False
    stance = runs[0 if first_is_stance else 1 :: 2]
    flight = runs[1 if first_is_stance else 0 :: 2]
    return {
        "speed": target,
        "up": round(up, 2),
        "mean": round(mean, 3),
        "err": round((mean - target) / target, 3),
        "pitch_max": round(math.degrees(float(np.abs(pitch[sel]).max())) if sel.any() else 0, 1),
        "stance": round(float(np.median(stance)), 3) if len(stance) else 0,
        "flight": round(float(np.median(flight)), 3) if len(flight) else 0,
        "apex": round(float(np.percentile(tr.com[sel, 2], 98)), 3) if sel.any() else 0,
        **table2,
    }


def score(rs: list[dict], time: float, tail: bool = False) -> float:
    s = 0.0
    for r in rs:
        s += r["up"] / time * 10 - (abs(r["err"]) * 10 if r["up"] >= time else 5)
        if tail and r["up"] >= time:  # the tail's wag toward the animal's 30 deg, in anti-phase
            s -= abs(r["tail_wag"] - 30) / 30 + r["tail_corr"]
    return s


TAIL = ("tail_k", "tail_kp", "tail_kv", "tail_down", "tail_up", "tail_b", "tail_stop")


def parse(args: list[str]) -> dict[str, str]:
    return dict(a.split("=", 1) for a in args)


def main() -> None:
    mode = sys.argv[1]
    if mode == "eval":
        kv = parse(sys.argv[2:])
        speeds = [float(v) for v in kv.pop("speed", "2,3,4,5").split(",")]
        time = float(kv.pop("time", "20"))
        sched = kv.pop("schedule", None)
        settings = {k: float(v) for k, v in kv.items()}
        rs = [run(v, time, settings) for v in speeds]
        if sched:
            rs.append(run(2.0, time, settings, later=5.0))
        for r in rs:
            print(json.dumps(r), flush=True)
        print("score", round(score(rs, time), 2))
        return
    n = int(sys.argv[2])
    kv = parse(sys.argv[3:])
    rng = random.Random(int(kv.pop("seed", "1")))
    speeds = [float(v) for v in kv.pop("speed", "3,5").split(",")]
    time = float(kv.pop("time", "10"))
    scale = float(kv.pop("scale", "1"))
    tail = kv.pop("score", "speed") == "tail"
    names = sorted(TAIL) if tail else sorted(SPACE)
    base = {k: float(v) for k, v in kv.items()}
    best = (-1e9, base)
    for i in range(n):
        if i == 0:
            trial = dict(base)
        else:
            centre = best[1]
            trial = dict(centre)
            for name in rng.sample(names, 3):
                lo, hi = SPACE[name]
                c = centre.get(name, (lo + hi) / 2)
                trial[name] = min(hi, max(lo, c + rng.gauss(0, 0.3 * scale * (hi - lo))))
        rs = [run(v, time, trial) for v in speeds]
        sc = score(rs, time, tail)
        line = {
            "i": i,
            "score": round(sc, 2),
            "runs": rs,
            "set": {k: round(v, 4) for k, v in trial.items()},
        }
        print(json.dumps(line), flush=True)
        if sc > best[0]:
            best = (sc, trial)
    print("BEST", json.dumps({"score": best[0], "set": best[1]}))


if __name__ == "__main__":
    main()
