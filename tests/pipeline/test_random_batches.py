"""Random batches (legdsl.pipeline.batch): the random control laws of tests/random_laws.py on the
hopper and the biped, and the passive random rigs of tests/random_rigs.py, each run as a batch
of 3 to 9 copies with drawn values of their own (the law's inputs and parameters, 0 and negative
among them; actuator settings; a perturbed start), in one thread (``Batch.run``) and in two
(``Creature.run_copies``, the API's). Each copy must be
the single run with its values on the C backend (``RunSession.prepare``, moved to the copy's
start), byte for byte: status, message, steps, events, every recorded array and the law's
records; a copy that faults, falls or diverges ends as its single run does, and the others are
not disturbed by it.

``LEGDSL_RANDOM_BATCHES=N`` checks N laws and N rigs from seed ``LEGDSL_RANDOM_BATCH_SEED``
(default 1), +1, ...; a failure names its seed and prints the law's or rig's text."""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest
from random_laws import law_text
from runtime_helpers import assert_same, needs_c_compiler

from legdsl.api import Creature
from legdsl.ir.model import Model
from legdsl.lang.errors import LegError, UsageError
from legdsl.pipeline.batch import Batch, Copies
from legdsl.pipeline.session import Run, RunSession
from legdsl.sim.run_loop import RunOptions

pytestmark = [
    needs_c_compiler,  # the API tells of a rig's stop too damped for the step, as legdsl run does
    pytest.mark.filterwarnings("ignore:.*too damped for the step:legdsl.api.notes.LegdslWarning"),
]

CI_BATCHES = 1  # law 1 and rig 1 (more: LEGDSL_RANDOM_BATCHES=N)
COUNT = int(os.environ.get("LEGDSL_RANDOM_BATCHES", CI_BATCHES))
FIRST_SEED = int(os.environ.get("LEGDSL_RANDOM_BATCH_SEED", "1"))
SEEDS = range(FIRST_SEED, FIRST_SEED + COUNT)
NO_VALUE = "gives no finite real number"  # a law sympy proves has no value: drawn again
DECLARED = re.compile(r"^\s*(input|param) (\w+) = (\S+) ?(.*)$", re.MULTILINE)


@dataclass
class Drawn:
    """A batch's values: what it varies (each with its unit) and its copies' starts."""

    vary: dict[str, tuple[np.ndarray, str]]
    q0: np.ndarray
    v0: np.ndarray


def _controller_values(rng: np.random.Generator, text: str, n: int) -> dict:
    """Each copy's value of some of the law's inputs and parameters: its default, 0, its
    negative, or a multiple of it from -2 to 2."""
    vary = {}
    for _, name, number, unit in DECLARED.findall(text):
        if rng.random() < 0.2:
            continue
        default = float(number)
        choices = [
            default,
            0.0,
            -default,
            default * rng.uniform(-2, 2),
            default * rng.uniform(-2, 2),
        ]
        vary[name] = (np.array([choices[i] for i in rng.integers(len(choices), size=n)]), unit)
    return vary


def _actuator_values(rng: np.random.Generator, model: Model, n: int) -> dict:
    """Each copy's value of one or two actuator settings: gains and dampings from 0 to their
    default (never stiffer: the step's bound), targets moved, forces of either sign."""
    vary: dict[str, tuple[np.ndarray, str]] = {}
    if not model.actuators:
        return vary
    for i in rng.choice(len(model.actuators), size=min(2, len(model.actuators)), replace=False):
        a = model.actuators[int(i)]
        params = dict(a.params)
        rotary = a.rotary
        if a.kind == "force":
            key, default, unit = "force", params.get("value", 0.0), "N*m" if rotary else "N"
            values = rng.uniform(-1, 1, n) * (20.0 if rotary else 100.0)
        else:
            keys = ("k", "b", "rest") if a.kind == "spring" else ("kp", "kv", "setpoint")
            key = keys[int(rng.integers(3))]
            default = params[key]
            if key in ("rest", "setpoint"):
                unit = "rad" if rotary else "m"
                values = default + rng.uniform(-0.2, 0.2, n) * (1.0 if rotary else 0.1)
            else:
                units = ("N*m/rad", "N*m*s/rad") if rotary else ("N/m", "N*s/m")
                unit = units[keys.index(key)]
                values = default * rng.choice([0.0, 0.5, 1.0, rng.uniform(0, 1)], n)
        values[0] = default  # copy 0 as the file has it
        vary[f"{a.name}.{key}"] = (values, unit)
    return vary


def _starts(rng: np.random.Generator, session: RunSession, q: list[float], v: list[float],
            n: int) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """Copy 0 starts as the single run does; the others perturbed: a free root lifted up to
    3 cm, joints turned or slid a little, every rate nudged."""
    model = session.model
    q0, v0 = np.tile(np.array(q, dtype=float), (n, 1)), np.tile(np.array(v, dtype=float), (n, 1))
    free = model.welded_root is None  # its root's coordinates come first
    root = model.dofs[0].joint if free and model.dofs else None
    for k in range(1, n):
        if rng.random() < 0.2:
            continue  # the template's start, with the others' values
        for d in model.dofs:
            if d.joint == root and d.name == "z":
                q0[k, d.q_index] += rng.uniform(0, 0.03)
            elif d.joint != root and rng.random() < 0.5:
                q0[k, d.q_index] += rng.uniform(-0.05, 0.05) * (0.2 if d.motion == "slide" else 1)
            if rng.random() < 0.5:
                v0[k, d.v_index] += rng.normal(0, 0.2)
    return q0, v0


def _batch(session: RunSession, n: int, controller: str | None, drawn: Drawn,
           options: RunOptions) -> Batch:  # fmt: skip
    """The batch; a copy whose perturbed start puts a contact under the ground (refused, as a
    single run's) starts as the template does instead."""
    for _ in range(n):
        try:
            return Batch(session, n, controller, vary=drawn.vary, q0=drawn.q0, v0=drawn.v0,
                         options=options)  # fmt: skip
        except UsageError as e:
            found = re.match(r"q0 of copy (\d+): ", str(e))
            if found is None:
                raise
            drawn.q0[int(found.group(1))] = drawn.q0[0]
    raise AssertionError("unreachable: every start was the template's")


def _single(session: RunSession, batch: Batch, k: int) -> Run:
    """Copy ``k`` as a single run on the C backend: its texts, moved to its start."""
    plan = session.prepare(batch.controller, batch.texts(k), (), batch.options, backend="c")
    plan.sim.move_to(batch.q0[k].tolist(), batch.v0[k].tolist())
    return plan.finish(plan.sim.run())


def _through_the_api(session: RunSession, batch: Batch) -> Copies:
    """The same batch as ``Creature.run_copies`` makes it (legdsl.api), in two threads."""
    opts = batch.options
    given = {name: (batch._given[name][0], batch._given[name][1]) for name in batch.vary}
    options = {k: getattr(opts, k) for k in ("dt", "control_dt", "record_rate", "fall_height",
                                             "fall_tilt", "drop", "integrator")}  # fmt: skip
    made = Creature(session).run_copies(batch.n, batch.controller, vary=given, q0=batch.q0,
                                        v0=batch.v0, threads=2, time=opts.duration, **options)  # fmt: skip
    assert made.copies.batch.options == opts
    return made.copies


def check_batch(session: RunSession, controller: str | None, drawn: Drawn,
                options: RunOptions) -> list[str]:  # fmt: skip
    """Copies with 1 and 2 threads, each the single run; their statuses."""
    n = len(drawn.q0)
    batch = _batch(session, n, controller, drawn, options)
    singles = [_single(session, batch, k) for k in range(n)]
    for threads in (1, 2):
        copies = batch.run(threads=1) if threads == 1 else _through_the_api(session, batch)
        for k, single in enumerate(singles):
            try:
                assert_same(single.result, copies.result(k))
                assert copies.status[k] == single.status
                if single.machine is not None:
                    m = copies.run(k).machine
                    assert m is not None
                    assert m.events == single.machine.events, "state events"
                    for name in ("state_index", "entered_at", "records", "inputs", "schedule"):
                        mine, its = getattr(m, name), getattr(single.machine, name)
                        assert repr(mine) == repr(its), name  # a record may be NaN
            except BaseException as e:
                if isinstance(e, KeyboardInterrupt):
                    raise
                raise AssertionError(
                    f"copy {k} of {n} ({threads} threads; {batch.texts(k)}, status "
                    f"{single.status}: {single.result.message}): {e}"
                ) from e
    return [r.status for r in singles]


def _law_session(seed: int, folder: Path) -> tuple[RunSession, str]:
    for attempt in range(5):
        text = law_text(seed, attempt)
        path = folder / f"law{seed}_{attempt}.leg"
        path.write_text(text)
        try:
            return RunSession.from_file(path, generated=folder / f"generated{attempt}"), text
        except LegError as error:
            if NO_VALUE not in str(error):
                raise
    pytest.skip(f"random law seed {seed}: 5 laws drawn, each refused: {NO_VALUE}")


def check_law(seed: int, folder: Path) -> None:
    rng = np.random.default_rng([seed, 11])
    session, text = _law_session(seed, folder)
    n = int(rng.integers(3, 10))
    options = RunOptions(duration=float(rng.uniform(0.2, 0.5)),
                         record_rate=float(rng.choice([0.0, 200.0])))  # fmt: skip
    vary = _controller_values(rng, text, n)
    if rng.random() < 0.5:
        vary |= _actuator_values(rng, session.model, n)
    sim = session.prepare("rand", [], options=options, backend="c").sim
    q0, v0 = _starts(rng, session, sim.q, sim.v, n)
    check_batch(session, "rand", Drawn(vary, q0, v0), options)


def check_rig(seed: int, folder: Path) -> None:
    from random_rigs import follow_advice, placed_rig

    rng = np.random.default_rng([seed, 12])
    source, drop = placed_rig(seed, folder)
    falls = rng.random() < 0.5
    options = RunOptions(duration=0.3, drop=drop, record_rate=float(rng.choice([0.0, 200.0])),
                         **({} if falls else {"fall_height": 0.0, "fall_tilt": math.pi}))  # fmt: skip
    for _ in range(4):
        session = RunSession.from_file(source, generated=folder / "generated")
        try:
            sim = session.prepare(None, [], options=options, backend="c").sim
            break
        except LegError as e:  # too stiff for the step: set as the refusal advises
            follow_advice(source, str(e))
    n = int(rng.integers(3, 10))
    q0, v0 = _starts(rng, session, sim.q, sim.v, n)
    vary = _actuator_values(rng, session.model, n)
    check_batch(session, None, Drawn(vary, q0, v0), options)


def _named(kind: str, seed: int, text_of: Path | str, error: BaseException) -> None:
    text = text_of if isinstance(text_of, str) else text_of.read_text()
    pytest.fail(f"random batch {kind} seed {seed}: {error!r}\n{text}", pytrace=False)


@pytest.mark.parametrize("seed", SEEDS)
def test_a_batch_of_a_random_law_is_its_single_runs(seed: int, tmp_path: Path) -> None:
    try:
        check_law(seed, tmp_path)
    except Exception as e:  # noqa: BLE001 -- every way it fails shows the law
        written = sorted(tmp_path.glob("law*.leg"))
        _named("law", seed, written[-1] if written else law_text(seed), e)


@pytest.mark.parametrize("seed", SEEDS)
def test_a_batch_of_a_random_rig_is_its_single_runs(seed: int, tmp_path: Path) -> None:
    pytest.importorskip("mujoco")  # placing a rig on its ground reads MuJoCo's kinematics
    try:
        check_rig(seed, tmp_path)
    except Exception as e:  # noqa: BLE001 -- every way it fails shows the rig
        _named("rig", seed, tmp_path / f"rig{seed}.leg", e)
