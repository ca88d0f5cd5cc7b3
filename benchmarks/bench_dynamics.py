"""Forward-dynamics benchmarks: legdsl's generated code, a sympy Kane baseline, and MuJoCo.

Run from the repository root (it measures this checkout's ``src``):

    python benchmarks/bench_dynamics.py

For each shipped creature it reports microseconds per forward-dynamics
evaluation of (a) ``generated/NAME/dynamics.py`` as legdsl compiles it,
(b) the Kane baseline of ``kane_baseline.py`` (sympy.physics.mechanics,
printed after ``sympy.cse``, solved with ``numpy.linalg.solve``) and (c)
MuJoCo's ``mj_forward`` on the exported MJCF (contacts, constraints and
actuators off); the compile time of (a) and (b) from the .leg file to the
written module, each in a fresh process so that sympy's cache starts cold;
and the accuracy of (a) and (b) against MuJoCo. A scaling study then
compiles generated creatures from 6 to 60 DOF (a many-legged walker and a
serial chain) with both compilers and plots the operation count and the
compile time against DOF into ``docs/img/scaling.png``. Every Kane or legdsl
compile has a time budget (``--budget``); a family stops growing for that
compiler at the first size that exceeds it, and the report says where.
Results go to ``docs/benchmarks.md`` together with the command line.
"""

from __future__ import annotations

import argparse
import ast
import functools
import importlib.util
import json
import multiprocessing as mp
import os
import platform
import sys
import tempfile
import time
import timeit
import traceback
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from types import ModuleType
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))  # measure this checkout, installed or not
sys.path.insert(0, str(Path(__file__).resolve().parent))

import mujoco  # noqa: E402
import numpy as np  # noqa: E402
from report import replace_section  # noqa: E402

from legdsl.check.source import check_model  # noqa: E402
from legdsl.export.mjcf import model_to_mjcf  # noqa: E402
from legdsl.ir.model import Model  # noqa: E402

SHIPPED = ("kangaroo", "biped", "quadruped")
SCALING_DOF = tuple(range(6, 61, 6))
ELEMENTARY = {"sin", "cos", "tan", "sqrt", "exp", "log", "atan2", "asin", "acos", "pow"}


def log(message: str) -> None:
    print(message, flush=True)


# ----------------------------------------------------------------- creatures
GROUND = """
  ground {
    normal spring(k = 2e4 N/m, b = 250 N*s/m)
    tangent spring(k = 1.2e4 N/m, b = 160 N*s/m)
    torsion spring(k = 15 N*m/rad, b = 1 N*m*s/rad)
    friction none
  }
"""


def walker_leg(dof: int) -> str:
    """A 3D free trunk with (dof - 6) / 3 legs (gimbal hip + telescoping shank), in two rows."""
    legs = (dof - 6) // 3
    assert 6 + 3 * legs == dof, dof
    rows = [f"creature walker{dof} {{", "  spatial", "  gravity 9.81 m/s^2", ""]
    rows.append(
        "  body trunk free { mass 10 kg  inertia (0.54, 2.35, 2.39) kg*m^2  "
        "shape box(0.9 m, 0.3 m, 0.15 m)  initial x = 0 m, y = 0 m, z = 0.84 m }"
    )
    per_side = (legs + 1) // 2
    for i in range(legs):
        side, k = (1 if i % 2 == 0 else -1), i // 2
        x = 0.39 - (0.78 * k / (per_side - 1) if per_side > 1 else 0.39)
        rows += [
            f"  body thigh{i} on trunk via gimbal hip{i} at ({x:.4f} m, {0.12 * side} m, 0 m) {{",
            "    length 0.41 m  com 0.2 m  mass 1.5 kg  inertia (0.043, 0.043, 0.0003) kg*m^2",
            "  }",
            f"  body shank{i} on thigh{i} via prismatic leg{i} at tip {{",
            "    length 0.4 m  com 0.2 m  mass 1.0 kg  inertia (0.0035, 0.0035, 0.00005) kg*m^2",
            "  }",
            f"  contact toe{i} on shank{i} at tip",
        ]
    rows += [GROUND, "}", ""]
    return "\n".join(rows)


def chain_leg(dof: int) -> str:
    """A fixed base and ``dof`` hinged links in series, axes alternating y and x."""
    rows = [f"creature chain{dof} {{", "  spatial", "  gravity 9.81 m/s^2", ""]
    rows.append(
        "  body base fixed at (0 m, 0 m, 2 m) { mass 2 kg  inertia (0.02, 0.02, 0.02) kg*m^2 }"
    )
    parent = "base"
    for i in range(dof):
        axis = "(0, 1, 0)" if i % 2 == 0 else "(1, 0, 0)"
        at = "(0 m, 0 m, -0.05 m)" if i == 0 else "tip"
        rows += [
            f"  body link{i} on {parent} via revolute j{i} at {at} {{",
            f"    axis {axis}  length 0.1 m  com 0.05 m  mass 0.2 kg",
            "    inertia (0.0002, 0.0002, 0.00005) kg*m^2",
            "  }",
        ]
        parent = f"link{i}"
    rows += [f"  contact tip on {parent} at tip", GROUND, "}", ""]
    return "\n".join(rows)


FAMILIES: dict[str, Callable[[int], str]] = {"walker": walker_leg, "chain": chain_leg}


# ------------------------------------------------------- isolated compilers
def _compile_worker(kind: str, leg: str, out: str, conn: Any) -> None:
    """Runs in a fresh process: compile ``leg`` with legdsl or Kane, report seconds and path."""
    try:
        if kind == "legdsl":
            from legdsl.pipeline.compile import compile_model
            from legdsl.pipeline.generated import write_generated

            t0 = time.perf_counter()
            compiled = compile_model(leg)
            write_generated(compiled, out)
            seconds = time.perf_counter() - t0
            found = sorted(Path(out).rglob("dynamics.py"))
            if len(found) != 1:
                raise RuntimeError(f"expected one dynamics.py under {out}, found {found}")
            conn.send({"seconds": seconds, "path": str(found[0])})
        else:
            from kane_baseline import compile_kane

            t0 = time.perf_counter()
            model = check_model(leg)
            path = Path(out) / "kane_dynamics.py"
            stages = compile_kane(model, path)
            conn.send({"seconds": time.perf_counter() - t0, "path": str(path), **stages})
    except BaseException:
        conn.send({"error": traceback.format_exc()})
    finally:
        conn.close()


def compile_isolated(kind: str, leg: Path, out: Path, budget: float) -> dict[str, Any]:
    """Compile in a fresh process; {'timeout': budget} if it takes longer than ``budget`` s."""
    ctx = mp.get_context("spawn")
    receiver, sender = ctx.Pipe(duplex=False)
    proc = ctx.Process(target=_compile_worker, args=(kind, str(leg), str(out), sender))
    proc.start()
    sender.close()
    try:
        result: dict[str, Any] = receiver.recv() if receiver.poll(budget) else {"timeout": budget}
    except EOFError:
        result = {"error": f"the {kind} worker died (exit code {proc.exitcode})"}
    proc.join(timeout=5)
    if proc.is_alive():
        proc.kill()
        proc.join()
    return result


def legdsl_available() -> str | None:
    """None if legdsl has the compile entry points (``legdsl.pipeline.compile.compile_model``,
    ``legdsl.pipeline.generated.write_generated``), else why not."""
    try:
        from legdsl.pipeline import compile as driver
        from legdsl.pipeline import generated
    except ImportError as e:
        return f"legdsl.pipeline.compile or .generated is not available ({e})"
    missing = [
        f"{module.__name__}.{n}"
        for module, n in ((driver, "compile_model"), (generated, "write_generated"))
        if not hasattr(module, n)
    ]
    return f"legdsl lacks {', '.join(missing)}" if missing else None


# --------------------------------------------------------------- measuring
def load_module(path: Path, name: str) -> ModuleType:
    spec = importlib.util.spec_from_file_location(name, path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def count_ops(source: str, entry: str = "forward_dynamics") -> int:
    """Arithmetic operators and elementary-function calls in ``entry`` and what it calls.

    Counted statically in the source: each ``+ - * / ** //``, augmented
    assignment, negation of a non-constant and call of sin, cos, sqrt... in
    the body of ``entry`` and of every module-level function it calls,
    transitively (a loop body counts once). Library calls such as
    ``numpy.linalg.solve`` are not counted.
    """
    tree = ast.parse(source)
    funcs = {n.name: n for n in tree.body if isinstance(n, ast.FunctionDef)}
    if entry not in funcs:
        raise ValueError(f"no function {entry} in the module")
    seen: set[str] = set()
    todo = [entry]
    ops = 0
    while todo:
        name = todo.pop()
        if name in seen:
            continue
        seen.add(name)
        for node in ast.walk(funcs[name]):
            if isinstance(node, ast.BinOp | ast.AugAssign):
                ops += 1
            elif isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub):
                ops += not isinstance(node.operand, ast.Constant)
            elif isinstance(node, ast.Call):
                f = node.func
                called = f.id if isinstance(f, ast.Name) else getattr(f, "attr", None)
                if called in funcs:
                    todo.append(called)
                elif called in ELEMENTARY:
                    ops += 1
    return ops


def per_call_us(fn: Callable[[], object]) -> float:
    """Best of 5 repeats of a run of at least 0.2 s, in microseconds per call."""
    timer = timeit.Timer(fn)
    number, _ = timer.autorange()
    return min(timer.repeat(repeat=5, number=number)) / number * 1e6


class MuJoCoModel:
    """The exported MJCF with contacts, constraints and actuators off: smooth dynamics only."""

    def __init__(self, model: Model):
        self.mj = mujoco.MjModel.from_xml_string(model_to_mjcf(model))
        off = mujoco.mjtDisableBit
        self.mj.opt.disableflags |= off.mjDSBL_CONTACT | off.mjDSBL_CONSTRAINT
        self.mj.opt.disableflags |= off.mjDSBL_ACTUATION
        self.data = mujoco.MjData(self.mj)
        self.qmap = np.zeros(model.nq, dtype=int)
        self.vmap = np.zeros(model.nv, dtype=int)
        for j in model.joints:  # by name, as in tests/lower/test_mujoco_oracle.py
            if j.is_free_3d:
                jj = self.mj.joint("root")
                self.qmap[j.q_start : j.q_start + 7] = jj.qposadr[0] + np.arange(7)
                self.vmap[j.v_start : j.v_start + 6] = jj.dofadr[0] + np.arange(6)
            for d in j.dofs:
                self.qmap[d.q_index] = self.mj.joint(d.name).qposadr[0]
                self.vmap[d.v_index] = self.mj.joint(d.name).dofadr[0]

    def set(self, q: np.ndarray, v: np.ndarray, tau: np.ndarray) -> None:
        self.data.qpos[self.qmap] = q
        self.data.qvel[self.vmap] = v
        self.data.qfrc_applied[self.vmap] = tau

    def qacc(self, q: np.ndarray, v: np.ndarray, tau: np.ndarray) -> np.ndarray:
        self.set(q, v, tau)
        mujoco.mj_forward(self.mj, self.data)
        return self.data.qacc_smooth[self.vmap].copy()


def random_state(model: Model, rng: np.random.Generator) -> tuple[np.ndarray, ...]:
    q = np.zeros(model.nq)
    for j in model.joints:
        if j.is_free_3d:
            quat = rng.normal(size=4)
            q[j.q_start : j.q_start + 7] = [*rng.uniform(-1, 1, 3), *(quat / np.linalg.norm(quat))]
        for d in j.dofs:
            q[d.q_index] = rng.uniform(-1, 1) * (1.0 if d.motion == "hinge" else 0.1)
    return q, rng.uniform(-1, 1, model.nv), rng.normal(size=model.nv)


def max_error(fd: Callable[..., Any], model: Model, oracle: MuJoCoModel) -> float:
    """Largest norm-wise relative difference from MuJoCo's qacc over 5 random states."""
    rng = np.random.default_rng(2024)
    worst = 0.0
    for _ in range(5):
        q, v, tau = random_state(model, rng)
        want = oracle.qacc(q, v, tau)
        got = np.asarray(fd(list(q), list(v), list(tau)), dtype=float)
        scale = max(1.0, float(np.linalg.norm(want)))
        worst = max(worst, float(np.linalg.norm(got - want)) / scale)
    return worst


# ---------------------------------------------------------------- results
@dataclass
class Compiled:
    seconds: float | None = None
    ops: int | None = None
    module: ModuleType | None = None
    note: str = ""


@dataclass
class ShippedRow:
    name: str
    dof: int
    compilers: dict[str, Compiled] = field(default_factory=dict)
    us: dict[str, float | None] = field(default_factory=dict)
    error: dict[str, float | None] = field(default_factory=dict)


def run_compiler(
    kind: str, leg: Path, work: Path, budget: float, tag: str, load: bool = True
) -> Compiled:
    out = work / f"{kind}-{tag}"
    log(f"  {kind:6s} compiling {leg.name} (budget {budget:.0f} s) ...")
    result = compile_isolated(kind, leg, out, budget)
    if "timeout" in result:
        log(f"  {kind:6s} {leg.name}: over the {budget:.0f} s budget, stopped")
        return Compiled(note=f"> {budget:.0f} s (stopped)")  # plot() reads the budget back
    if "error" in result:
        first = result["error"].strip().splitlines()[-1]
        log(f"  {kind:6s} {leg.name}: FAILED\n{result['error']}")
        return Compiled(note=f"failed: {first}")
    path = Path(result["path"])
    module = load_module(path, f"_bench_{kind}_{tag}") if load else None
    ops = count_ops(path.read_text())
    log(f"  {kind:6s} {leg.name}: {result['seconds']:.2f} s, {ops} operations")
    return Compiled(seconds=result["seconds"], ops=ops, module=module)


def bench_shipped(work: Path, budget: float, legdsl_reason: str | None) -> list[ShippedRow]:
    rows = []
    for name in SHIPPED:
        leg = ROOT / "creatures" / f"{name}.leg"
        model = check_model(leg)
        log(f"{name} ({model.nv} DOF)")
        row = ShippedRow(name, model.nv)
        oracle = MuJoCoModel(model)
        for kind in ("legdsl", "kane"):
            if kind == "legdsl" and legdsl_reason:
                row.compilers[kind] = Compiled(note="n/a")
            else:
                row.compilers[kind] = run_compiler(kind, leg, work, budget, name)
            c = row.compilers[kind]
            row.us[kind] = row.error[kind] = None
            if c.module is not None:
                fd = c.module.forward_dynamics
                q, v, tau = random_state(model, np.random.default_rng(1))
                qs, vs, ts = list(q), list(v), list(tau)
                row.error[kind] = max_error(fd, model, oracle)
                row.us[kind] = per_call_us(functools.partial(fd, qs, vs, ts))
                log(
                    f"  {kind:6s} forward dynamics: {row.us[kind]:.1f} us/call, "
                    f"max rel. error vs MuJoCo {row.error[kind]:.1e}"
                )
        q, v, tau = random_state(model, np.random.default_rng(1))
        oracle.set(q, v, tau)
        row.us["mujoco"] = per_call_us(functools.partial(mujoco.mj_forward, oracle.mj, oracle.data))
        log(f"  mujoco mj_forward: {row.us['mujoco']:.1f} us/call")
        rows.append(row)
    return rows


def bench_scaling(
    work: Path, budget: float, legdsl_reason: str | None, sizes: tuple[int, ...]
) -> dict[str, dict[str, dict[int, Compiled]]]:
    """family -> compiler -> DOF -> result; a compiler stops at its first size over budget."""
    results: dict[str, dict[str, dict[int, Compiled]]] = {}
    for family, make in FAMILIES.items():
        results[family] = {"legdsl": {}, "kane": {}}
        stopped = {"legdsl": bool(legdsl_reason), "kane": False}
        for dof in sizes:
            if family == "walker" and (dof - 6) % 3:
                continue
            leg = work / f"{family}{dof}.leg"
            leg.write_text(make(dof))
            model = check_model(leg)  # the generator must write valid .leg text
            assert model.nv == dof, (family, dof, model.nv)
            log(f"{family} {dof} DOF")
            for kind in ("legdsl", "kane"):
                if stopped[kind]:
                    continue
                # Only counts and times are plotted: the module is not imported.
                c = run_compiler(kind, leg, work, budget, f"{family}{dof}", load=False)
                results[family][kind][dof] = c
                stopped[kind] = c.seconds is None
    return results


# ----------------------------------------------------------------- report
def fmt(x: float | None, spec: str, missing: str = "n/a") -> str:
    return missing if x is None else format(x, spec)


def plot(results: dict[str, dict[str, dict[int, Compiled]]], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax_ops, ax_time) = plt.subplots(1, 2, figsize=(11, 4.2))
    styles = {"legdsl": "-o", "kane": "--s"}
    colors = {"walker": "#4070b0", "chain": "#b04040"}
    for family, by_kind in results.items():
        for kind, points in by_kind.items():
            done = sorted((d, c) for d, c in points.items() if c.seconds is not None)
            if not done:
                continue
            dofs = [d for d, _ in done]
            label = f"{'legdsl' if kind == 'legdsl' else 'Kane (sympy)'}, {family}"
            ax_ops.plot(dofs, [c.ops for _, c in done], styles[kind], color=colors[family],
                        label=label)  # fmt: skip
            ax_time.plot(dofs, [c.seconds for _, c in done], styles[kind], color=colors[family],
                         label=label)  # fmt: skip
            over = [d for d, c in points.items() if c.seconds is None]
            if over:  # an x at the budget, where the compiler was stopped
                budget = float(points[min(over)].note.split()[1])
                ax_time.plot([min(over)], [budget], "x", color=colors[family], markersize=10)
                ax_time.annotate(
                    f"{label}: stopped at {min(over)} DOF",
                    (min(over), budget),
                    textcoords="offset points",
                    xytext=(8, -3),
                    ha="left",
                    fontsize=8,
                    color=colors[family],
                )
    for ax, title, unit in (
        (ax_ops, "Operations in forward_dynamics (static count)", "operations"),
        (ax_time, "Compile time, .leg to written module", "seconds"),
    ):
        ax.set_yscale("log")
        ax.set_xlabel("degrees of freedom")
        ax.set_ylabel(unit)
        ax.set_title(title, fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110, metadata={"Software": None})
    plt.close(fig)


def save_scaling(results: dict[str, dict[str, dict[int, Compiled]]], path: Path) -> None:
    """The scaling numbers as JSON beside the plot, so that ``--replot`` can redraw it."""
    raw = {
        family: {
            kind: {
                str(d): {"seconds": c.seconds, "ops": c.ops, "note": c.note} for d, c in pts.items()
            }
            for kind, pts in by_kind.items()
        }
        for family, by_kind in results.items()
    }
    path.write_text(json.dumps(raw, indent=1, sort_keys=True) + "\n")


def load_scaling(path: Path) -> dict[str, dict[str, dict[int, Compiled]]]:
    raw = json.loads(path.read_text())
    return {
        family: {
            kind: {
                int(d): Compiled(c["seconds"], c["ops"], None, c["note"]) for d, c in pts.items()
            }
            for kind, pts in by_kind.items()
        }
        for family, by_kind in raw.items()
    }


def report(
    command: str,
    shipped: list[ShippedRow],
    scaling: dict[str, dict[str, dict[int, Compiled]]],
    legdsl_reason: str | None,
    budget: float,
    plot_path: Path,
) -> str:
    lines = [
        "## Forward dynamics and compilation (issue 3)",
        "",
        "Produced by",
        "",
        "```",
        command,
        "```",
        "",
        f"on {platform.machine()} with Python {platform.python_version()}, "
        f"MuJoCo {mujoco.__version__}, sympy {__import__('sympy').__version__}, "
        f"numpy {np.__version__}, {os.cpu_count()} CPUs (shared with other jobs, so "
        "take the timings as rough). Times are the best of 5 runs.",
        "",
        "* **legdsl**: `forward_dynamics(q, v, tau)` of the module that `legdsl.pipeline.compile` generates.",
        "* **Kane**: `benchmarks/kane_baseline.py` builds the same model with "
        "`sympy.physics.mechanics.KanesMethod` (same coordinates and speeds as legdsl, "
        "quaternion free root), prints the mass matrix and forcing after `sympy.cse` "
        "(as PyDy does) and solves with `numpy.linalg.solve`.",
        "* **MuJoCo**: `mj_forward` on the MJCF from `legdsl export`, with contacts, "
        "constraints and actuators disabled.",
        "* **error**: largest norm-wise relative difference of the accelerations from "
        "MuJoCo's `qacc_smooth` over 5 random states with random applied forces.",
        "* **ops**: arithmetic operators and elementary-function calls in "
        "`forward_dynamics` and the module functions it calls, counted in the source "
        "(a loop body counts once; `numpy.linalg.solve` in the Kane module is not counted, "
        "about n^3/3 multiply-adds at run time).",
        "* **compile**: seconds from the .leg file to the written module, in a fresh "
        "process (parse, check, derive, simplify, print, write).",
        "",
    ]
    if legdsl_reason:
        lines += [f"**legdsl columns are missing: {legdsl_reason}.**", ""]
    lines += [
        "## Shipped creatures",
        "",
        "| creature | DOF | legdsl us/call | Kane us/call | MuJoCo us/call | "
        "legdsl compile s | Kane compile s | legdsl ops | Kane ops | legdsl error | Kane error |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in shipped:
        a, k = r.compilers["legdsl"], r.compilers["kane"]
        lines.append(
            f"| {r.name} | {r.dof} | {fmt(r.us['legdsl'], '.1f')} | {fmt(r.us['kane'], '.1f')} "
            f"| {fmt(r.us['mujoco'], '.1f')} | {fmt(a.seconds, '.2f', a.note)} "
            f"| {fmt(k.seconds, '.2f', k.note)} | {fmt(a.ops, 'd')} | {fmt(k.ops, 'd')} "
            f"| {fmt(r.error['legdsl'], '.1e')} | {fmt(r.error['kane'], '.1e')} |"
        )
    lines += [
        "",
        "## Scaling with the number of degrees of freedom",
        "",
        "Generated creatures: **walker** is a 3D free trunk with (DOF - 6) / 3 legs "
        "(gimbal hip and telescoping shank, like the quadruped's); **chain** is a fixed "
        "base with DOF hinged links in series, axes alternating y and x. "
        f"Each compile has a budget of {budget:.0f} s; a compiler stops growing a family "
        "at its first size over budget.",
        "",
        f"![operation count and compile time against DOF]({os.path.relpath(plot_path, ROOT / 'docs')})",
        "",
    ]
    for family, by_kind in scaling.items():
        dofs = sorted(set(by_kind["legdsl"]) | set(by_kind["kane"]))
        lines += [
            f"### {family}",
            "",
            "| DOF | legdsl ops | Kane ops | legdsl compile s | Kane compile s |",
            "|---:|---:|---:|---:|---:|",
        ]
        for d in dofs:
            a = by_kind["legdsl"].get(d, Compiled(note="not run"))
            k = by_kind["kane"].get(d, Compiled(note="not run"))
            lines.append(
                f"| {d} | {fmt(a.ops, 'd', a.note or 'n/a')} | {fmt(k.ops, 'd', k.note or 'n/a')} "
                f"| {fmt(a.seconds, '.2f', a.note or 'n/a')} | {fmt(k.seconds, '.2f', k.note or 'n/a')} |"
            )
        for kind, points in by_kind.items():
            over = sorted(d for d, c in points.items() if c.seconds is None)
            if over:
                last = max((d for d, c in points.items() if c.seconds is not None), default=None)
                lines.append("")
                lines.append(
                    f"{'legdsl' if kind == 'legdsl' else 'Kane'} stopped at {over[0]} DOF "
                    f"(over the {budget:.0f} s budget); the largest it finished is "
                    f"{last if last is not None else 'none'} DOF."
                )
        lines.append("")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--budget", type=float, default=300.0, help="seconds per compile (300)")
    p.add_argument(
        "--sizes",
        type=lambda s: tuple(int(x) for x in s.split(",")),
        default=SCALING_DOF,
        help="comma-separated DOF for the scaling study (6,12,...,60)",
    )
    p.add_argument("--out", type=Path, default=ROOT / "docs" / "benchmarks.md")
    p.add_argument("--plot", type=Path, default=ROOT / "docs" / "img" / "scaling.png")
    p.add_argument(
        "--replot",
        action="store_true",
        help="only redraw the plot from the JSON beside it (PLOT with .json) and stop",
    )
    argv = sys.argv[1:] if argv is None else argv
    args = p.parse_args(argv)
    data = args.plot.with_suffix(".json")
    if args.replot:
        if not data.exists():
            log(f"{data} is missing: run the benchmark once without --replot to write it")
            return 2
        plot(load_scaling(data), args.plot)
        log(f"wrote {args.plot} from {data}")
        return 0
    command = " ".join(["python benchmarks/bench_dynamics.py", *argv])
    legdsl_reason = legdsl_available()
    if legdsl_reason:
        log(f"!!! {legdsl_reason}: legdsl columns will be empty !!!")
    with tempfile.TemporaryDirectory(prefix="legdsl-bench-") as tmp:
        work = Path(tmp)
        log("== shipped creatures ==")
        shipped = bench_shipped(work, args.budget, legdsl_reason)
        log("== scaling study ==")
        scaling = bench_scaling(work, args.budget, legdsl_reason, args.sizes)
    plot(scaling, args.plot)
    save_scaling(scaling, data)
    log(f"wrote {args.plot} and {data}")
    text = report(command, shipped, scaling, legdsl_reason, args.budget, args.plot)
    replace_section("dynamics", text, args.out)
    log(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
