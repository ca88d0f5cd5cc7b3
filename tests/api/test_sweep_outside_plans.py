"""legdsl sweep's plan and table, as an outside user found them: a value too stiff for the
step found only at its run, rows that are not the plan's, --keep-runs added on a resume."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.api.sweep_cli import _largest, _plan_differs
from legdsl.cli import main
from legdsl.lang.errors import UsageError

ROOT = Path(__file__).resolve().parents[2]
HOPPER = ROOT / "creatures" / "hopper.leg"

pytestmark = pytest.mark.usefixtures("hopper_modules")


def sweep(tmp_path: Path, *extra: str) -> list[str]:
    return once(["sweep", str(HOPPER), "--controller", "hop", "--time", "0.5", "--from", "0.1",
                 "--jobs", "1", "--out", str(tmp_path / "out"),
                 "--generated", str(tmp_path / "generated"), *extra])  # fmt: skip


def once(argv: list[str]) -> list[str]:
    """``argv`` with a one-value option given again later taking the place of the first (a
    second value is refused)."""
    last = {flag: k for k, flag in enumerate(argv) if flag in ("--time", "--from", "--jobs")}
    dropped = {k + d for k, flag in enumerate(argv) if flag in last and last[flag] != k
               for d in (0, 1)}  # fmt: skip
    return [x for k, x in enumerate(argv) if k not in dropped]


def test_a_value_too_stiff_later_in_the_plan_is_refused_before_any_run(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """`--grid leg_spring.k=3000,1e7` ran k = 3000, wrote sweep.json and its row, then stopped
    at 1e7; the corrected command (k below the bound, as told) was refused as another sweep."""
    assert main(sweep(tmp_path, "--grid", "leg_spring.k=3000,1e7")) == 2
    err = capsys.readouterr().err
    assert "sweep: its runs at leg_spring.k = 1e+07 N/m: actuator 'leg_spring' is too stiff" in err
    assert (
        "a step below 0.341 ms (dt in the file's simulation block; a sweep or a tune has no --dt)"
        in err
    )
    assert not (tmp_path / "out" / "sweep.json").exists()
    assert not (tmp_path / "out" / "sweep.csv").exists()
    assert main(sweep(tmp_path, "--grid", "leg_spring.k=3000,5e6")) == 0


def test_a_too_long_time_is_told_a_step_a_sweep_can_take(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """It said "or a longer --dt", an option legdsl sweep has not."""
    assert main(once([*sweep(tmp_path, "--grid", "speed=0.5,1"), "--time", "1e20"])) == 2
    err = capsys.readouterr().err
    assert "sweep: its first run (speed = 0.5 m/s): --time 1e+20s is" in err, err
    assert err.rstrip().endswith(
        "or a longer step (dt in the file's simulation block; a sweep or a tune has no --dt)"
    )  # it advised --dt, which a sweep refuses as an unknown argument
    assert "steps of dt 0.0004s" in err
    assert not (tmp_path / "out" / "sweep.json").exists()


def test_the_largest_values_are_those_no_other_exceeds_in_both() -> None:
    assert _largest([(1.0,), (2.0,), (3.0,)]) == [(3.0,)]
    pairs = sorted([(1.0, 9.0), (2.0, 1.0), (3.0, 5.0), (3.0, 2.0), (2.5, 6.0), (0.5, 9.5)])
    assert _largest(pairs) == [(3.0, 5.0), (2.5, 6.0), (1.0, 9.0), (0.5, 9.5)]


def test_keep_runs_added_on_a_resume_says_the_rows_from_before_have_no_directory(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """An interrupted sweep resumed with --keep-runs added kept the new runs' directories only,
    and said nothing of the rows from before."""
    assert main(sweep(tmp_path, "--grid", "speed=0.5,1,1.5")) == 0
    table = tmp_path / "out" / "sweep.csv"
    table.write_text("".join(table.read_text().splitlines(keepends=True)[:3]))  # runs 0 and 1
    capsys.readouterr()
    assert main(sweep(tmp_path, "--grid", "speed=0.5,1,1.5", "--keep-runs")) == 0
    err = capsys.readouterr().err
    assert "--keep-runs keeps the runs a sweep runs: 2 of the 2 rows from before in" in err, err
    assert "have no directory under" in err and "(run 0, ...), as they ran without it" in err
    assert sorted(p.name for p in (tmp_path / "out" / "runs").iterdir()) == ["0002"]


@pytest.mark.parametrize(
    ("table", "message"),
    [("run,speed\n0,0.5\n1,1.0\n1,1.0\n", "at line 4: a second row of run 1 (line 3 is one)"),
     ("run,speed\n0,0.5\n0,1.0\n", "at line 3: run 0's speed is 1.0 there, but 0.5 in the sweep's plan"),
     ("run,speed\n1,0.5\n", "at line 2: run 1's speed is 0.5 there, but 1.0 in the sweep's plan")],
    ids=["a row twice", "renumbered", "other values"],
)  # fmt: skip
def test_a_row_that_is_not_the_plans_is_told_by_its_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], table: str, message: str
) -> None:
    """A run's row pasted twice (or two tables joined) made '8 runs, 8 of them from before' of a
    6-run sweep, and a row renumbered to another run was kept under that run's number."""
    (tmp_path / "out").mkdir()
    (tmp_path / "out" / "sweep.csv").write_text(table)
    assert main(sweep(tmp_path, "--grid", "speed=0.5,1")) == 2
    err = capsys.readouterr().err
    assert f"sweep.csv is damaged {message}" in err, err


def test_a_fixed_setting_in_other_units_is_the_same_sweep(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """`--set speed=150cm/s` after `--set speed=1.5m/s` was refused as another sweep, where
    grid values in other units were taken as the same."""
    assert main(sweep(tmp_path, "--grid", "k_speed=0.04,0.08", "--set", "speed=1.5m/s")) == 0
    capsys.readouterr()
    assert main(sweep(tmp_path, "--grid", "k_speed=40ms,80ms", "--set", "speed=150cm/s")) == 0
    assert "2 runs, 2 of them from before" in capsys.readouterr().out
    assert main(sweep(tmp_path, "--grid", "k_speed=0.04,0.08", "--set", "speed=1.4m/s")) == 2
    assert "holds another sweep (other --set)" in capsys.readouterr().err


def test_another_creature_of_the_file_is_named_as_the_difference() -> None:
    """A sweep of `--creature heavy`, then `--creature hopper` into the same --out, was told
    "the .leg file's creature or controller has changed since its rows were run"."""
    plan = {"file": "two.leg", "creature": "hopper", "controller": "hop", "set": [],
            "creature_digest": "a", "controller_digest": "b"}  # fmt: skip
    before = {**plan, "creature": "heavy", "creature_digest": "c", "controller_digest": "d"}
    assert _plan_differs(before, plan) == "other --creature"
    assert _plan_differs({**plan, "time": 2.0}, {**plan, "time": 3.0}) == "other --time"


def test_a_table_without_its_plan_is_not_taken_as_this_sweeps(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """sweep.csv with its sweep.json gone (the table alone copied to a new folder) was taken
    as this sweep's, its rows of a 5 s sweep measured from 2 s mixed with 8 s ones from 1 s."""
    assert main(sweep(tmp_path, "--grid", "speed=0.5,1")) == 0
    (tmp_path / "out" / "sweep.json").unlink()
    capsys.readouterr()
    assert main(once([*sweep(tmp_path, "--grid", "speed=0.5,1"), "--time", "0.4"])) == 2
    assert "sweep.csv has rows but no sweep.json, so what they were run with is unknown" in (
        capsys.readouterr().err
    )
    assert not (tmp_path / "out" / "sweep.json").exists()  # nothing claims them


@pytest.mark.parametrize("command", ["sweep", "tune"])
def test_an_out_made_for_a_refused_command_is_not_left_with_its_lock_alone(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, command: str
) -> None:
    """`--dask tcp://127.0.0.1:1` (a scheduler not reached, here a refusal as the workers
    start) left a new --out folder holding only its .sweep.lock or .tune.lock."""
    from legdsl.api.workers import Workers

    def unreached(self: Workers) -> Workers:
        raise UsageError("--dask tcp://127.0.0.1:1: cannot reach the scheduler")

    monkeypatch.setattr(Workers, "__enter__", unreached)
    argv = sweep(tmp_path, "--grid", "speed=0.5,1")
    if command == "tune":
        argv = ["tune", str(HOPPER), "--controller", "hop", "--param", "kp=50:300", "--speeds",
                "1", "--time", "0.5", "--from", "0.1", "--jobs", "1", "--out",
                str(tmp_path / "out"), "--generated", str(tmp_path / "generated")]  # fmt: skip
    assert main(argv) == 2
    assert not (tmp_path / "out").exists()
    (tmp_path / "out").mkdir()  # one that was there before stays, its lock gone or not
    assert main(argv) == 2 and (tmp_path / "out").is_dir()


def test_a_sweep_without_a_c_compiler_says_its_runs_go_on_python(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """legdsl run says it runs on the Python backend where no C compiler is found; a sweep and
    a tune said nothing, and ran many times slower (their runs' notices are not shown)."""
    from legdsl.pipeline.backend import python_backend_note

    monkeypatch.setenv("LEGDSL_CC", "/nonexistent")
    assert main(sweep(tmp_path, "--grid", "speed=0.5,1", "--time", "0.2")) == 0
    err = capsys.readouterr().err
    assert "legdsl: note: LEGDSL_CC=/nonexistent: no such program" in err
    assert err.count("the runs go on the Python backend") == 1
    monkeypatch.setenv("LEGDSL_BACKEND", "python")  # chosen: nothing to say
    assert python_backend_note() is None
