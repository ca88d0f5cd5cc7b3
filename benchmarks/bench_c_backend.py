"""The C backend beside the Python backend and MuJoCo: steps per second, forward dynamics, compile.

Run from the repository root (niced, it takes about two minutes):

    nice python benchmarks/bench_c_backend.py

For every shipped creature and controller (and the quadruped's passive drop), a 5 s run on the
Python backend and on the C backend, checked identical (status, steps, events, every recorded
array byte for byte), and its steps per second on each; MuJoCo's ``mj_step`` on the exported
MJCF with its contacts and actuators on (``bench_runtime.mujoco_drop``: a 3 s drop, the same step
and its Euler integrator). Then microseconds per ``forward_dynamics`` (Python, C called in a
loop inside C, MuJoCo ``mj_forward`` without contacts, Pinocchio's ``aba`` on the URDF
export), the time from the ``.leg`` file to a loaded library, first with an empty cache and
then cached, and the batch's throughput (``legdsl.pipeline.batch``: N kangaroo runs in 1 and 2
threads). The results replace the "c-backend" section of docs/benchmarks.md.
"""

from __future__ import annotations

import argparse
import ctypes
import functools
import os
import platform
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_dynamics import MuJoCoModel, per_call_us, random_state  # noqa: E402
from bench_runtime import STEP, mujoco_drop  # noqa: E402
from report import DOC, replace_section  # noqa: E402

from legdsl.check.source import check_model  # noqa: E402
from legdsl.codegen.c.build import build, find_compiler, sources  # noqa: E402
from legdsl.pipeline.compile import compile_model  # noqa: E402
from legdsl.pipeline.generated import write_generated  # noqa: E402
from legdsl.pipeline.session import RunSession  # noqa: E402
from legdsl.sim.run_loop import RunOptions  # noqa: E402
from legdsl.sim.trajectory import ARRAYS  # noqa: E402

# The transliteration of forward_dynamics into C, microseconds per call (issue 14)
TRANSLITERATION_US = {"kangaroo": 0.22, "biped": 0.45, "quadruped": 0.36}
RUNS = [
    ("hopper", "hop", ["speed=1m/s"]),
    ("kangaroo", "hop", ["speed=3m/s"]),
    ("biped", "run", ["speed=1.5m/s"]),
    ("biped", "gallop", ["speed=1.5m/s"]),
    ("biped", "gallop_human", ["speed=1.5m/s"]),
    ("quadruped", "trot", []),
    ("quadruped", None, []),  # the passive drop
]
DURATION = 5.0
REPEAT = 3  # the C runs and MuJoCo's: the best of this many (the machine is shared)


def identical(a, b) -> bool:  # type: ignore[no-untyped-def]
    same = (a.status, a.message, a.steps, a.events, a.stop_time) == (
        b.status, b.message, b.steps, b.events, b.stop_time)  # fmt: skip
    return same and all(
        getattr(a.trajectory, n).tobytes() == getattr(b.trajectory, n).tobytes() for n in ARRAYS
    )


def bench_runs() -> list[tuple[str, float, float, float, float, bool]]:
    rows = []
    mj_cache: dict[str, tuple[float, float]] = {}
    for name, controller, settings in RUNS:
        session = RunSession.from_file(
            ROOT / "creatures" / f"{name}.leg", generated=ROOT / "generated"
        )
        options = RunOptions(duration=DURATION, drop=0.3 if controller is None else None)
        py = session.run(controller, settings, options=options, backend="python").result
        runs = [session.run(controller, settings, options=options, backend="c").result
                for _ in range(REPEAT)]  # fmt: skip
        same = all(identical(py, r) for r in runs)
        c_rate = max(r.steps / r.wall_time for r in runs)
        if name not in mj_cache:
            q0 = [float(x) for x in py.trajectory.q[0]]
            mj_cache[name] = tuple(  # type: ignore[assignment]
                max(mujoco_drop(name, q0, pads)[0] for _ in range(REPEAT)) / STEP
                for pads in (False, True)
            )
        label = f"{name} {controller or '(drop)'}"
        rows.append((label, py.steps / py.wall_time, c_rate, *mj_cache[name], same))
        print(f"{label}: python {rows[-1][1]:.0f} steps/s, C {rows[-1][2]:.0f}, "
              f"MuJoCo {rows[-1][3]:.0f} (with pads {rows[-1][4]:.0f}), identical {same}",
              flush=True)  # fmt: skip
    return rows


def pinocchio_aba_us(model) -> float:  # type: ignore[no-untyped-def]
    """Microseconds per Pinocchio ``aba`` on the URDF export (``--base free``), called from
    Python as ``mj_forward`` is (tests/lower/test_pinocchio_oracle.py checks the two agree)."""
    import pinocchio as pin

    from legdsl.export.urdf import model_to_urdf

    root = (pin.JointModelFreeFlyer(),) if model.joints[0].is_free_3d else ()
    reference = pin.buildModelFromXML(model_to_urdf(model, base="free"), *root)
    data = reference.createData()
    rng = np.random.default_rng(1)
    q = pin.neutral(reference)
    v, tau = rng.normal(size=reference.nv), rng.normal(size=reference.nv)
    return per_call_us(functools.partial(pin.aba, reference, data, q, v, tau))


def c_forward_dynamics(name: str, q: Any, v: Any, tau: Any) -> Callable[[int], np.ndarray]:
    """A function that calls the creature's C ``forward_dynamics`` at (q, v, tau) ``calls``
    times in a loop inside C (``leg_bench_forward_dynamics``) and returns its result; each
    call of it has arrays of its own, so threads may call it at once."""
    lib = ctypes.CDLL(str(build(name, sources(ROOT / "generated" / name)).path))
    doubles = ctypes.POINTER(ctypes.c_double)
    lib.leg_bench_forward_dynamics.argtypes = [doubles, doubles, doubles, ctypes.c_int64, doubles]

    def loop(calls: int) -> np.ndarray:
        arrays = [np.ascontiguousarray(x, dtype=float) for x in (q, v, tau, np.zeros(len(v)))]
        q_, v_, tau_, out = (a.ctypes.data_as(doubles) for a in arrays)
        lib.leg_bench_forward_dynamics(q_, v_, tau_, calls, out)
        return arrays[3]

    return loop


def bench_dynamics() -> list[tuple[str, float, float, float, float]]:
    import mujoco

    rows = []
    for name in ("kangaroo", "biped", "quadruped", "hopper"):
        session = RunSession.from_file(
            ROOT / "creatures" / f"{name}.leg", generated=ROOT / "generated"
        )
        model = session.model
        q, v, tau = random_state(model, np.random.default_rng(1))
        py_us = per_call_us(
            functools.partial(session.dynamics.forward_dynamics, list(q), list(v), list(tau))
        )
        loop = c_forward_dynamics(name, q, v, tau)
        n = 200_000
        best = float("inf")
        for _ in range(5):
            start = time.perf_counter()
            out = loop(n)
            best = min(best, (time.perf_counter() - start) / n * 1e6)
        assert list(out) == session.dynamics.forward_dynamics(list(q), list(v), list(tau))
        oracle = MuJoCoModel(check_model(ROOT / "creatures" / f"{name}.leg"))
        oracle.set(q, v, tau)
        mj_us = per_call_us(functools.partial(mujoco.mj_forward, oracle.mj, oracle.data))
        pin_us = pinocchio_aba_us(model)
        rows.append((name, py_us, best, mj_us, pin_us))
        print(
            f"{name}: forward_dynamics python {py_us:.1f} us, C {best:.3f} us, mj_forward {mj_us:.1f} us, "
            f"pinocchio aba {pin_us:.2f} us",
            flush=True,
        )
    return rows


def bench_batch() -> tuple[list[tuple[int, float, int, float, float]], dict[int, float]]:
    """N kangaroo hop runs, each with its own commanded speed, as one ``Batch`` in 1 or 2
    threads: (N, run seconds, threads, creature-steps per second per thread, the share of the
    wall time outside C: the batch's setup and results in Python), the whole call timed. And
    the same 256 runs of 0.5 s through ``run_batch`` (each run set up in Python), by threads."""
    from legdsl.pipeline.backend import run_batch
    from legdsl.pipeline.batch import Batch

    session = RunSession.from_file(
        ROOT / "creatures" / "kangaroo.leg", generated=ROOT / "generated"
    )
    Batch(session, 2, "hop", options=RunOptions(duration=0.01)).run()  # built, loaded
    rows = []
    for n, seconds in ((1, 0.5), (16, 0.5), (256, 0.5), (4096, 0.5), (256, 5.0)):
        speeds = (2 + 3 * np.arange(n) / n, "m/s")
        for threads in (1, 2):
            rate, outside = 0.0, 0.0
            for _ in range(REPEAT + 2):  # the best of a few: the host's other work comes and goes
                start = time.perf_counter()
                batch = Batch(session, n, "hop", vary={"speed": speeds},
                              options=RunOptions(duration=seconds))  # fmt: skip
                copies = batch.run(threads)
                wall = time.perf_counter() - start
                assert not copies.rerun and set(copies.status) == {"ok"}
                if copies.steps.sum() / wall / threads > rate:
                    rate = copies.steps.sum() / wall / threads
                    outside = 1 - copies.wall_time / wall
            rows.append((n, seconds, threads, rate, outside))
            print(
                f"batch N={n} of {seconds:g} s, threads={threads}: "
                f"{rate:,.0f} creature-steps/s per thread, {outside:.1%} outside C",
                flush=True,
            )
    jobs = [{"controller": "hop", "settings": [f"speed={2 + 3 * k / 256:.4f}m/s"],
             "options": RunOptions(duration=0.5)} for k in range(256)]  # fmt: skip
    per_run = {}
    for threads in (1, 2):
        best = 0.0
        for _ in range(REPEAT):
            start = time.perf_counter()
            runs = run_batch(session, jobs, threads)
            best = max(best, sum(r.result.steps for r in runs) / (time.perf_counter() - start))
        per_run[threads] = best / threads
        print(f"run_batch N=256, threads={threads}: {best / threads:,.0f} per thread", flush=True)
    return rows, per_run


def c_alone_scaling(name: str = "kangaroo", calls: int = 2_000_000) -> float:
    """Two threads against one on C alone, no Python between calls: the creature's
    ``forward_dynamics`` called ``calls`` times in a loop inside C, once in each of two threads
    at once against twice in one (the best of ``REPEAT``): what the machine's two cores give."""
    import threading

    session = RunSession.from_file(ROOT / "creatures" / f"{name}.leg", generated=ROOT / "generated")
    loop = c_forward_dynamics(name, *random_state(session.model, np.random.default_rng(1)))
    best = 0.0
    for _ in range(REPEAT):
        start = time.perf_counter()
        loop(calls)
        loop(calls)
        one = time.perf_counter() - start
        threads = [threading.Thread(target=loop, args=(calls,)) for _ in range(2)]
        start = time.perf_counter()
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        best = max(best, one / (time.perf_counter() - start))
    print(f"C alone: two threads {best:.2f}x one", flush=True)
    return best


def bench_compile(name: str = "quadruped") -> tuple[float, float, float, float]:
    """(.leg -> generated files, C compiler, load; then the cached .leg -> loaded library)."""
    with tempfile.TemporaryDirectory() as tmp:
        os.environ["LEGDSL_CACHE"] = str(Path(tmp) / "cache")
        start = time.perf_counter()
        compiled = compile_model(ROOT / "creatures" / f"{name}.leg")
        folder = write_generated(compiled, Path(tmp) / "generated")
        printed = time.perf_counter() - start
        built = build(name, sources(folder))
        assert not built.cached
        ctypes.CDLL(str(built.path))
        first = time.perf_counter() - start
        start = time.perf_counter()
        again = build(name, sources(folder))
        ctypes.CDLL(str(again.path))
        cached = time.perf_counter() - start
        assert again.cached and again.path == built.path
        del os.environ["LEGDSL_CACHE"]
        return printed, built.seconds, first, cached


def main() -> None:
    compiler = find_compiler()
    assert compiler is not None, "no C compiler"
    runs = bench_runs()
    dyn = bench_dynamics()
    printed, cc, first, cached = bench_compile()
    batch, per_run = bench_batch()
    alone = c_alone_scaling()
    lines = [
        "## The C backend (issue 14)",
        "",
        "Command: `nice python benchmarks/bench_c_backend.py` "
        f"(Python {platform.python_version()}, {platform.machine()}, {compiler.version}, "
        "2 cores shared with other work, so take the timings as rough).",
        "",
        f"Controlled runs of {DURATION:g} s at the paper's step (semi-implicit Euler, 0.0004 s, "
        "control every 2 ms, recording at 200 Hz); steps per second of the run loop (`RunResult.wall_time`; "
        f"C and MuJoCo: the best of {REPEAT} runs, Python: one). "
        "On the C backend the state machine runs in C too (runtime/machine.c with the generated "
        "control_CONTROLLER.c), so a run enters Python only to start, to grow its recording and "
        "every 20000 steps; the quadruped trots and, without a controller, drops. MuJoCo: `mj_step` (its own loop in C, `nstep`) on the exported MJCF "
        "with its contacts and actuators on, twice: on the bare tree with MuJoCo's own soft "
        "contacts (as in the runtime section, the cheaper for MuJoCo), and as `legdsl export` "
        "writes it by default, whose anchor pads (a small body on two or three slides per foot, "
        "with the `.leg` tangent spring) give MuJoCo legdsl's ground model, so that it drops "
        "within 5 mm of legdsl (docs/export.md). *identical*: the C run's "
        "status, steps, events and every recorded array equal the Python run's byte for byte.",
        "",
        "| run | Python steps/s | C steps/s | MuJoCo mj_step steps/s, bare / with pads | C / Python | C / MuJoCo, bare / with pads | identical |",
        "|---|---|---|---|---|---|---|",
    ]
    for label, py, c, mj, mj_pads, same in runs:
        lines.append(
            f"| {label} | {py:,.0f} | {c:,.0f} | {mj:,.0f} / {mj_pads:,.0f} | {c / py:.1f}x | "
            f"{c / mj:.2f}x / {c / mj_pads:.2f}x | {'yes' if same else 'NO'} |"
        )
    lines += [
        "",
        "`forward_dynamics` at one random state, microseconds per call (C: called 200000 times in a "
        "loop inside C, so no ctypes overhead; its result equals the Python one exactly). "
        "MuJoCo: `mj_forward` with contacts, constraints and actuators off. Pinocchio "
        "(pin 4.1.0): `aba` on the URDF export (`--base free`), the same dynamics to 1e-15 "
        "(tests/lower/test_pinocchio_oracle.py). Both are called from Python, so about a "
        "microsecond of each of their figures is the call.",
        "",
        "| creature | Python | C | MuJoCo mj_forward | Pinocchio aba | Python / C | mj_forward / C | aba / C |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for name, py_us, c_us, mj_us, pin_us in dyn:
        lines.append(
            f"| {name} | {py_us:.1f} | {c_us:.3f} | {mj_us:.2f} | {pin_us:.2f} | "
            f"{py_us / c_us:.0f}x | {mj_us / c_us:.1f}x | {pin_us / c_us:.1f}x |"
        )
    lines += [
        "",
        f"Compile, the quadruped: `.leg` to the generated files {printed:.2f} s, the C compiler "
        f"{cc:.2f} s, `.leg` to a loaded library {first:.2f} s in all; a second build finds the "
        f"library in the cache and loads it in {cached * 1000:.1f} ms (no compiler run).",
    ]
    lines += [
        "",
        "Batched (`legdsl.pipeline.batch.Batch`, docs/runtime.md): N kangaroo hop runs of 0.5 s "
        "(and, in the last row, of 5 s), each with its own commanded speed, as one batch: the "
        "run set up once, its struct's arrays laid out once per copy and each copy's speed "
        "written in with numpy, then runtime/batch.c runs the copies in 1 or 2 threads, one C "
        "call per thread. Creature-steps per second per thread (the best of "
        f"{REPEAT} tries), the whole call timed: the setup, the C and the results (*outside C*: "
        "the share of the wall time in Python). Every copy ran to its end in C (none needed "
        f"Python on the way). Load average {os.getloadavg()[0]:.1f} at the end; this is a "
        "virtual machine whose 2 cores its host shares, so the two-thread figures are a lower "
        "bound.",
        "",
        "| N | run | 1 thread | 2 threads (per thread) | 2 threads / 1 | outside C, 1 / 2 threads |",
        "|---|---|---|---|---|---|",
    ]
    by = {(n, d, t): v for n, d, t, v, _ in batch}
    share = {(n, d, t): o for n, d, t, _, o in batch}
    for n, d in dict.fromkeys((n, d) for n, d, *_ in batch):
        lines.append(
            f"| {n} | {d:g} s | {by[(n, d, 1)]:,.0f} | {by[(n, d, 2)]:,.0f} | "
            f"{2 * by[(n, d, 2)] / by[(n, d, 1)]:.2f}x | "
            f"{share[(n, d, 1)]:.1%} / {share[(n, d, 2)]:.1%} |"
        )
    ratios = [c / mj for _, _, c, mj, _, _ in runs]
    padded = [c / mj_pads for _, _, c, _, mj_pads, _ in runs]
    kangaroo = next(c for label, _, c, *_ in runs if label.startswith("kangaroo"))
    below = [label for label, _, c, mj, _, _ in runs if c / mj < 10]
    aim = (
        "every run reaches the aim of 10x"
        if not below
        else f"below the aim of 10x: {', '.join(below)} (a C step is its forward dynamics, "
        "the contacts' kinematics and Jacobians, the body poses for the ground's torsion, the "
        "controller's sensors every 5 steps and the recording; the forward dynamics alone is "
        "a quarter to a third of it)"
    )
    same = "every run identical" if all(r[5] for r in runs) else "NOT every run identical"
    worst = max(c_us / TRANSLITERATION_US[n] for n, _, c_us, *_ in dyn if n in TRANSLITERATION_US)
    lines += [
        "",
        f"Against the issue's aims: {same}; C runs {min(ratios):.1f}x to "
        f"{max(ratios):.1f}x as many steps per second as MuJoCo's `mj_step` on the bare tree "
        f"({min(padded):.1f}x to {max(padded):.1f}x on the export with anchor pads); {aim}. Forward "
        f"dynamics {worst:.2f} times the issue's transliteration figure at worst (the aim: "
        "within 2x); the quadruped from `.leg` "
        f"to a loaded library in {first:.1f} s (the C compiler {cc:.1f} s), reused from the "
        f"cache the second time. A creature-step of the batch at N = 256 costs "
        f"{kangaroo / by[(256, 0.5, 1)]:.2f} times one of a single 5 s run on the C backend "
        f"(the kangaroo hop row above) and {by[(1, 0.5, 1)] / by[(256, 0.5, 1)]:.2f} times one "
        "of a batch of one 0.5 s run; two threads give "
        f"{2 * by[(256, 0.5, 2)] / by[(256, 0.5, 1)]:.2f} times one thread's throughput at "
        f"N = 256, {2 * by[(4096, 0.5, 2)] / by[(4096, 0.5, 1)]:.2f} at N = 4096 and "
        f"{2 * by[(256, 5.0, 2)] / by[(256, 5.0, 1)]:.2f} at N = 256 with runs of 5 s (the aim: "
        "1.8). The machine's own ceiling, in this run: the kangaroo's `forward_dynamics` looped "
        f"in C with no Python between calls, in two threads at once, gives {alone:.2f} times "
        "one thread's throughput. The same 256 runs as separate jobs "
        "(`legdsl.pipeline.backend.run_batch`: each its own settings, paths or switches, each "
        f"set up and finished in Python, about 0.6 ms a run) give {per_run[1]:,.0f} "
        f"creature-steps per second in one thread and {per_run[2]:,.0f} per thread in two "
        f"({2 * per_run[2] / per_run[1]:.2f}x): there each run's Python takes turns at the "
        "GIL, which the batch leaves only for its setup and results.",
    ]
    replace_section("c-backend", "\n".join(lines))
    print(f"wrote {DOC}")


if __name__ == "__main__":
    # no options: --help says what it measures and where it writes, rather than starting
    argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    ).parse_args()
    main()
