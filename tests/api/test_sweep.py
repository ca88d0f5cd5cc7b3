"""legdsl sweep: every combination run once, in parallel processes, one row each; resumable."""

from __future__ import annotations

import contextlib
import csv
import json
import math
import re
from collections.abc import Iterator
from pathlib import Path

import pytest

from legdsl.api.sweep import points
from legdsl.api.sweep_axes import Axis, parse_axis
from legdsl.cli import main
from legdsl.lang.errors import UsageError

ROOT = Path(__file__).resolve().parents[2]
HOPPER = ROOT / "creatures" / "hopper.leg"
DIMS = {"speed": (0, 1, -1, 0), "k_speed": (0, 0, 1, 0), "k_trim": (0, 0, 0, 0)}

pytestmark = pytest.mark.usefixtures("hopper_modules")


def sweep(out: Path, generated: Path, *extra: str) -> int:
    """The hopper's sweep, a one-value option in ``extra`` in place of its own (a second
    value is refused)."""
    given = {"--time": "3", "--from": "0.5", "--jobs": "2"}
    for flag, value in zip(extra, extra[1:], strict=False):
        if flag in given:
            given[flag] = value
    rest = [
        x for k, x in enumerate(extra) if x not in given and (k == 0 or extra[k - 1] not in given)
    ]
    return main([
        "sweep", str(HOPPER), "--controller", "hop", "--grid", "speed=0.5m/s:1.5m/s:2",
        "--grid", "k_speed=0.04,0.06", *(p for kv in given.items() for p in kv),
        "--out", str(out), "--generated", str(generated), *rest,
    ])  # fmt: skip


def rows(out: Path) -> list[dict[str, str]]:
    with (out / "sweep.csv").open(newline="") as f:
        return list(csv.DictReader(f))


def test_a_grid_sweep_and_its_resume(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out, generated = tmp_path / "sweep", tmp_path / "generated"
    assert sweep(out, generated, "--keep-runs") == 0
    table = rows(out)
    assert sorted((float(r["speed"]), float(r["k_speed"])) for r in table) == [
        (0.5, 0.04), (0.5, 0.06), (1.5, 0.04), (1.5, 0.06),
    ]  # fmt: skip
    assert all(r["outcome"] == "ok" and float(r["simulated"]) == 3.0 for r in table)
    fast = [float(r["running_speed"]) for r in table if float(r["speed"]) == 1.5]
    slow = [float(r["running_speed"]) for r in table if float(r["speed"]) == 0.5]
    assert min(fast) > max(slow)  # the command took effect
    assert (out / "sweep.png").stat().st_size > 10_000
    assert len(list((out / "runs").iterdir())) == 4
    # An interrupted sweep: the table lost its last two rows (and half of a third).
    lines = (out / "sweep.csv").read_text().splitlines(keepends=True)
    (out / "sweep.csv").write_text("".join(lines[:3]) + lines[3][:10])
    kept = {r["run"]: r for r in rows(out)[:2]}
    capsys.readouterr()
    assert sweep(out, generated) == 0
    assert "4 runs, 2 of them from before" in capsys.readouterr().out  # only two were run
    again = {r["run"]: r for r in rows(out)}
    assert sorted(again) == ["0", "1", "2", "3"]
    assert all(again[k] == row for k, row in kept.items())  # the finished runs were kept
    # a whole sweep asked to keep its runs runs none: said (it kept nothing without a word)
    assert sweep(out, generated, "--keep-runs") == 0
    assert "--keep-runs keeps the runs a sweep runs, and every run" in capsys.readouterr().err


@pytest.mark.parametrize("plan", [b"{}\n", b"not json {", b"\xff\xfe"])
def test_another_sweep_in_the_same_directory_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], plan: bytes
) -> None:
    """Another sweep's plan, or a damaged one: refused as a user error, never resumed into."""
    out, generated = tmp_path / "sweep", tmp_path / "generated"
    out.mkdir()
    (out / "sweep.json").write_bytes(plan)
    assert sweep(out, generated) == 2
    assert "holds another sweep" in capsys.readouterr().err


def test_another_sweep_is_told_what_differs(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """It said "its sweep.json differs, or is damaged", naming nothing (a tune names it)."""
    out, generated = tmp_path / "sweep", tmp_path / "generated"
    out.mkdir()
    plan = {"file": str(HOPPER), "controller": "hop", "time": 3.0, "from": 0.5, "set": [],
            "runs": []}  # fmt: skip
    (out / "sweep.json").write_text(json.dumps(plan))
    assert sweep(out, generated) == 2
    err = capsys.readouterr().err
    assert "holds another sweep (other swept values (--grid," in err, err
    assert "--time" not in err.partition("choose")[0]


def test_axes_take_units_and_check_them() -> None:
    assert parse_axis("grid", "speed=2:6:3", DIMS).values == (2.0, 4.0, 6.0)
    assert parse_axis("grid", "speed=3.6km/s:7.2km/s:2", DIMS).values == pytest.approx(
        (3600.0, 7200.0)
    )
    assert parse_axis("grid", "k_speed=50ms,100ms", DIMS).values == pytest.approx((0.05, 0.1))
    with pytest.raises(UsageError, match="speed is a velocity .*, but '2kg' is a mass"):
        parse_axis("grid", "speed=2kg:6kg:3", DIMS)
    with pytest.raises(UsageError, match="not an input or parameter"):
        parse_axis("random", "sped=1:2", DIMS)
    with pytest.raises(UsageError, match="LO < HI"):
        parse_axis("lhs", "k_trim=0.5:0.1", DIMS)


def test_bare_numbers_for_an_angle_get_a_note_that_they_are_radians(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """--grid stand=-50:-30:3 for a parameter declared in degrees swept -50 to -30 radians
    without a word; a note now says so and how to write degrees. It comes once no mistake of
    the options is refused (a name swept twice here: refused alone), before any run (stopped
    here as the sweep would compile)."""
    import legdsl.api.sweep_cli as sweep_cli

    source = ROOT / "tests" / "good" / "outside" / "knee_runner.leg"
    argv = ["sweep", str(source), "--controller", "run", "--grid", "stand=-50:-30:3",
            "--grid", "speed=1:2:2", "--grid", "speed=1:2:2", "--out", str(tmp_path / "s")]  # fmt: skip
    assert main(argv) == 2
    assert "note" not in capsys.readouterr().err

    def stopped() -> None:
        raise KeyboardInterrupt

    monkeypatch.setattr(sweep_cli, "python_backend_note", stopped)
    assert main(argv[:-4] + argv[-2:]) == 130
    err = capsys.readouterr().err
    assert "note: --grid stand=-50:-30:3: a bare number is in rad: to give them in deg, " in err
    assert "write stand=-50deg:-30deg:3" in err
    assert "--grid speed" not in err  # m/s is the usual unit of a speed: nothing to say


def test_latin_hypercube_draws_fill_every_stratum_once() -> None:
    axes = [Axis("speed", "grid", (1.0, 2.0)), Axis("k_trim", "lhs", (0.0, 1.0))]
    drawn = points(axes, 10, seed=3)
    assert len(drawn) == 20  # each grid value with the same 10 draws
    strata = sorted(int(p["k_trim"] * 10) for p in drawn if p["speed"] == 1.0)
    assert strata == list(range(10))
    assert points(axes, 10, seed=3) == drawn  # the seed makes it reproducible


def test_a_sweep_on_a_dask_local_cluster_gives_the_same_table(tmp_path: Path) -> None:
    pytest.importorskip("distributed")
    generated = tmp_path / "generated"
    assert sweep(tmp_path / "local", generated) == 0
    assert sweep(tmp_path / "dask", generated, "--dask", "local") == 0
    by_run = [{r["run"]: r for r in rows(tmp_path / d)} for d in ("local", "dask")]
    assert by_run[0] == by_run[1]


def test_two_sweeps_never_write_one_directory_at_once(tmp_path: Path) -> None:
    """The second is refused while the first holds OUT/.sweep.lock (they would both append)."""
    from legdsl.api.sweep_cli import writer_lock
    from legdsl.lang.errors import UsageError

    held = writer_lock(tmp_path, "sweep")
    with pytest.raises(UsageError, match="another legdsl sweep is writing"):
        writer_lock(tmp_path, "sweep")
    held.close()
    writer_lock(tmp_path, "sweep").close()  # free again once the first is done


def test_the_jobs_go_to_the_workers_in_batches_of_one_creature(tmp_path: Path) -> None:
    """Each worker is handed a few runs of one creature at a time, which it runs as one
    batch (Creature.run_many); every job comes back as one row."""
    from legdsl.api.sweep import BATCH_RUNS, Job, run_jobs

    class InProcess:  # a pool of 2 "workers" that runs what it is handed here
        workers = 2

        def __init__(self) -> None:
            self.handed: list[list[Job]] = []

        def as_completed(self, fn, items):  # type: ignore[no-untyped-def]
            for item in items:
                self.handed.append(list(item))
                yield fn(item)

    def job(i: int, source: Path) -> Job:
        return Job(index=i, source=str(source), creature=None, controller="hop",
                   values={"speed": 0.5 + 0.1 * i}, units={"speed": "m/s"}, fixed=(),
                   duration=0.3, start=0.0, generated=str(tmp_path / "generated"), keep=None)  # fmt: skip

    other = tmp_path / "hopper2.leg"  # the same creature from another file: its own batches
    other.write_text(HOPPER.read_text())
    jobs = [job(i, HOPPER) for i in range(10)] + [job(i, other) for i in range(10, 13)]
    pool = InProcess()
    rows = list(run_jobs(jobs, pool))  # type: ignore[arg-type]
    assert sorted(r["run"] for r in rows) == list(range(13))
    assert all(r["outcome"] == "ok" for r in rows)
    assert all(len({j.source for j in batch}) == 1 for batch in pool.handed)
    assert all(1 <= len(batch) <= BATCH_RUNS for batch in pool.handed)
    assert len(pool.handed) >= 2 * 2  # a few per worker


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--seed", "-1"], "--seed -1: give a whole number, 0 or more"),
        (["--from", "nan"], "--from nan: 'nan' is not a number"),
        (["--from", "-1"], "--from -1: --from must not be negative"),
        (["--from", "3"], "--from 3 is not a time within the runs .--time 3."),
        (["--grid", "k_trim=1e400,1"], "--grid k_trim: 1e400 is too large to be a number"),
        (["--grid", "k_trim=0:1:100000000"], "100,000,000 runs, more than a sweep takes"),
        (
            ["--grid", "k_trim=0:1:2000", "--lhs", "k_apex=0:1", "--samples", "1000"],
            "the sweep: 8,000,000 runs",  # times the 2 x 2 grid beside it
        ),
        # each an internal error (distributed's ValueError) as the runs were about to start
        (["--dask", "bogus"], "--dask bogus: not the address of a Dask scheduler .missing port"),
        (["--dask", "http://h:8786"], "unknown address scheme 'http'.*give tcp://HOST:PORT"),
        (["--dask", "tcp://h:port"], "--dask tcp://h:port: not the address of a Dask scheduler"),
        (["--dask", "Local"], "--dask Local: did you mean --dask local"),
    ],
)
def test_options_that_would_give_nothing_are_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], extra: list[str], message: str
) -> None:
    """A negative seed was an internal error (numpy refuses it), 1e400 was read as infinity
    and reported as a --set of 'infm/s', and a --from outside the runs gave rows of n/a."""
    assert sweep(tmp_path / "out", tmp_path / "generated", *extra) == 2
    assert re.search(message, capsys.readouterr().err)
    assert not (tmp_path / "out" / "sweep.csv").exists()


@pytest.mark.parametrize(
    ("under", "message"),
    [("", "this is a file, not a directory; give a directory"),
     ("sub", "is a file, so nothing can be made under it; give a directory")],
)  # fmt: skip
def test_an_out_that_cannot_be_a_folder_is_refused_as_run_refuses_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], under: str, message: str
) -> None:
    """They came out as the OS says them: "File exists (out); check the path and its
    permissions", "Not a directory (...)"."""
    (tmp_path / "out").write_text("mine\n")
    out = tmp_path / "out" / under
    assert sweep(out, tmp_path / "generated") == 2
    err = capsys.readouterr().err
    assert f"--out {out}: " in err and message in err
    assert (tmp_path / "out").read_text() == "mine\n"


def test_an_interrupted_run_is_no_row_and_stops_the_sweep(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """At Ctrl-C the workers' runs come back 'interrupted': they are left out of the table
    (the resume runs them again) and the sweep stops there."""
    import legdsl.api.sweep as sweep_module
    from legdsl.api.sweep import Job, run_sweep

    def job(i: int) -> Job:
        return Job(index=i, source=str(HOPPER), creature=None, controller="hop",
                   values={"speed": 1.0}, units={"speed": "m/s"}, fixed=(), duration=1.0,
                   start=0.0, generated="generated", keep=None)  # fmt: skip

    def outcomes(jobs, pool):  # type: ignore[no-untyped-def]
        yield {"run": 0, "speed": 1.0, "outcome": "ok"}
        yield {"run": 1, "speed": 1.0, "outcome": "interrupted at 0.400 s"}
        yield {"run": 2, "speed": 1.0, "outcome": "ok"}  # pragma: no cover (never asked for)

    monkeypatch.setattr(sweep_module, "run_jobs", outcomes)
    table = tmp_path / "sweep.csv"
    with pytest.raises(KeyboardInterrupt):
        run_sweep([job(i) for i in range(3)], table, 1)
    assert [r["run"] for r in rows(tmp_path)] == ["0"]


def test_a_worker_stops_its_batch_at_an_interrupted_run(monkeypatch: pytest.MonkeyPatch) -> None:
    """The runs after one that Ctrl-C cut short are not started (they ran to their end)."""
    import legdsl.api.sweep as sweep_module
    from legdsl.api.sweep import Job, run_batch_of_jobs

    started: list[int] = []

    class FakeRun:
        def __init__(self, status: str):
            self.status, self.info = status, {"sim_time": 0.5}

        def metrics(self, start: float) -> None:
            raise UsageError("no strides")

    class FakeCreature:
        def run_many(self, runs, threads):  # type: ignore[no-untyped-def]
            for i, _ in enumerate(runs):
                started.append(i)
                yield i, FakeRun("interrupted" if i == 1 else "ok")

    monkeypatch.setattr(sweep_module, "_creature", lambda job: FakeCreature())
    jobs = [Job(index=i, source="x.leg", creature=None, controller="hop", values={},
                units={}, fixed=(), duration=1.0, start=0.0, generated="generated",
                keep=None) for i in range(4)]  # fmt: skip
    out = run_batch_of_jobs(jobs)
    assert started == [0, 1]
    assert [r["outcome"] for r in out] == ["ok", "interrupted at 0.500 s"]


def test_workers_left_by_an_exception_drop_the_work_not_started() -> None:
    """Ctrl-C in the sweep's process: the pool no longer runs every queued batch before it
    lets the command end (a whole sweep, its results thrown away)."""
    import time

    from legdsl.api.workers import Workers

    start = time.monotonic()
    with pytest.raises(KeyboardInterrupt), Workers(1) as pool:
        for _ in pool.as_completed(time.sleep, [0.2] * 40):
            raise KeyboardInterrupt
    assert time.monotonic() - start < 4.0  # not the 8 s of all forty


def test_workers_left_by_an_exception_leave_no_pool_thread_for_the_exit_to_wake() -> None:
    """Ctrl-C held down as a sweep started: Python's exit hook woke the pool's thread through a
    pipe the thread was closing at that moment and printed a traceback (OSError: Bad file
    descriptor) under "legdsl: interrupted". The thread has ended when the pool is left."""
    import time
    from concurrent.futures import process

    from legdsl.api.workers import Workers

    with pytest.raises(KeyboardInterrupt), Workers(2) as pool:
        for _ in pool.as_completed(time.sleep, [0.2] * 4):
            raise KeyboardInterrupt
    threads = list(process._threads_wakeups)  # what the exit hook would wake
    assert not any(thread.is_alive() for thread in threads)


@pytest.mark.parametrize("interrupted", [False, True])
def test_the_pools_processes_are_closed_when_it_is_left(interrupted: bool) -> None:
    """Each process's finalizer (it closes the process's own pipes) was left to the garbage
    collector: a Ctrl-C landing in it was "Exception ignored in: <Finalize object, dead>", a
    traceback, and lost. They are run as the pool is left, with the signals held."""
    import time

    from legdsl.api.workers import Workers

    pool = Workers(2)
    with contextlib.suppress(KeyboardInterrupt), pool:
        for _ in pool.as_completed(time.sleep, [0.05] * 4):
            if interrupted:
                raise KeyboardInterrupt
    assert pool._started
    for process in pool._started:
        with pytest.raises(ValueError, match="process object is closed"):
            process.is_alive()


def test_a_sweep_starts_no_more_processes_than_it_has_runs(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """--jobs 100000 forked 100000 processes for a sweep of two runs (a process pool under
    fork starts all of its processes at its first task), until the machine ran out of them."""
    from legdsl.api import sweep as sweep_module

    asked: list[int] = []

    class Counted(sweep_module.Workers):
        def __init__(self, workers: int, dask: str | None = None) -> None:
            asked.append(workers)
            super().__init__(workers, dask)

    monkeypatch.setattr(sweep_module, "Workers", Counted)
    assert sweep(tmp_path / "out", tmp_path / "generated", "--jobs", "64") == 0
    assert asked == [4] and len(rows(tmp_path / "out")) == 4


def test_time_and_from_take_a_unit_as_for_legdsl_run(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    argv = ["sweep", str(HOPPER), "--controller", "hop", "--grid", "speed=1", "--time", "1.5s",
            "--from", "500ms", "--out", str(tmp_path / "s"), "--generated", str(tmp_path / "g")]  # fmt: skip
    assert main(argv) == 0
    plan = json.loads((tmp_path / "s" / "sweep.json").read_text())
    assert (plan["time"], plan["from"]) == (1.5, 0.5)
    bad = ["sweep", str(HOPPER), "--controller", "hop", "--grid", "speed=1", "--time", "2kg",
           "--out", str(tmp_path / "t")]  # fmt: skip
    assert main(bad) == 2
    assert "--time is a time (s), but 2kg is a mass" in capsys.readouterr().err


def test_an_actuator_setting_is_swept_as_set_takes_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--grid leg_spring.k=... was refused ("not an input or parameter") although every run
    takes it as --set leg_spring.k=..."""
    out = tmp_path / "springs"
    code = main(["sweep", str(HOPPER), "--controller", "hop", "--grid",
                 "leg_spring.k=2500N/m,3500N/m", "--time", "1.5", "--from", "0.5", "--jobs", "1",
                 "--out", str(out), "--generated", str(tmp_path / "generated")])  # fmt: skip
    assert code == 0
    table = sorted(rows(out), key=lambda r: r["run"])
    assert [float(r["leg_spring.k"]) for r in table] == [2500.0, 3500.0]
    assert table[0]["stride_duration"] != table[1]["stride_duration"]  # the spring took effect
    code = main(["sweep", str(HOPPER), "--controller", "hop", "--grid", "hip_servo.kp=-1:1:2",
                 "--out", str(tmp_path / "negative")])  # fmt: skip
    assert code == 2
    assert "--grid hip_servo.kp: must not be negative" in capsys.readouterr().err


@pytest.mark.parametrize("setting", ["speed=1m/s", "k_speed = 0.05s", "hop.k_speed=0.05s"])
def test_a_fixed_setting_of_a_swept_name_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], setting: str
) -> None:
    """--set speed=1m/s beside --grid speed=... ran every row at 1 m/s, each row naming its
    swept speed (and --set hop.k_speed=... every row at that k_speed)."""
    assert sweep(tmp_path / "out", tmp_path / "generated", "--set", setting) == 2
    assert "is swept, and this would set it in every run" in capsys.readouterr().err
    assert not (tmp_path / "out" / "sweep.csv").exists()


def test_a_sweep_of_an_edited_file_is_not_resumed_into_the_old_rows(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The plan named the file, not what it says: after the creature was edited the same
    command appended rows of the new creature to the old one's table."""
    source = tmp_path / "hopper.leg"
    source.write_text(HOPPER.read_text())
    command = ["sweep", str(source), "--controller", "hop", "--grid", "speed=1,1.5", "--time",
               "0.5", "--from", "0.1", "--jobs", "1", "--out", str(tmp_path / "out"),
               "--generated", str(tmp_path / "generated")]  # fmt: skip
    assert main(command) == 0
    lines = (tmp_path / "out" / "sweep.csv").read_text().splitlines(keepends=True)
    (tmp_path / "out" / "sweep.csv").write_text("".join(lines[:2]))  # interrupted after a row
    source.write_text(HOPPER.read_text().replace("mass 10 kg", "mass 12 kg"))
    capsys.readouterr()
    assert main(command) == 2
    assert "the .leg file's creature or controller has changed" in capsys.readouterr().err
    assert len(rows(tmp_path / "out")) == 1


def test_one_value_from_lo_to_hi_is_refused_not_cut_to_lo() -> None:
    """--grid speed=1:2:1 ran speed 1 alone, without a word about the 2."""
    with pytest.raises(UsageError, match=r"1 value from LO to HI is LO alone; write speed=1m/s"):
        parse_axis("grid", "speed=1m/s:2m/s:1", DIMS)
    assert parse_axis("grid", "speed=1:1:1", DIMS).values == (1.0,)
    assert parse_axis("grid", "speed=1", DIMS).values == (1.0,)


def test_a_wrong_fixed_setting_is_refused_before_the_plan_is_recorded(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A --set without its unit was refused by the runs, after sweep.json had recorded it: the
    corrected command was then refused as another sweep."""
    assert sweep(tmp_path / "out", tmp_path / "generated", "--set", "k_trim=0.4kg") == 2
    assert "--set k_trim" in capsys.readouterr().err
    assert not (tmp_path / "out" / "sweep.json").exists()
    assert sweep(tmp_path / "out", tmp_path / "generated", "--set", "k_trim=0.4") == 0


@pytest.mark.parametrize(
    ("table", "message"),
    [(b"run,speed\n\xff\xfe,1\n", "is damaged"), (b"run,speed\nx,1\n", "is damaged"),
     (b"run,speed\n7,1\n", "has rows of runs this sweep has not")],
    ids=["not text", "no run number", "another run"],
)  # fmt: skip
def test_a_damaged_table_is_a_usage_error(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], table: bytes, message: str
) -> None:
    """A table that was not a sweep's was an internal error (exit 70), and a row of a run the
    plan has not was counted among its rows."""
    out = tmp_path / "out"
    out.mkdir()
    (out / "sweep.csv").write_bytes(table)
    assert sweep(out, tmp_path / "generated") == 2
    assert f"sweep.csv {message}" in capsys.readouterr().err


def _killed_by_the_system(k: int) -> int:
    """A worker's job that the out-of-memory killer ends (SIGKILL) when it is number 1."""
    import os
    import signal
    import time

    if k == 1:
        os.kill(os.getpid(), signal.SIGKILL)
    time.sleep(0.3)
    return k


def test_a_worker_killed_by_the_system_is_said_so_not_a_bug() -> None:
    """A worker killed by SIGKILL (out of memory) was an internal error, 'a bug in legdsl'
    (BrokenProcessPool), saying nothing of what was kept or what to do."""
    from legdsl.api.workers import Workers

    killed = r"killed \(SIGKILL: out of memory\?\).*fewer --jobs"
    with pytest.raises(UsageError, match=killed), Workers(2) as pool:
        list(pool.as_completed(_killed_by_the_system, [0, 1, 2]))


def test_a_sweep_records_the_step_its_runs_take_from_the_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Runs from Python took 0.4 ms whatever the file's simulation block said, until they took
    its step as legdsl run does: a sweep begun before would have mixed both in one table. The
    plan records the file's step, so such a sweep (its plan without it) is not resumed."""
    pogo = Path(__file__).resolve().parents[1] / "good" / "outside" / "insect_pogo.leg"
    out = tmp_path / "s"
    argv = ["sweep", str(pogo), "--controller", "hop", "--grid", "speed=0.1", "--time", "0.1",
            "--from", "0.05", "--jobs", "1", "--out", str(out), "--generated", str(tmp_path / "g")]  # fmt: skip
    assert main(argv) == 0
    plan = json.loads((out / "sweep.json").read_text())
    assert plan["simulation"]["dt"] == pytest.approx(1e-4)
    del plan["simulation"]  # as a sweep of an older legdsl wrote it
    (out / "sweep.json").write_text(json.dumps(plan))
    capsys.readouterr()
    assert main(argv) == 2
    assert "holds another sweep" in capsys.readouterr().err


def test_a_range_is_read_as_set_reads_a_value() -> None:
    """``--param k_center=0s^-1:6s^-1`` was 'not a number with an optional unit' (the sweep's
    own pattern had no '-' for an exponent) where ``--set k_center=2s^-1`` was taken."""
    from legdsl.api.sweep import parse_axis
    from legdsl.lang.units import parse_unit

    per_second = parse_unit("s^-1")[1]
    dims = {"k_center": per_second}
    assert parse_axis("param", "k_center=0s^-1:6s^-1", dims).values == (0.0, 6.0)
    assert parse_axis("param", "k_center=0:6", dims).values == (0.0, 6.0)
    assert parse_axis("grid", "k_center=1 Hz, 2 Hz", dims).values == (1.0, 2.0)
    with pytest.raises(UsageError, match=r"k_center is .*, but '1 m' is a length"):
        parse_axis("param", "k_center=1 m:2 m", dims)


def test_the_table_has_the_speeds_spread_and_an_older_table_resumes(tmp_path: Path) -> None:
    """sweep.csv had the mean running speed only (tune's mean ± spread had no column); a
    table written before the column existed is resumed, its rows kept with the column empty."""
    from legdsl.api.sweep import METRICS, Job, run_sweep

    jobs = [Job(index=i, source=str(HOPPER), creature=None, controller="hop",
                values={"speed": s}, units={"speed": "m/s"}, fixed=(), duration=5.0,
                start=1.0, generated=str(tmp_path / "generated"), keep=None)
            for i, s in enumerate((0.5, 1.0))]  # fmt: skip
    table = tmp_path / "sweep.csv"
    old_columns = ["run", "speed", "outcome", "simulated", "strides",
                   *(m for m in METRICS if m != "running_speed_std")]  # fmt: skip
    table.write_text(",".join(old_columns) + "\n0,0.5,ok,2.0,3," + ",".join(["1"] * 11) + "\n")
    rows = run_sweep(jobs, table, workers=1)
    assert table.read_text().splitlines()[0].split(",")[5:7] == [
        "running_speed",
        "running_speed_std",
    ]
    assert math.isnan(rows[0]["running_speed_std"])  # the older row: not measured then,
    assert table.read_text().splitlines()[1].split(",")[6] == ""  # its cell empty
    assert isinstance(rows[1]["running_speed_std"], float) and rows[1]["running_speed_std"] >= 0


def test_a_metric_no_run_measured_is_said(capsys: pytest.CaptureFixture[str]) -> None:
    """A controller whose command is 'vel', not 'speed', swept to an empty map, saying nothing."""
    import argparse
    from types import SimpleNamespace

    from legdsl.api.sweep_cli import _say_unmeasured

    args = argparse.Namespace(controller="hop", t_from=3.0)
    novel = SimpleNamespace(inputs=[SimpleNamespace(name="vel")])
    rows = [{"outcome": "ok", "speed_error": math.nan}]
    _say_unmeasured(rows, "speed_error", args, novel, Path("s.png"))
    err = capsys.readouterr().err
    assert "no run measured speed_error, so s.png shows none: controller 'hop' has no input" in err
    _say_unmeasured([{"outcome": "fell at 1.000 s", "cot": "nan"}], "cot", args, novel, Path("s"))
    assert capsys.readouterr().err.endswith("every run fell or diverged\n")
    _say_unmeasured([{"outcome": "ok", "cot": 0.5}], "cot", args, novel, Path("s"))
    assert capsys.readouterr().err == ""


def _time_left(monkeypatch: pytest.MonkeyPatch, out: Path, arrivals: list[float],
               workers: int, simulated: list[float]) -> list:  # fmt: skip
    """(time, time left) as a sweep tells them, its rows coming back at ``arrivals`` (s) having
    simulated ``simulated`` s each, the pool waiting (a call each 0.6 s) between them."""
    from legdsl.api import sweep

    jobs = [sweep.Job(k, "x.leg", None, "hop", {"speed": 1.0}, {"speed": "m/s"}, (), 1.0, 0.0,
                      "g", None) for k in range(len(arrivals))]  # fmt: skip
    now = {"t": 0.0}
    from types import SimpleNamespace

    pool = SimpleNamespace(waiting=None)

    def rows(todo: list, _: object) -> Iterator[dict]:
        for job, t, sim in zip(todo, arrivals, simulated, strict=True):
            while now["t"] + 0.6 < t:
                now["t"] += 0.6
                pool.waiting()
            now["t"] = t
            yield {"run": job.index, "speed": 1.0, "outcome": "ok", "simulated": sim}

    monkeypatch.setattr(sweep, "run_jobs", rows)
    monkeypatch.setattr(sweep, "Workers", lambda *a: contextlib.nullcontext(pool))
    monkeypatch.setattr(sweep.time, "monotonic", lambda: now["t"])
    told: list = []
    sweep.run_sweep(jobs, out / "sweep.csv", workers,
                    lambda d, n, left: told.append((now["t"], left)))  # fmt: skip
    return told


def test_the_time_left_is_reckoned_from_the_first_row(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Before the first row the workers start and compile, and rows come back in waves: a
    sweep of 75 s said '24m08s left' at its first row. The pace is taken from the first wave's
    rows on, once the second has come back."""
    arrivals = [14.8] + [14.9] * 7 + [16.0] * 8 + [17.1] * 8 + [18.2] * 8 + [19.3] * 8
    told = _time_left(monkeypatch, tmp_path, arrivals, 2, [1.0] * len(arrivals))
    assert all(left is None for t, left in told if t <= 16.0)  # no pace before the second
    first = next((t, left) for t, left in told if left is not None)
    assert first[1] == pytest.approx(19.3 - first[0], rel=0.1)  # 1.1 s a wave, 3 to come
    assert all(left is None or left < 60 for _, left in told)


def test_the_time_left_follows_the_last_rows_not_the_mean_since_the_first(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """An outside user's 300 runs, the first 230 falling at once: the mean pace since the first
    row said 'about 0m02s left' with 18 s to go. Here 72 runs fall at once, then batches of 8
    take 1 s a run: two waves in, 12 runs (12 s) are left."""
    arrivals = [10 + 0.01 * i for i in range(72)] + [10.72 + 8.0 * (1 + i // 8) for i in range(28)]
    simulated = [0.01] * 72 + [8.0] * 28
    told = _time_left(monkeypatch, tmp_path, arrivals, 1, simulated)
    after = next(left for t, left in told if t > 26.72 + 0.1)
    assert after == pytest.approx(12.0 - 0.6, rel=0.1)
