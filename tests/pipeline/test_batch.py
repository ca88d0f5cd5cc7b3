"""The batch (legdsl.pipeline.batch): N copies of a run, each with its own values and start, run
in C in one call per thread; every copy must equal the single run with its values, bit for bit."""

from __future__ import annotations

import contextlib
import os
import signal
import threading
import time
import types
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from conftest import CREATURES, GENERATED
from runtime_helpers import assert_same

import legdsl.pipeline.batch as batch_module
import legdsl.pipeline.batch_memory as batch_memory
from legdsl.lang.errors import UsageError
from legdsl.pipeline.batch import Batch
from legdsl.pipeline.session import RunSession
from legdsl.sim.c_backend import available
from legdsl.sim.machine import StateMachine
from legdsl.sim.run_loop import RunOptions
from legdsl.sim.simulate import Simulation

pytestmark = pytest.mark.skipif(
    available() is not None,
    reason=f"the batch runs on the C backend, which needs a C compiler: {available()}",
)

HOP = RunOptions(duration=0.4)


@pytest.fixture(scope="module")
def roo() -> RunSession:
    return RunSession.from_file(CREATURES / "kangaroo.leg", generated=GENERATED)


def alone(session: RunSession, texts: list[str], options: RunOptions) -> object:
    """The single run on the Python backend, the reference."""
    return session.run("hop", texts, options=options, backend="python").result


def test_each_copy_is_the_single_run_with_its_values(roo: RunSession) -> None:
    speeds = np.array([2.0, 3.5, 5.0])
    batch = Batch(roo, 3, "hop", settings=["height=0.48m"], options=HOP, vary={
        "speed": (speeds * 100, "cm/s"),            # an input, in a unit not SI
        "k_speed": ([0.03, 0.025, 0.035], "s"),     # a parameter
        "hip_servo.kp": ([300, 400, 500], "N*m/rad"),  # an actuator setting
    })  # fmt: skip
    copies = batch.run(threads=2)
    assert list(copies.status) == ["ok"] * 3 and copies.rerun == 0
    for k in range(3):
        texts = batch.texts(k)
        assert texts[0] == "height=0.48m" and f"speed={float(speeds[k] * 100)!r}cm/s" in texts
        assert_same(alone(roo, texts, HOP), copies.result(k))
    commanded = [float(copies.trajectory(k).speed_command[-1]) for k in range(3)]
    assert commanded == pytest.approx(list(speeds))
    run = copies.run(1)  # the session's Run: its settings and machine are the copy's own
    assert run.info()["inputs"]["speed"] == pytest.approx(3.5)
    assert run.settings.params["k_speed"] == 0.025


def test_copies_start_where_told_and_threads_change_nothing(roo: RunSession) -> None:
    drops = [0.0, 0.05, 0.1, 0.15]
    starts = np.array([roo.prepare("hop", [], options=RunOptions(drop=d)).sim.q for d in drops])
    one = Batch(roo, 4, "hop", q0=starts, options=HOP).run(threads=1)
    two = Batch(roo, 4, "hop", q0=starts, options=HOP).run(threads=2)
    for k, drop in enumerate(drops):
        opts = RunOptions(duration=HOP.duration, drop=drop)
        assert_same(roo.run("hop", [], options=opts, backend="python").result, one.result(k))
        assert_same(one.result(k), two.result(k))


def test_copies_of_a_3d_creature_on_a_path_are_the_single_runs() -> None:
    """The quadruped trotting on a circle: a 3D root, the ground's torsion, a path tracker's
    state and the placer's solves, per copy; the path report of each copy's run too."""
    quad = RunSession.from_file(CREATURES / "quadruped.leg", generated=GENERATED)
    circle = "circle(center = (0, 3) m, radius = 3 m, turn = left)"
    opts = RunOptions(duration=1.0)
    copies = Batch(quad, 2, "trot", paths=[circle], options=opts,
                   vary={"speed": ([0.8, 1.2], "m/s")}).run(threads=2)  # fmt: skip
    for k, speed in enumerate((0.8, 1.2)):
        single = quad.run("trot", [f"speed={speed}m/s"], [circle], options=opts, backend="python")
        assert_same(single.result, copies.result(k))
        assert copies.run(k).path_reports == single.path_reports


def test_copies_without_a_controller_and_with_rk4_and_a_schedule(roo: RunSession) -> None:
    quad = RunSession.from_file(CREATURES / "quadruped.leg", generated=GENERATED)
    drops = (0.0, 0.1)
    starts = np.array([quad.prepare(None, options=RunOptions(drop=d)).sim.q for d in drops])
    passive = Batch(quad, 2, None, q0=starts, options=RunOptions(duration=0.5)).run()
    for k, drop in enumerate(drops):
        opts = RunOptions(duration=0.5, drop=drop)
        assert_same(quad.run(None, options=opts, backend="python").result, passive.result(k))
    opts = RunOptions(duration=0.6, integrator="rk4")
    scheduled = Batch(roo, 2, "hop", settings=["speed=4m/s@0.3s"], options=opts,
                      vary={"speed": ([2, 3], "m/s")}).run()  # fmt: skip
    for k in range(2):
        assert_same(alone(roo, scheduled.batch.texts(k), opts), scheduled.result(k))


def test_a_fall_and_a_divergence_end_as_alone() -> None:
    hopper = RunSession.from_file(CREATURES / "hopper.leg", generated=GENERATED)
    opts = RunOptions(duration=1.0)
    at_once = ["max_step=100m/s"]  # each speed placed for at once: 6 m/s falls
    copies = Batch(hopper, 2, "hop", settings=at_once, options=opts,
                   vary={"speed": ([1, 6], "m/s")}).run()  # fmt: skip
    assert list(copies.status) == ["ok", "fell"]
    fell = hopper.run("hop", [*at_once, "speed=6m/s"], options=opts, backend="python").result
    assert_same(fell, copies.result(1))
    coarse = RunOptions(duration=1.0, dt=0.01, control_dt=0.01)  # too coarse for the contact
    copies = Batch(hopper, 1, "hop", options=coarse).run()
    assert list(copies.status) == ["diverged"]
    assert_same(hopper.run("hop", [], options=coarse, backend="python").result, copies.result(0))


def test_a_copy_that_needs_python_is_run_again_alone(
    roo: RunSession, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(batch_module, "EVENTS_PER_SECOND", 0)  # buffers of 16 events a contact
    opts = RunOptions(duration=2.0)
    copies = Batch(roo, 2, "hop", options=opts, vary={"speed": ([2, 3], "m/s")}).run()
    assert copies.rerun == 2  # more than 16 touchdowns and liftoffs each: Python drained them
    for k in range(2):
        single = alone(roo, copies.batch.texts(k), opts)
        assert_same(single, copies.result(k))
        # the arrays over the copies say the run again's end (they said where C stopped: 0 s)
        assert copies.sim_time[k] == single.sim_time == 2.0
        assert copies.steps[k] == single.steps and copies.recorded[k] == len(single.trajectory)


def test_a_ctrl_c_in_a_copys_run_again_stops_the_copies_after_it(
    roo: RunSession, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The copies C gave back are run again one after another; a Ctrl-C in one (here: asked
    for at its start) ended that one, and the next ran to its end all the same."""
    monkeypatch.setattr(batch_module, "EVENTS_PER_SECOND", 0)
    again: list[int] = []

    def interrupted_again(copies: batch_module.Copies, k: int) -> object:
        again.append(k)
        b = copies.batch
        plan = b.session.prepare(b.controller, b.texts(k), options=b.options, backend="c")
        return plan.finish(plan.sim.run(stop=lambda: "SIGINT (Ctrl-C)"))

    monkeypatch.setattr(batch_module.Copies, "_run_in_python", interrupted_again)
    copies = Batch(roo, 3, "hop", options=RunOptions(duration=2.0)).run()
    assert again == [0] and copies.interrupted == "SIGINT (Ctrl-C)"
    assert list(copies.status) == ["interrupted"] * 3
    assert copies.result(0).sim_time == copies.sim_time[0] == 0.0
    assert "interrupted by SIGINT (Ctrl-C)" in copies.result(2).message


def test_ctrl_c_stops_the_runs_of_a_batch_in_threads(
    roo: RunSession, monkeypatch: pytest.MonkeyPatch
) -> None:
    """run_batch's runs in two threads: the Ctrl-C comes to this thread, waiting for them (here
    sent as the first run starts); both runs stop at their next report and say so, as a
    single run does, and the third never starts. They ran on to their ends before."""
    from legdsl.pipeline.backend import iter_batch

    run, sent, once = Simulation.run, [], threading.Lock()
    idle = threading.Event()  # a thread of the caller's own, taking signals (xdist's, a kernel's)
    taker = threading.Thread(target=idle.wait)
    taker.start()

    def ctrl_c_at_a_start(sim: Simulation, progress: Any = None, stop: Any = None) -> object:
        def asked() -> str:
            with once:  # both threads start at once: one Ctrl-C
                if not sent:
                    # Taken by the idle thread once this one waits for the runs: Python runs its
                    # handler here only when this thread runs Python again. It waited on the
                    # runs without a timeout, so the Ctrl-C came as the first run ended (its 20
                    # s of steps), the third run already started (CI, 2026-12-02).
                    time.sleep(0.3)
                    sent.append(signal.pthread_kill(taker.ident or 0, signal.SIGINT))
            return stop()

        return run(sim, progress, asked)

    monkeypatch.setattr(Simulation, "run", ctrl_c_at_a_start)
    long = RunOptions(duration=5000.0)  # some 20 s of the C backend each
    jobs = [{"controller": "hop", "options": long} for _ in range(3)]
    try:
        done = dict(iter_batch(roo, jobs, threads=2))
    finally:
        idle.set()
        taker.join()
    assert sorted(done) == [0, 1]
    for k in (0, 1):
        result = done[k].result
        assert result.status == "interrupted" and result.cause == "SIGINT (Ctrl-C)"
        assert result.sim_time < 1000.0


def test_an_interrupted_batch_stops_its_copies_and_keeps_what_they_recorded(
    roo: RunSession, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Ctrl-C while the copies run (here: raised by the progress report): C stops the copy it
    runs at its next step budget (here 1000 steps, 20000 in use), starts no more, and each
    copy says how it ended, as a single run does."""

    def ctrl_c(done: int, n: int, left: float) -> None:
        raise KeyboardInterrupt

    monkeypatch.setattr(batch_module, "STEP_BUDGET", 1000)
    opts = RunOptions(duration=200.0)  # the 8 copies take seconds: the first report stops them
    batch = Batch(roo, 8, "hop", options=opts, vary={"speed": (np.linspace(2, 4, 8), "m/s")})
    copies = batch.run(threads=1, progress=ctrl_c)
    assert copies.interrupted == "SIGINT (Ctrl-C)" and copies.rerun == 0
    assert "interrupted" in set(copies.status) and copies.wall_time < 2.0
    for k in [k for k in range(8) if 0 < copies.sim_time[k] < 200.0]:  # stopped on the way
        result = copies.result(k)
        assert result.status == "interrupted" and result.cause == "SIGINT (Ctrl-C)"
        assert f"at t = {copies.sim_time[k]:.4f} s of 200 s" in result.message
        whole = roo.run("hop", batch.texts(k), options=opts, backend="c").result.trajectory
        kept = result.trajectory
        assert 0 < len(kept) < len(whole)
        assert kept.q.tobytes() == whole.q[: len(kept)].tobytes()
    for k in np.flatnonzero(copies.sim_time == 0.0):
        assert copies.status[k] == "interrupted" and len(copies.trajectory(int(k))) == 0


class _Started(threading.Thread):
    """A batch's thread that is kept, and whose first start is followed by a Ctrl-C."""

    made: list[threading.Thread] = []
    ctrl_c = True

    def start(self) -> None:
        super().start()
        first = not _Started.made
        _Started.made.append(self)
        if first and _Started.ctrl_c:
            os.kill(os.getpid(), signal.SIGINT)


def test_ctrl_c_among_the_thread_starts_stops_the_copies_before_their_memory_goes(
    roo: RunSession, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A Ctrl-C landing as the batch started its threads escaped before the threads were
    known: the copies ran on in C while Python freed the arrays they wrote (a segfault,
    random API interrupts seed 20013). It now stops them as any Ctrl-C does."""
    monkeypatch.setattr(_Started, "made", [])
    monkeypatch.setattr(batch_module, "threading", types.SimpleNamespace(Thread=_Started))
    monkeypatch.setattr(batch_module, "STEP_BUDGET", 1000)
    batch = Batch(roo, 4, "hop", options=RunOptions(duration=200.0))
    copies = batch.run(threads=2)
    assert copies.interrupted == "SIGINT (Ctrl-C)" and "interrupted" in set(copies.status)
    assert len(_Started.made) == 2 and not any(t.is_alive() for t in _Started.made)


def test_a_ctrl_c_as_the_copies_are_joined_keeps_them(
    roo: RunSession, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A Ctrl-C as the threads were joined at the end was held, then raised out of the run:
    run_copies raised KeyboardInterrupt, the copies lost (an outside user's 512 copies, 7 of
    15 tries). The copies come back; those done are as they ended."""
    held = batch_module.signals_held
    entered: list[int] = []

    @contextlib.contextmanager
    def ctrl_c_at_the_joins() -> Iterator[None]:
        with held():
            entered.append(1)
            if len(entered) == 2:  # the joins (the first holds the starts)
                os.kill(os.getpid(), signal.SIGINT)
            yield

    monkeypatch.setattr(batch_module, "signals_held", ctrl_c_at_the_joins)
    copies = Batch(roo, 4, "hop", options=RunOptions(duration=0.3)).run(threads=2)
    assert len(entered) == 2 and copies.interrupted == "SIGINT (Ctrl-C)"
    assert set(copies.status) == {"ok"}  # every copy had ended: none is cut short


def test_an_error_in_the_progress_report_stops_and_joins_the_copies(
    roo: RunSession, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Any exception out of the run, not only Ctrl-C, stops the C threads and joins them
    before it goes on (they would write into freed arrays)."""

    def broken(done: int, n: int, left: float) -> None:
        raise ValueError("a progress bar's own bug")

    monkeypatch.setattr(_Started, "made", [])
    monkeypatch.setattr(_Started, "ctrl_c", False)
    monkeypatch.setattr(batch_module, "threading", types.SimpleNamespace(Thread=_Started))
    monkeypatch.setattr(batch_module, "STEP_BUDGET", 1000)
    batch = Batch(roo, 4, "hop", options=RunOptions(duration=200.0))
    with pytest.raises(ValueError, match="a progress bar's own bug"):
        batch.run(threads=2, progress=broken)
    assert len(_Started.made) == 2 and not any(t.is_alive() for t in _Started.made)


@pytest.mark.parametrize(
    ("vary", "q0", "says"),
    [
        ({"speed": ([2, 3], "s")}, None, "speed is a velocity (m/s), but 2.0s is a time"),
        ({"speed": ([2, 3, 4], "m/s")}, None, "give 2 values (one per copy)"),
        ({"hip_servo.kp": ([-1, 400], "N*m/rad")}, None, "hip_servo.kp"),
        ({"spead": ([2, 3], "m/s")}, None, "no input or parameter 'spead'"),
        ({"hop.k_speed": ([0.03, 0.02], "s")}, None, "name an input or parameter of hop alone"),
        ({}, "under", "q0 of copy 1: "),
        ({"speed@0.1s": ([2, 3], "m/s")}, None, "vary 'speed@0.1s': name an input"),
        ({"speed=2m/s": ([2, 3], "m/s")}, None, "vary 'speed=2m/s': name an input"),
    ],
)
def test_a_wrong_value_is_refused_before_anything_runs(
    roo: RunSession, vary: dict, q0: str | None, says: str
) -> None:
    starts = None
    if q0 == "under":
        starts = np.array([roo.model.q0, roo.model.q0], dtype=float)
        starts[1, roo.model.q_names.index("z") if "z" in roo.model.q_names else 1] -= 0.2
    with pytest.raises(UsageError) as e:
        Batch(roo, 2, "hop", vary=vary, q0=starts, options=HOP)
    assert says in str(e.value)


def test_a_copy_s_own_start_is_told_as_its_row_of_q0_or_v0(roo: RunSession) -> None:
    """A q0 row under the ground said "raise the root's initial z ... in the .leg file, or start
    with --drop H", and a v0 of 1e6 m/s ended its copy diverged blaming "the start velocity its
    file gives": both came from the call's arrays, and are told as the copy's row."""
    starts = np.array([roo.model.q0, roo.model.q0], dtype=float)
    starts[1, 1] = -1.0  # the kangaroo's z
    with pytest.raises(UsageError) as e:
        Batch(roo, 2, "hop", q0=starts, options=HOP)
    said = str(e.value)
    assert said.startswith("q0 of copy 1: contact ") and ".leg" not in said
    assert "; raise its root's z, q0[1, 1] (now -1 m), by at least " in said
    assert "--drop" not in said and "initial" not in said
    speeds = np.zeros((2, roo.model.nv))
    speeds[1, 0] = 1e6
    with pytest.raises(UsageError) as e:
        Batch(roo, 2, "hop", v0=speeds, options=HOP)
    assert str(e.value).startswith("v0 of copy 1: x = 1e+06 m/s is past the divergence limit")
    assert "give v0[1, 0] a speed under " in str(e.value)
    speeds[1, 0] = 3.0  # a start a copy can run from
    assert Batch(roo, 2, "hop", v0=speeds, options=HOP).v0[1, 0] == 3.0


@pytest.mark.parametrize(
    ("jobs", "threads", "says"),
    [
        ([{"controller": "hop"}], -1, "threads is a whole number, 1 or more"),
        ([{"controller": "hop"}], 1.5, "threads is a whole number"),
        ({"controller": "hop"}, None, "jobs is a list of RunSession.run's keyword arguments"),
        (["hop"], None, "job 0 is a dict"),
        ([{"controller": "hop"}, {"controler": "hop"}], None, "did you mean 'controller'?"),
    ],
)
def test_run_batch_misuse_is_a_usage_error(
    roo: RunSession, jobs: object, threads: object, says: str
) -> None:
    """These were a thread pool's ValueError, a TypeError from inside a thread, an
    AttributeError ('str' object has no attribute 'get'), or a pool of 1.5 threads."""
    from legdsl.pipeline.backend import run_batch

    with pytest.raises(UsageError) as e:
        run_batch(roo, jobs, threads)  # type: ignore[arg-type]
    assert says in str(e.value)


def test_a_batch_too_large_for_memory_is_refused_before_anything_is_laid_out(
    roo: RunSession, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Only the recordings were counted: copies of a short run, recorded rarely, whose states
    outgrow the memory were laid out anyway (a MemoryError, or the system killing the run)."""
    options = RunOptions(duration=0.01, record_rate=100.0)
    per_sample = batch_memory.sample_bytes(roo.model) * batch_memory.run_samples(options)
    monkeypatch.setattr(batch_memory, "recording_budget", lambda: 200 * per_sample)
    batch = Batch(roo, 100, "hop", options=options)  # their recordings fit
    laid: list[int] = []
    monkeypatch.setattr(batch_module, "lined_up", lambda n, *a: laid.append(n))
    with pytest.raises(UsageError, match=r"a batch of 100 copies: their states and recordings"):
        batch.run(threads=1)
    assert laid == []


def test_a_batch_too_large_names_the_limit_it_passes(
    roo: RunSession, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Under ulimit -v 4000000 on a 23 GB machine, 10**5 copies were refused as "more than half
    of this machine's memory (1.8 GiB)": half of what the address-space limit left. Each
    limit is named as what it is."""
    import resource

    gib = 2**30
    monkeypatch.setattr(batch_memory, "recording_budget", lambda: int(1.5 * gib))
    monkeypatch.setattr(batch_memory, "address_space_left", lambda: 3 * gib)
    monkeypatch.setattr(resource, "getrlimit", lambda what: (4 * gib, resource.RLIM_INFINITY))
    with pytest.raises(UsageError) as e:
        Batch(roo, 10**5, "hop", options=RunOptions(duration=0.5))
    said = str(e.value)
    assert "more than 1.5 GiB, half of what this process's address-space limit (ulimit -v: " in said
    assert "4.0 GiB, 1.0 GiB of it taken) leaves it; record less often" in said
    assert "machine" not in said
    monkeypatch.setattr(batch_memory, "address_space_left", lambda: None)  # no limit
    with pytest.raises(UsageError, match=r"more than 1\.5 GiB, half of this machine's memory;"):
        Batch(roo, 10**5, "hop", options=RunOptions(duration=0.5))


@pytest.mark.parametrize(("quaternion", "norm"), [((0, 0, 0, 0), "0"), ((2, 0, 0, 0), "2")])
def test_a_3d_copys_orientation_is_a_unit_quaternion(quaternion: tuple, norm: str) -> None:
    """A zero quaternion was a ZeroDivisionError; (2, 0, 0, 0) ran, its first sample
    recorded as given (q.qw = 2) and the next normalised."""
    quad = RunSession.from_file(CREATURES / "quadruped.leg", generated=GENERATED)
    starts = np.array([quad.model.q0, quad.model.q0], dtype=float)
    starts[1, 3:7] = quaternion
    with pytest.raises(UsageError) as e:
        Batch(quad, 2, "trot", q0=starts, options=RunOptions(duration=0.05))
    assert (
        f"q0 of copy 1: the root's orientation (qw, qx, qy, qz) is a unit quaternion, and its norm is {norm};"
        in str(e.value)
    )


def test_a_batch_run_again_gives_the_same_copies(roo: RunSession) -> None:
    """A copy's result is made by moving the template to the copy's end (t too): a batch run
    again then started every copy at the first run's end time (its first state entered at 0.4 s)."""
    batch = Batch(roo, 2, "hop", options=HOP, vary={"speed": ([2, 3], "m/s")})
    first = batch.run(threads=1)
    ends = [first.result(k) for k in range(2)]
    again = batch.run(threads=2)
    for k in range(2):
        first_state = next(e for e in again.result(k).events if e["kind"] == "state")
        assert first_state["t"] == 0.0
        assert_same(ends[k], again.result(k))


def test_a_copys_divergence_names_the_stiffness_its_controller_set(tmp_path) -> None:  # noqa: ANN001
    """A copy's message was written with the template's actuators (as at the start), so a
    divergence the controller caused by stiffening a spring left out the single run's 'Likely
    cause: actuator 'leg_spring' has k = ... now, too stiff for the step' (random batch law 17)."""
    from random_laws import creature_text

    law = "leg_spring.k = 3000 N/m * (1 + growth * time / 1 ms) ^ 3"
    source = tmp_path / "stiffen.leg"
    source.write_text(creature_text("hopper") + "\ncontroller stiffen for hopper {\n  input growth"
                      f" = 1\n  table {{\n    state S0 on time < 1 s: {law}\n  }}\n}}\n")  # fmt: skip
    hopper = RunSession.from_file(source, generated=tmp_path / "generated")
    opts = RunOptions(duration=0.5)
    copies = Batch(hopper, 2, "stiffen", vary={"growth": ([0, 1], "")}, options=opts).run()
    assert list(copies.status) == ["ok", "diverged"]
    for k in range(2):
        single = hopper.run("stiffen", copies.batch.texts(k), options=opts, backend="c").result
        assert_same(single, copies.result(k))
    assert "actuator 'leg_spring' has k = " in copies.result(1).message
    assert copies.batch.sim.actuators.by_name["leg_spring"].gain == 3000.0  # the template's


def test_a_copys_run_keeps_the_state_machine_its_single_run_ends_with(roo: RunSession) -> None:
    """``copies.run(k).machine`` was made fresh with the copy's events: its state, records,
    inputs, integrals, schedule and clocks were the start's, where a single run's machine
    keeps those of its end (what the API's runs hand on, e.g. the records a tune reads)."""
    opts, settings = RunOptions(duration=0.7), ["speed=3m/s@0.3s"]  # a change mid-run
    copies = Batch(roo, 2, "hop", settings=settings, options=opts,
                   vary={"height": ([0.4, 0.5], "m")}).run(threads=1)  # fmt: skip
    for k, height in enumerate((0.4, 0.5)):
        ended = roo.run("hop", [f"height={height}m", *settings], options=opts, backend="c").machine
        copy = copies.run(k).machine
        assert isinstance(ended, StateMachine) and isinstance(copy, StateMachine)
        for name in ("started", "state_index", "binding", "entered_at", "records", "inputs",
                     "events", "_history", "schedule", "integrals"):  # fmt: skip
            assert getattr(copy, name) == getattr(ended, name), name
        assert _clocks(copy) == _clocks(ended)


def _clocks(m: StateMachine) -> list[dict[str, object]]:
    return [vars(c) for c in (*m.sensors.clocks.values(), *m.sensors.leg_clocks.values())]


def test_a_threaded_run_batch_builds_its_c_libraries_in_the_calling_thread(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Seed 21055 of tests/api/test_random_api_interrupts.py: run_many in 2 threads with an
    empty cache, Ctrl-C held down. The libraries were built by the worker threads, which a
    Ctrl-C never reaches: the second one cut the pool's wait short, and the compilers ran on
    after the call. They are built first in the calling thread, which stops them on Ctrl-C."""
    from legdsl.pipeline.backend import run_batch
    from legdsl.sim import c_library

    monkeypatch.setenv("LEGDSL_CACHE", str(tmp_path / "cache"))
    monkeypatch.setattr(c_library, "_BY_STAT", {})  # this process may hold it from another test
    monkeypatch.setattr(c_library, "_TRUSTED", {})
    building = []
    build = c_library._build

    def noted(*args: Any, **kwargs: Any) -> Any:
        building.append(threading.current_thread())
        return build(*args, **kwargs)

    monkeypatch.setattr(c_library, "_build", noted)
    hopper = RunSession.from_file(CREATURES / "hopper.leg", generated=GENERATED)
    options = RunOptions(duration=0.05)
    jobs = [
        {"controller": "hop", "settings": [f"speed={v}m/s"], "options": options, "backend": "c"}
        for v in (0.5, 1.0, 1.5, 2.0)
    ]
    runs = run_batch(hopper, [*jobs, {"options": options, "backend": "c"}], threads=2)
    assert [r.status for r in runs] == ["ok"] * 5
    assert len(building) == 2  # the hop's library, and the one of no controller
    assert all(thread is threading.main_thread() for thread in building)


def test_a_ctrl_c_while_the_copies_run_leaves_them_as_they_stopped(roo: RunSession) -> None:
    """A Ctrl-C as the batch waited on its threads (Python 3.11's Thread.join, cut short, marks
    the thread ended) let the copies be read while C ran on to its step budget: an outside
    user's copy said 32.0 s and 80000 steps in its Run, 24.85 s in the batch's sim_time, its
    samples stopping at 24.86 s. The copies are read once C has returned."""
    timers: list[threading.Timer] = []

    def ctrl_c_soon(done: int, n: int, left: float) -> None:  # the copies are running
        if not timers:
            timers.append(threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT)))
            timers[0].start()

    copies = Batch(roo, 4, "hop", options=RunOptions(duration=400.0)).run(1, ctrl_c_soon)
    assert copies.interrupted == "SIGINT (Ctrl-C)"
    read = copies.sim_time.copy(), copies.steps.copy(), copies.recorded.copy()
    time.sleep(0.5)  # C, still running, would move them on
    now = [[getattr(s, f) for s in copies.structs] for f in ("t", "steps", "recorded")]
    assert [list(a) for a in read] == now
    cut = [k for k in range(4) if 0 < copies.sim_time[k] < 400.0]
    for k in cut:
        result = copies.result(k)
        assert result.sim_time == copies.sim_time[k] and result.steps == copies.steps[k]
        assert result.trajectory.t[-1] <= result.sim_time < result.trajectory.t[-1] + 0.02
