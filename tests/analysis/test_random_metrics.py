"""Runs no one planned through ``legdsl metrics`` and ``legdsl plot``.

Random rigs (tests/random_rigs.py) run passively (the Python backend, half with the default
fall rules, so some runs end by a fall or a divergence), and the shipped creatures run a
controller drawn from their file at a drawn speed, time and recording rate (the C backend; some
fall). Each run is measured and drawn with options drawn for it: a window inside, across or
outside the run, or empty; a reference leg (or contact, for a rig without legs) or a virtual
leg of two; a coordinate with ``--joint`` and ``--against``; ``--min-stance``,
``--friction-edge``, ``--json``, ``--table2``, ``--top``. Every command must end as the docs
say a command ends: 0 with its files written (metrics.json whose numbers are finite or null; a
PNG), or a user's mistake told in lines that start with ``legdsl``, exit 2; never a traceback
or an internal error.

``LEGDSL_RANDOM_METRICS=N`` checks N rigs (default ``CI_RIGS``) and
``LEGDSL_RANDOM_METRICS_GAITS=M`` M gaits (default ``CI_GAITS``), from seed
``LEGDSL_RANDOM_METRICS_SEED``; a failure names its seed and the command, and prints the rig.
"""

from __future__ import annotations

import functools
import json
import math
import os
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from conftest import CREATURES, GENERATED
from runtime_helpers import legdsl_in_process
from seeded import told_with_seed

pytest.importorskip("mujoco")  # the rigs are placed on their ground by MuJoCo's kinematics
from random_rigs import recorded_rig, rig_shown  # noqa: E402

from legdsl.pipeline.session import RunSession  # noqa: E402
from legdsl.sim.trajectory import Trajectory  # noqa: E402

CI_RIGS, CI_GAITS = 1, 1
GAITS = int(os.environ.get("LEGDSL_RANDOM_METRICS_GAITS", CI_GAITS))
TABLE2_ROWS = ("kangaroo hop", "biped run", "quadruped trot", "quadruped bound")
COUNT = int(os.environ.get("LEGDSL_RANDOM_METRICS", CI_RIGS))
FIRST_SEED = int(os.environ.get("LEGDSL_RANDOM_METRICS_SEED", "0"))


def _finite_or_null(value: Any, where: str) -> None:
    """Every number in a metrics.json is finite, or null where it has no value."""
    if isinstance(value, dict):
        for key, inner in value.items():
            _finite_or_null(inner, f"{where}.{key}")
    elif isinstance(value, list):
        for k, inner in enumerate(value):
            _finite_or_null(inner, f"{where}[{k}]")
    elif isinstance(value, float):
        assert math.isfinite(value), f"{where} is {value}"


def _told(status: int, said: str, argv: list[str]) -> None:
    """The command ended as a command may: 0, or a refusal said in legdsl's words."""
    shown = f"legdsl {' '.join(argv)} -> {status}:\n{said}"
    assert "Traceback" not in said and "internal error" not in said, shown
    assert status in (0, 2), shown
    if status == 2:
        assert said.strip().startswith("legdsl"), shown


def _drawn_options(rng: np.random.Generator, run_dir: Path) -> tuple[list[str], list[str]]:
    """Options for ``metrics`` and ``plot`` drawn over the run's contacts and coordinates."""
    recorded = Trajectory.load(run_dir)
    end = float(recorded.t[-1]) if len(recorded) else 0.0
    # what stands (a stride's reference, a group's member): the legs, or each contact
    contacts = list(recorded.leg_names or recorded.contact_names)
    names = list(recorded.q_names)
    metrics: list[str] = []
    plot: list[str] = []
    windows = ["none", "inside", "across", "outside", "empty"]
    window = rng.choice(windows, p=[0.35, 0.35, 0.1, 0.1, 0.1])
    if window == "inside":
        t0 = float(rng.uniform(0, end / 2))
        metrics += ["--from", f"{t0:.4g}", "--to", f"{end:.4g}"]
        plot += ["--from", f"{t0:.4g}"]
    elif window == "across":
        metrics += ["--from", f"{end / 2:.4g}", "--to", f"{end * 3 + 1:.4g}"]
        plot += ["--to", f"{end * 3 + 1:.4g}"]
    elif window == "outside":
        metrics += ["--from", f"{end + 1:.4g}"]
        plot += ["--from", f"{end + 1:.4g}"]
    elif window == "empty":
        metrics += ["--from", f"{end / 2:.4g}", "--to", f"{end / 2:.4g}"]
    if contacts and rng.random() < 0.5:
        metrics += ["--leg", str(rng.choice(contacts))]
    elif len(contacts) >= 2 and rng.random() < 0.5:
        picked = rng.choice(contacts, size=2, replace=False)
        metrics += ["--group", f"pair={picked[0]},{picked[1]}", "--leg", "pair"]
    if rng.random() < 0.3:
        metrics += ["--min-stance", f"{rng.choice([0, 5, 20, 500])}ms"]
    if rng.random() < 0.3:
        metrics += ["--friction-edge", f"{rng.choice([0, 1, 10, 400])}ms"]
    if rng.random() < 0.5:
        metrics += ["--json"]
    elif rng.random() < 0.3:
        metrics += ["--table2", str(rng.choice(TABLE2_ROWS))]
    if names and rng.random() < 0.5:
        metrics += ["--joint", str(rng.choice(names))]
        if rng.random() < 0.5:
            metrics += ["--against", str(rng.choice(names))]
    if rng.random() < 0.5:
        plot += ["--top"]
    return metrics, plot


def check_rig(seed: int, where: Path) -> None:
    rng = np.random.default_rng([seed, 31])
    duration = float(rng.choice([0.05, 0.3, 0.8]))
    record_rate = float(rng.choice([50.0, 200.0, 1000.0]))
    recorded_rig(seed, where, duration, record_rate)
    measure_and_draw(rng, where)


def check_gait(seed: int, where: Path) -> str:
    """A shipped creature's controller drawn, run at a drawn speed for a drawn time (the C
    backend), measured and drawn: strides of legs and groups of legs, Table 2 rows."""
    rng = np.random.default_rng([seed, 32])
    name = str(rng.choice(["hopper", "kangaroo", "biped", "quadruped"]))
    model = _session(name).model
    controller = model.controllers[int(rng.integers(len(model.controllers)))]
    argv = ["run", str(CREATURES / f"{name}.leg"), "--controller", controller.name]
    if "speed" in [i.name for i in controller.inputs]:
        argv += ["--set", f"speed={rng.uniform(0.0, 3.0):.3g}m/s"]
    argv += ["--time", f"{rng.choice([0.5, 2.0, 4.0]):g}", "--out", str(where / "run")]
    argv += ["--record-rate", f"{rng.choice([100.0, 200.0, 1000.0]):g}", "--backend", "c"]
    status, said = legdsl_in_process([*argv, "--generated", str(GENERATED)])
    assert status in (0, 4), f"legdsl {' '.join(argv)} -> {status}: {said}"
    measure_and_draw(rng, where)
    return " ".join(argv)


@functools.cache
def _session(name: str) -> RunSession:
    return RunSession.from_file(CREATURES / f"{name}.leg", generated=GENERATED)


def measure_and_draw(rng: np.random.Generator, where: Path) -> None:
    """``legdsl metrics`` and ``legdsl plot`` of the run in ``where``/run, options drawn."""
    run_dir = where / "run"
    metrics, plot = _drawn_options(rng, run_dir)
    generated = ["--generated", str(where / "generated")]
    argv = ["metrics", str(run_dir), *metrics, *generated]
    status, said = legdsl_in_process(argv)
    _told(status, said, argv)
    if status == 0:
        _finite_or_null(json.loads((run_dir / "metrics.json").read_text()), "metrics.json")
    picture = where / "figure.png"
    argv = ["plot", str(run_dir), "-o", str(picture), *plot]
    status, said = legdsl_in_process(argv)
    _told(status, said, argv)
    if status == 0:
        assert picture.stat().st_size > 1000, f"legdsl {' '.join(argv)}: an empty picture"


@pytest.mark.parametrize("seed", range(FIRST_SEED, FIRST_SEED + COUNT))
def test_a_random_rig_is_measured_and_drawn(seed: int, tmp_path: Path) -> None:
    rerun = f"LEGDSL_RANDOM_METRICS_SEED={seed} LEGDSL_RANDOM_METRICS=1"
    with told_with_seed(f"random rig of seed {seed}", rerun, lambda: rig_shown(seed, tmp_path)):
        check_rig(seed, tmp_path)


@pytest.mark.parametrize("seed", range(FIRST_SEED, FIRST_SEED + GAITS))
def test_a_shipped_gait_at_a_random_command_is_measured_and_drawn(
    seed: int, tmp_path: Path
) -> None:
    rerun = f"LEGDSL_RANDOM_METRICS_SEED={seed} LEGDSL_RANDOM_METRICS_GAITS=1"
    with told_with_seed(f"gait of seed {seed}", rerun, lambda: ""):
        check_gait(seed, tmp_path)
