"""Dynamic scaling (Raibert & Hodgins 1991, Table 1; docs/scaling.md) on creatures no one wrote:
the random rigs of tests/random_rigs.py (planar and 3D, free and welded roots, every joint kind,
templates with mirrored instances, every actuator kind, limits and stops, every ground and
terrain), each scaled by L = 4 (sqrt(L) = 2: every factor a power of two, the arithmetic exact)
and by L = 0.37 (no factor a binary fraction).

For each L:

1. ``legdsl scale FILE --by L -o OUT.leg`` writes a file that checks and compiles, and its run
   agrees with ``legdsl run FILE --scale L`` (same status, every recorded channel within 1e-9
   of the larger value, as tests/pipeline/test_scaling.py compares);
2. dynamic similarity: OUT's run, its times divided by sqrt(L), lengths by L, forces by L^3 and
   so on, is the run of FILE over the same (unscaled) window -- anything the scaler forgets (a
   terrain dimension, a pad thickness, a drop, an initial velocity) shows here, as a fall or a
   divergence that comes at another time.

The same for the random control laws of tests/random_laws.py on the hopper and the biped.

``LEGDSL_RANDOM_SCALING=N`` checks N rigs (default ``CI_RIGS``) from seed
``LEGDSL_RANDOM_SCALING_SEED`` (default 0), +1, ...; ``LEGDSL_RANDOM_SCALING_LAWS=N`` and
``LEGDSL_RANDOM_SCALING_LAW_SEED=S`` the laws (default ``CI_LAWS``); a failure names its seed
and prints the rig's or the law's text.
"""

from __future__ import annotations

import contextlib
import dataclasses
import functools
import io
import math
import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from seeded import told_with_seed

from legdsl.cli import main
from legdsl.lang.errors import LegError
from legdsl.lang.scaling import scale_name
from legdsl.pipeline.scaled import run_options, scale_result
from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import CHECK_INTERVAL, RunResult
from legdsl.sim.sizes import DIVERGENCE_SPEED
from legdsl.sim.trajectory import ARRAYS

mujoco = pytest.importorskip("mujoco")  # random_rigs places welded roots with MuJoCo
from random_laws import law_text  # noqa: E402
from random_rigs import follow_advice, placed_rig, rig_shown  # noqa: E402

CI_RIGS = 1  # with rig 9 below and one law: about 20 s
COUNT = int(os.environ.get("LEGDSL_RANDOM_SCALING", CI_RIGS))
FIRST_SEED = int(os.environ.get("LEGDSL_RANDOM_SCALING_SEED", "0"))
DURATION = 0.25  # s of the unscaled rig: short, before rounding grows in a chaotic run
SCALES = (4.0, 0.37)
BACKEND = os.environ.get("LEGDSL_RANDOM_SCALING_BACKEND", "python")
NEAR_DIVERGENCE = DIVERGENCE_SPEED / 2  # m/s or rad/s: half the least divergence limit
ROUNDING_HORIZON = 1e-9  # a twin run this far off: the rig has carried rounding far enough


ENERGIES = (  # J: compared against the largest of them
    "leg_spring_energy", "kinetic", "potential", "elastic", "work_positive", "work_negative",
)  # fmt: skip


def _magnitude(*runs: RunResult, names: tuple[str, ...]) -> float:
    """The largest finite magnitude of the channels ``names`` in ``runs``."""
    values = [getattr(run.trajectory, name).astype(float) for run in runs for name in names]
    return max((float(np.abs(x[np.isfinite(x)]).max(initial=0.0)) for x in values), default=0.0)


def sample_differences(a: RunResult, b: RunResult) -> np.ndarray:
    """Each sample's largest difference of two runs' recorded values, each relative to the
    larger of the two (with a floor of 1e-9 of the channel's magnitude, for values that cross
    zero; for the energies and work, of all of them: a spring that barely moves does work of
    1e-24 J in one run and 1e-42 J in the other, rounding both, against a run's joules: seed
    700000)."""
    x_traj, y_traj = a.trajectory, b.trajectory
    assert len(x_traj) == len(y_traj) > 0, (len(x_traj), len(y_traj))
    energy = _magnitude(a, b, names=ENERGIES)
    worst = np.zeros(len(x_traj))
    for name in ARRAYS:
        x, y = getattr(x_traj, name).astype(float), getattr(y_traj, name).astype(float)
        assert x.shape == y.shape, name
        assert (np.isnan(x) == np.isnan(y)).all(), name
        both = np.isfinite(x) & np.isfinite(y)
        if not both.any():
            continue
        own = max(float(np.abs(x[both]).max()), float(np.abs(y[both]).max()))
        floor = 1e-9 * max(energy if name in ENERGIES else own, own, 1e-300)
        with np.errstate(invalid="ignore"):
            rel = np.abs(x - y) / np.maximum(np.maximum(np.abs(x), np.abs(y)), floor)
        rel = np.where(both, rel, 0.0).reshape(len(rel), -1)
        worst = np.maximum(worst, rel.max(axis=1, initial=0.0))
    return worst


def assert_alike(
    a: RunResult,
    b: RunResult,
    twin_of_b: Callable[[], RunResult],
    tolerance: float,
    what: str,
    within: float = 0.0,
) -> None:
    """``a`` and ``b``, two runs of one motion whose arithmetic differs by rounding, end alike
    (``_same_ending``) and agree to ``tolerance`` in the samples both have (``_common``).
    Where they do not, ``b``'s twin (its run from a start one ulp away) tells how far this rig
    carries a rounding difference. An ending the twin does not share depends on rounding
    (seed 720014 at L = 0.37 spins a joint up to the divergence limit at 0.029 s, its twin at
    0.045 s, the scaled file not in its 0.15 s), so either may come. The samples are held to
    agree before the one where the twin departs from ``b`` by 1e-9 (seed 710005 at L = 0.37
    doubles a rounding difference every 7 samples, 1.7 ms: 1e-9 at sample 76, 1e-5 at 150,
    then a foot touches in one run and not the other; its twin departs at sample 43). A
    scaling mistake shows from the first samples (that rig's scaled file with gravity 1e-6
    off: 1e-6 at sample 1)."""
    twin = functools.cache(twin_of_b)
    differs = _ending_difference(a, b, within)
    assert differs is None or _ending_difference(twin(), b, within), f"{what}: {differs}"
    if not (len(a.trajectory) and len(b.trajectory)):
        return  # one stopped before its first sample
    both = _common(a, b)
    differences = sample_differences(_first(a, both), _first(b, both))
    if differences.max() < tolerance:
        return
    both = min(both, _common(twin(), b))
    spread = sample_differences(_first(twin(), both), _first(b, both))
    departs = np.flatnonzero(spread > ROUNDING_HORIZON)
    horizon = int(departs[0]) if departs.size else both
    worst = float(differences[:horizon].max(initial=0.0))
    assert worst < tolerance, (
        f"{what} differ by {worst:.3g} before sample {horizon}, where a twin run from a start one ulp"
        f" away departs by {ROUNDING_HORIZON:g} (at its worst {spread.max():.3g})"
    )


def _ending_difference(a: RunResult, b: RunResult, within: float = 0.0) -> str | None:
    """How two runs' endings differ: their status, or their times by more than ``within`` s
    (inf: either may end first); None where they do not."""
    if within < math.inf and a.status != b.status:
        return f"{a.status} ({a.message}) vs {b.status} ({b.message})"
    if abs(a.sim_time - b.sim_time) > within + 1e-9 * b.sim_time:
        return f"ended at {a.sim_time} s and {b.sim_time} s"
    return None


def _same_ending(a: RunResult, b: RunResult, what: str, within: float = 0.0) -> None:
    """The same status, at the same time (within ``within`` s; inf: either may end first)."""
    differs = _ending_difference(a, b, within)
    assert differs is None, f"{what}: {differs}"


def _common(a: RunResult, b: RunResult) -> int:
    """The samples two runs both have (of runs that diverged, those before their last 10),
    up to the first where either moves at more than ``NEAR_DIVERGENCE``: a link spinning up
    towards the divergence limit doubles their 1e-16 difference every sample or two (seed
    15600 at L = 0.37: 1e-10 to 1e-4 of 2240 rad/s in 25 samples, both runs ending ok)."""
    both = min(len(a.trajectory), len(b.trajectory))
    if "diverged" in (a.status, b.status):
        both = max(1, both - 10)
    for run in (a, b):
        fast = np.flatnonzero(
            np.abs(run.trajectory.v[:both]).max(axis=1, initial=0.0) > NEAR_DIVERGENCE
        )
        both = max(1, int(fast[0])) if fast.size else both
    return both


def _first(result: RunResult, samples: int) -> RunResult:
    """The run's first ``samples`` samples."""
    traj = result.trajectory
    cut = {name: getattr(traj, name)[:samples] for name in ARRAYS}
    return dataclasses.replace(result, trajectory=dataclasses.replace(traj, **cut))


def _given(scale: float, drop: float | None, falls: bool, record_rate: float) -> dict[str, Any]:
    """Run options for the rig scaled by ``scale`` (1: the rig), the step and control interval
    left to the file (or to --scale, which scales the rig's)."""
    tick = math.sqrt(scale)
    return {
        "duration": DURATION * tick,
        "drop": None if drop is None else drop * scale,
        "record_rate": record_rate / tick,
        **({} if falls else {"fall_height": 0.0, "fall_tilt": math.pi}),
    }


def _scaled_file(source: Path, scale: float) -> Path:
    """``legdsl scale SOURCE --by L -o OUT.leg``, which checks OUT."""
    out = source.with_name(f"{scale_name(source.stem, scale)}.leg")
    said = io.StringIO()
    with contextlib.redirect_stderr(said):
        status = main(["scale", str(source), "--by", repr(scale), "-o", str(out)])
    assert status == 0, f"legdsl scale --by {scale:g} failed: {said.getvalue()}"
    return out


@dataclasses.dataclass
class _Drawn:
    drop: float | None
    falls: bool
    record_rate: float


def drawn_rig(seed: int, folder: Path) -> tuple[Path, _Drawn]:
    """The rig ``seed`` placed in ``folder``, and the run options drawn for it."""
    source, drop = placed_rig(seed, folder)
    rng = np.random.default_rng([seed, 10])
    falls = bool(rng.random() < 0.5)  # the default fall rules, or none: the whole run
    return source, _Drawn(drop, falls, float(rng.choice([0.0, 200.0])))


def check_rig(seed: int, folder: Path, scales: tuple[float, ...] = SCALES) -> None:
    source, drawn = drawn_rig(seed, folder)
    drop, falls, record_rate = drawn.drop, drawn.falls, drawn.record_rate
    generated = folder / "generated"
    for _ in range(3):
        session = RunSession.from_file(source, generated=generated)
        opts = run_options(session.model, **_given(1.0, drop, falls, record_rate))
        try:
            plain = session.run(options=opts, backend=BACKEND).result
            break
        except LegError as e:  # an actuator too stiff or damped for the step: set as advised
            follow_advice(source, str(e))
    else:
        pytest.fail("still refused after following the advice three times")
    check_scalings(session, plain, None, drawn, scales)


def _run_at(
    session: RunSession,
    controller: str | None,
    scale: float,
    given: dict[str, Any],
    nudged: bool = False,
) -> RunResult:
    """``session``'s run with ``--scale scale`` and the options ``given``; ``nudged``, from a
    start one ulp away in each coordinate."""
    opts = run_options(session.model, scale, **given)
    plan = session.prepare(controller, options=opts, scale=scale, backend=BACKEND)
    if nudged:
        plan.sim.q = [math.nextafter(x, math.inf) for x in plan.sim.q]
    return plan.finish(plan.sim.run(None)).result


def check_scalings(
    session: RunSession,
    plain: RunResult,
    controller: str | None,
    drawn: _Drawn,
    scales: tuple[float, ...] = SCALES,
) -> None:
    """For each of ``scales``: the scaled file's run agrees with the --scale run, and brought back
    by Table 1 with ``plain``, the run of ``session``'s own file with ``drawn``."""
    generated = session.generated
    drop, falls, record_rate = drawn.drop, drawn.falls, drawn.record_rate
    for scale in scales:
        # sqrt(4) = 2: every factor a power of two, the two runs' arithmetic the same; else
        # they start 1e-16 apart and contacts and stops amplify it
        tolerance = 1e-9 if math.log(scale, 4).is_integer() else 1e-6
        given = _given(scale, drop, falls, record_rate)
        big = RunSession.from_file(_scaled_file(session.source, scale), generated=generated)
        opts = run_options(big.model, **given)
        file_run = big.run(controller, options=opts, backend=BACKEND).result
        scaled_run = _run_at(session, controller, scale, given)
        what = f"L = {scale:g}"
        # the --scale run is held to the scaled file's fall and divergence rules: one ending
        twin = functools.partial(_run_at, session, controller, scale, given, nudged=True)
        assert_alike(file_run, scaled_run, twin, tolerance, f"{what}: the scaled file and --scale")
        if not (file_run.trajectory.t.size or scaled_run.trajectory.t.size):
            # both stopped at their first tick, alike (a law reading a stance time not yet
            # measured: law 9800), before a sample: nothing more to compare, but the rig's run
            _same_ending(file_run, plain, f"{what}, the scaled file and the rig")
            continue
        # dynamic similarity: the scaled file's run, brought back by 1/L, is the rig's own
        # (a fall or divergence is looked for every CHECK_INTERVAL of each creature's own time,
        # so the two ends may be that far apart; the samples both have must agree)
        # The divergence limit (1000 m/s or rad/s from 10 cm up) does not follow the size: where
        # a run diverges, the samples both have (but the last 10) are compared, not the ends.
        back = scale_result(file_run, big.model, 1 / scale)
        blows = "diverged" in (plain.status, file_run.status)
        within = math.inf if blows else CHECK_INTERVAL * max(1.0, 1 / math.sqrt(scale))
        unscaled = _given(1.0, drop, falls, record_rate)
        twin = functools.partial(_run_at, session, controller, 1.0, unscaled, nudged=True)
        brought = f"{what}: the scaled file brought back and the rig"
        assert_alike(back, plain, twin, tolerance, brought, within)


SEEDS = range(FIRST_SEED, FIRST_SEED + COUNT)
NO_VALUE = "gives no finite real number"  # a law the lowering refuses, soundly: another drawn


@pytest.mark.parametrize("seed", SEEDS)
def test_a_random_rig_scaled_is_dynamically_similar(seed: int, tmp_path: Path) -> None:
    rerun = f"LEGDSL_RANDOM_SCALING_SEED={seed} LEGDSL_RANDOM_SCALING=1"
    with told_with_seed(f"random rig of seed {seed}", rerun, lambda: rig_shown(seed, tmp_path)):
        check_rig(seed, tmp_path)


def test_a_fall_of_the_scaled_file_and_of_its_scaled_run_comes_at_one_time(tmp_path: Path) -> None:
    """Rig 9 falls. Its run with --scale 4 looked for a fall every 2 ms of the unscaled model's
    time (4 ms of the scaled creature's), the scaled file's run every 2 ms of its own: the two
    runs ended 1.6 ms apart. --scale L now looks every 2 ms / sqrt(L) of the model's time."""
    check_rig(9, tmp_path, scales=(4.0,))


CI_LAWS = 1
LAWS = int(os.environ.get("LEGDSL_RANDOM_SCALING_LAWS", CI_LAWS))
FIRST_LAW = int(os.environ.get("LEGDSL_RANDOM_SCALING_LAW_SEED", "0"))


def check_law(seed: int, folder: Path) -> None:
    """The random law ``seed`` of tests/random_laws.py (a redrawn one for a law the lowering
    refuses as having no value), on its creature, scaled by each of SCALES."""
    for attempt in range(5):
        source = folder / f"law{seed}.leg"
        source.write_text(law_text(seed, attempt))
        try:
            session = RunSession.from_file(source, generated=folder / f"generated{attempt}")
            session.control("rand")
        except LegError as error:
            if NO_VALUE not in str(error):
                raise
            continue
        drawn = _Drawn(None, True, 200.0)
        opts = run_options(session.model, **_given(1.0, None, True, 200.0))
        plain = session.run("rand", options=opts, backend=BACKEND).result
        check_scalings(session, plain, "rand", drawn)
        return
    pytest.skip(f"random law seed {seed}: 5 laws drawn, each refused: {NO_VALUE}")


@pytest.mark.parametrize("seed", range(FIRST_LAW, FIRST_LAW + LAWS))
def test_a_random_control_law_scaled_is_dynamically_similar(seed: int, tmp_path: Path) -> None:
    written = tmp_path / f"law{seed}.leg"
    rerun = f"LEGDSL_RANDOM_SCALING_LAW_SEED={seed} LEGDSL_RANDOM_SCALING_LAWS=1"
    shown = lambda: written.read_text() if written.exists() else ""  # noqa: E731
    with told_with_seed(f"random law of seed {seed}", rerun, shown):
        check_law(seed, tmp_path)


def test_a_divergence_of_the_scaled_file_and_of_its_scaled_run_comes_at_one_time(
    tmp_path: Path,
) -> None:
    """Rig 10 diverges. At L = 4 its scaled file's run was stopped at 0.3056 s and its --scale 4
    run at 0.256 s: the --scale run held the unscaled model's speeds to 1000 m/s and rad/s, not
    the scaled creature's (its speeds are twice the model's, its turning rates half). Both
    backends hold it to the same limits, bit for bit."""
    check_rig(10, tmp_path, scales=(4.0,))
    source, d = drawn_rig(10, tmp_path)
    session = RunSession.from_file(source, generated=tmp_path / "generated")
    opts = run_options(session.model, 4.0, **_given(4.0, d.drop, d.falls, d.record_rate))
    runs = [session.run(options=opts, scale=4.0, backend=b).result for b in ("python", "c")]
    assert runs[0].status == runs[1].status == "diverged"
    assert (runs[0].sim_time, runs[0].message) == (runs[1].sim_time, runs[1].message)
    assert "rad/s" in runs[0].message or "m/s" in runs[0].message
    for name in ARRAYS:
        a, b = (getattr(r.trajectory, name) for r in runs)
        assert a.shape == b.shape and np.array_equal(a, b, equal_nan=True), name
