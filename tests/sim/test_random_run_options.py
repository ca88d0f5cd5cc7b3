"""Random run options: ``legdsl run`` on the shipped creatures (creatures/*.leg) and the outside
ones (tests/good/outside/*.leg) with the options people outside the team combine, drawn from
a seeded generator: ``--set`` of a controller's inputs and parameters (in their units, within
and somewhat outside their sensible range, now and then changed during the run: ``@T``), of
a switched-to controller's own (``bound.k_speed=...``) and of actuator settings
(``hip_servo.setpoint=10deg``); ``--switch`` to the creature's controllers (at 0, during the
run, past its end); ``--path`` shapes and waypoint files for the controllers that follow a
path; ``--scene`` with more ``--set``, ``--switch`` and ``--time``; ``--integrator``, ``--dt``,
``--control-dt``, ``--record-rate`` (0 and odd values, in ms or Hz), ``--drop``,
``--fall-height``, ``--fall-tilt`` and ``--scale``. Runs are short (0.2 to 0.6 s).

Each case runs in this process (``legdsl.cli.main``) with ``--backend python`` and
``--backend c``, and must: exit 0, 2, 3 or 4, the same on both; never print a traceback or
an internal error; for 0, 3 and 4 leave byte-identical trajectory.npz arrays and the same
run.json; for 2 say the same one-line message (or file:line:col with a caret) on both.

``LEGDSL_RANDOM_RUNS=N`` checks N cases (default ``CI_RUNS``) from seeds
``LEGDSL_RANDOM_RUN_SEED``, +1, ...; a failure names its seed and the command to repeat it.
CI draws the shipped creatures, a set ``LEGDSL_RANDOM_RUNS`` every creature
(``LEGDSL_RANDOM_RUN_POOL=shipped`` or ``all`` says which).
"""

from __future__ import annotations

import json
import os
import shlex
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest
from runtime_helpers import is_compile_notice, legdsl_in_process, needs_c_compiler
from seeded import told_with_seed
from set_values import in_unit, models, number

from legdsl.ir.model import SETTABLE, Model, setting_kind
from legdsl.lang.units import KINDS, Dim

ROOT = Path(__file__).resolve().parents[2]
SHIPPED = sorted((ROOT / "creatures").glob("*.leg"))
OUTSIDE = sorted((ROOT / "tests" / "good" / "outside").glob("*.leg"))
CI_RUNS = 6  # about 12 s: the python backend is the cost
COUNT = int(os.environ.get("LEGDSL_RANDOM_RUNS", CI_RUNS))
FIRST_SEED = int(os.environ.get("LEGDSL_RANDOM_RUN_SEED", "0"))
# CI draws the shipped creatures only (their generated code is checked in; an outside one
# compiles for 3 to 13 s); a run of more cases draws all, unless told
POOL = os.environ.get(
    "LEGDSL_RANDOM_RUN_POOL", "all" if "LEGDSL_RANDOM_RUNS" in os.environ else "shipped"
)
ALLOWED = {0, 2, 3, 4}

pytestmark = needs_c_compiler


def _scaled(rng: np.random.Generator, value: float, dim: Dim) -> str:
    """A value near ``value`` (in its sensible range), or somewhat outside it."""
    factor = float(rng.choice([0.0, 0.5, 0.9, 1.0, 1.2, 2.0, 4.0, 10.0, -1.0]))
    base = value if value != 0 else float(rng.uniform(0.1, 2.0))
    return in_unit(base * factor, dim)


def _at(rng: np.random.Generator, end: float) -> str:
    """A time in the run, now and then at its start or past its end."""
    at = float(rng.choice([0.0, end + 1] + [rng.uniform(0, end)] * 6))
    return f"@{number(at)}s"


def _controller_sets(rng: np.random.Generator, model: Model, name: str, own: bool, end: float):
    ctl = model.controller(name)
    values = [*ctl.inputs, *ctl.params]
    out = []
    for c in rng.choice(values, size=min(len(values), int(rng.integers(0, 4))), replace=False):
        text = f"{name + '.' if own else ''}{c.name}={_scaled(rng, c.value, c.dim)}"
        # only an input changes during a run: a parameter's @T, now and then, is refused
        if rng.random() < (0.5 if c in ctl.inputs and not own else 0.05):
            text += _at(rng, end)
        out += ["--set", text]
    return out


def _actuator_sets(rng: np.random.Generator, model: Model) -> list[str]:
    out = []
    for _ in range(int(rng.integers(0, 3))):
        act = model.actuators[int(rng.integers(len(model.actuators)))]
        key = str(rng.choice(SETTABLE[act.kind]))
        dim = KINDS[setting_kind(key, act.rotary)][0]
        current = dict(act.params).get(key, 0.0)
        out += ["--set", f"{act.name}.{key}={_scaled(rng, current, dim)}"]
    return out


def _path(rng: np.random.Generator, folder: Path) -> list[str]:
    shape = int(rng.integers(5))
    turn = str(rng.choice(["left", "right"]))
    if shape == 0:
        text = f"circle(center = (0, {number(rng.uniform(1, 8))}) m, radius = "
        text += f"{number(rng.uniform(0.5, 8))} m, turn = {turn})"
    elif shape == 1:
        points = np.cumsum(rng.uniform(-3, 3, (int(rng.integers(2, 5)), 2)), axis=0)
        text = "polyline(" + ", ".join(f"({number(x)}, {number(y)}) m" for x, y in points)
        text += ")"
    elif shape == 2:
        points = [(0, 0), (4, 0), (float(rng.uniform(2, 6)), float(rng.uniform(2, 6)))]
        text = "polygon(" + ", ".join(f"({number(x)}, {number(y)}) m" for x, y in points)
        text += f", lookahead = {number(rng.uniform(0.2, 3))} m)"
    elif shape == 3:
        text = f"square(corner = (0, 0) m, side = {number(rng.uniform(1, 10))} m, turn = {turn})"
    else:
        csv = folder / "waypoints.csv"
        points = np.cumsum(rng.uniform(0, 2, (int(rng.integers(2, 6)), 2)), axis=0)
        csv.write_text("".join(f"{number(x)},{number(y)}\n" for x, y in points))
        text = str(csv)
    return ["--path", text]


OPTIONS = {
    "--integrator": ["rk4", "euler"],
    "--dt": ["0.2ms", "0.39ms", "4e-4", "0.5ms", "0.25ms", "1ms"],
    "--control-dt": ["1ms", "2ms", "3ms", "0.0025", "5ms", "0.77ms"],
    "--record-rate": ["0", "150Hz", "77", "200Hz", "1000", "333Hz"],
    "--drop": ["0", "1cm", "0.05", "10cm", "0.3"],
    "--fall-height": ["0", "0.1m", "5cm", "1", "30cm"],
    "--fall-tilt": ["30deg", "1rad", "90", "180deg", "5"],
    "--scale": ["0.5", "2", "1.5", "0.8", "1"],
}


@dataclass
class Case:
    source: Path
    argv: list[str]  # after FILE, without --backend, --out and --generated

    def command(self, backend: str = "c") -> str:
        words = ["legdsl", "run", str(self.source.relative_to(ROOT)), *self.argv]
        return shlex.join([*words, "--backend", backend, "--out", "runs/random"])


def draw(seed: int, folder: Path, outside: bool) -> Case:
    rng = np.random.default_rng([seed, 31])
    source = Path(rng.choice(SHIPPED + OUTSIDE if outside else SHIPPED))
    all_models = models(source)
    model = all_models[int(rng.integers(len(all_models)))]
    argv: list[str] = ["--creature", model.name] if len(all_models) > 1 else []
    end = float(rng.uniform(0.2, 0.6))
    argv += ["--time", f"{number(end)}s"]
    names = [c.name for c in model.controllers]
    running: str | None = None
    if model.scenes and rng.random() < 0.3:
        scene = model.scenes[int(rng.integers(len(model.scenes)))]
        argv += ["--scene", scene.name]
        running = scene.controller
    elif names and rng.random() < 0.9:
        running = str(rng.choice(names))
        argv += ["--controller", running]
    if running is not None:
        argv += _controller_sets(rng, model, running, False, end)
        for _ in range(int(rng.choice([0, 0, 1, 2]))):
            other = str(rng.choice(names))
            argv += ["--switch", f"{_at(rng, end)[1:]}={other}"]
            if rng.random() < 0.4:
                argv += _controller_sets(rng, model, other, True, end)
        if model.controller(running).paths and rng.random() < 0.6:
            argv += _path(rng, folder)
            if rng.random() < 0.1:  # one path given twice: refused
                argv += _path(rng, folder)
    argv += _actuator_sets(rng, model)
    for flag in rng.choice(sorted(OPTIONS), size=int(rng.integers(0, 4)), replace=False):
        argv += [str(flag), str(rng.choice(OPTIONS[flag]))]
    return Case(source, argv)


def _said(err: str) -> str:
    """What a run said but the note that its generated code was (first) compiled or copied."""
    return "".join(x for x in err.splitlines(True) if not is_compile_notice(x))


def _run_json(out: Path) -> dict[str, object]:
    return json.loads((out / "run.json").read_text())


def _one_message(err: str) -> bool:
    """A usage error: one line, or a file:line:col error with its caret (after any notes)."""
    lines = [x for x in err.splitlines() if x.strip() and not x.startswith("legdsl: note:")]
    return len(lines) == 1 or any(line.strip().startswith("^") for line in lines)


def check_case(case: Case, folder: Path, generated: Path) -> tuple[int, str]:
    """Check one case; its exit status and what it said."""
    said: dict[str, tuple[int, str]] = {}
    for backend in ("python", "c"):
        out = folder / backend
        argv = ["run", str(case.source), *case.argv, "--backend", backend]
        code, err = legdsl_in_process([*argv, "--generated", str(generated), "--out", str(out)])
        said[backend] = code, _said(err)
        assert "Traceback" not in err and "internal error" not in err, err
        assert code in ALLOWED, f"exit {code}\n{err}"
    (python, perr), (c, cerr) = said["python"], said["c"]
    assert python == c, f"exit {python} (python) vs {c} (c)\n{perr}\n{cerr}"
    if python == 2:
        assert perr == cerr, f"python said:\n{perr}\nc said:\n{cerr}"
        assert _one_message(perr), f"not one line:\n{perr}"
        return python, perr
    a, b = folder / "python", folder / "c"
    assert _run_json(a) == _run_json(b)
    with np.load(a / "trajectory.npz") as pa, np.load(b / "trajectory.npz") as pb:
        assert pa.files == pb.files
        for name in pa.files:
            assert pa[name].tobytes() == pb[name].tobytes(), f"{name} differs"
    return python, perr


def _waypoints(folder: Path) -> str:
    csv = folder / "waypoints.csv"
    return f"\nwith {csv}:\n{csv.read_text()}" if csv.exists() else ""


SEEDS = range(FIRST_SEED, FIRST_SEED + COUNT)


@pytest.mark.parametrize("seed", SEEDS)
def test_random_run_options_run_alike_on_both_backends(
    seed: int, tmp_path: Path, generated: Path
) -> None:
    case = draw(seed, tmp_path, POOL == "all")
    rerun = f"LEGDSL_RANDOM_RUN_SEED={seed} LEGDSL_RANDOM_RUNS=1 LEGDSL_RANDOM_RUN_POOL={POOL}"
    shown = lambda: f"{case.command()}{_waypoints(tmp_path)}"  # noqa: E731
    with told_with_seed(f"random run options of seed {seed}", rerun, shown):
        check_case(case, tmp_path, generated)
