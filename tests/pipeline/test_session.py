"""The compile driver (every stage, each file parsed once) and the run session ``legdsl run`` is."""

from __future__ import annotations

import io
import json
import os
import re
from collections import Counter
from pathlib import Path
from typing import Any

import pytest
from conftest import CREATURES, GENERATED
from runtime_helpers import assert_same

import legdsl.check.source
import legdsl.pipeline.compile
import legdsl.pipeline.session
import legdsl.sim.run_loop
from legdsl.check.source import check_file, check_tree
from legdsl.cli import main
from legdsl.lang.errors import LegError, UsageError
from legdsl.lang.parser import parse_file
from legdsl.pipeline.compile import compile_file
from legdsl.pipeline.session import RunSession
from legdsl.sim.recorder import sample_bytes
from legdsl.sim.run_loop import RunOptions

HOPPER = CREATURES / "hopper.leg"


@pytest.fixture
def parses(monkeypatch: pytest.MonkeyPatch) -> Counter[str]:
    """How often each file is parsed, wherever the parser is called from."""
    counts: Counter[str] = Counter()

    def counting(path: str | Path, recover: bool = False) -> Any:
        counts[str(Path(path).resolve())] += 1
        return parse_file(path, recover)

    for module in (legdsl.check.source, legdsl.pipeline.compile, legdsl.pipeline.session):
        monkeypatch.setattr(module, "parse_file", counting)
    return counts


def test_check_tree_is_check_file_on_a_parsed_tree() -> None:
    tree, text = parse_file(HOPPER)
    assert check_tree(tree, text, HOPPER) == check_file(HOPPER)


def test_check_tree_reports_mistakes_as_check_file_does(tmp_path: Path) -> None:
    bad = tmp_path / "bad.leg"
    bad.write_text("use nothing_of_the_kind\n", encoding="utf-8")
    with pytest.raises(LegError) as from_tree:
        check_tree(*parse_file(bad), bad)
    with pytest.raises(LegError) as from_file:
        check_file(bad)
    assert from_tree.value.render() == from_file.value.render()
    assert "cannot find 'nothing_of_the_kind'" in from_tree.value.render()


def test_the_driver_returns_every_stage_and_parses_each_file_once(
    parses: Counter[str],
) -> None:
    (compiled,) = compile_file(HOPPER)
    assert parses[str(HOPPER.resolve())] == 1
    assert set(parses.values()) == {1}  # the files it uses too
    assert compiled.syntax.creatures[0].name.name == "hopper"
    assert compiled.model.name == "hopper"
    assert compiled.controllers == tuple(compiled.model.controllers)
    assert [c.name for c in compiled.controllers] == ["hop"]
    assert len(compiled.lowered) == 1
    assert compiled.system is not None
    assert [name for name, _ in compiled.files] == [
        "__init__.py",
        "dynamics.py",
        "dynamics.c",
        "dynamics_some.c",
        "dynamics.h",
        "control_hop.py",
        "control_hop.c",
        "SHA256SUMS",
    ]
    assert [stage for stage, _ in compiled.timings] == ["parse", "check", "lower", "print"]


def test_a_session_compiles_what_is_missing_parsing_once_and_then_reuses_it(
    parses: Counter[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("LEGDSL_CACHE", str(tmp_path / "cache"))  # not copied from another test's
    log = io.StringIO()
    session = RunSession.from_file(HOPPER, generated=tmp_path / "gen", log=log)
    assert parses[str(HOPPER.resolve())] == 1
    assert "dynamics.py is missing; compiling" in log.getvalue()
    assert sorted(p.name for p in (tmp_path / "gen" / "hopper").iterdir()) == [
        "SHA256SUMS",
        "__init__.py",
        "control_hop.c",
        "control_hop.py",
        "dynamics.c",
        "dynamics.h",
        "dynamics.py",
        "dynamics_some.c",
    ]
    session.control("hop")  # fresh now: no second compile
    again = RunSession.from_file(HOPPER, generated=tmp_path / "gen", log=log)
    again.control("hop")
    assert log.getvalue().count("compiling") == 1
    assert session.controllers == ("hop",)


@pytest.mark.parametrize(
    ("damage", "said"),
    [
        (lambda text: text[: len(text) // 3], "changed since it was written"),  # cut short
        (lambda text: text.replace("9.81", "1.62"), "changed since it was written"),  # an edit
    ],
)
def test_a_damaged_generated_module_is_written_again(
    generated: Path, damage: Any, said: str
) -> None:
    """A generated file cut short (its fingerprint intact) or edited by hand is not the file
    SHA256SUMS lists: the run compiles the creature again instead of running the damaged code
    (a cut one used to fail mid-run as a legdsl bug)."""
    folder = generated / "hopper"
    whole = (folder / "dynamics.py").read_text()
    damaged = damage(whole)
    assert damaged != whole and "MODEL_FINGERPRINT" in damaged
    (folder / "dynamics.py").write_text(damaged)
    log = io.StringIO()
    session = RunSession.from_file(HOPPER, generated=generated, log=log)
    assert f"dynamics.py is {said}" in log.getvalue()
    assert (folder / "dynamics.py").read_text() == whole
    run = session.run("hop", ["speed=1m/s"], options=RunOptions(duration=0.2), backend="python")
    assert run.status == "ok"
    (folder / "SHA256SUMS").unlink()  # an older legdsl's directory: written again, then listed
    RunSession.from_file(HOPPER, generated=generated, log=log)
    assert "dynamics.py is unchecked (not in a SHA256SUMS beside it)" in log.getvalue()
    assert (folder / "SHA256SUMS").is_file()


def test_a_recording_that_would_fill_the_memory_stops_the_run_keeping_it(
    generated: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The recording grows with the samples; one that would pass half the machine's memory
    stops the run there, as interrupted, with what it recorded (the system would kill it
    later with nothing written). The same on both backends. (The machine here has 1 MB.)"""
    monkeypatch.setattr(legdsl.sim.run_loop, "recording_budget", lambda: 2**19)
    session = RunSession.from_file(HOPPER, generated=generated)
    runs = [
        session.run("hop", ["speed=1m/s"], options=RunOptions(duration=1e9), backend=backend)
        for backend in ("python", "c")
    ]
    for run in runs:
        assert run.status == "interrupted"
        assert "by its recording filling half of the memory the run may take" in run.result.message
        rows = len(run.result.trajectory)
        assert rows == 1024 and 2 * rows * sample_bytes(session.model) > 2**19  # no doubling
    assert_same(*(run.result for run in runs))


def test_a_batch_whose_recordings_cannot_fit_is_refused(generated: Path) -> None:
    from legdsl.pipeline.batch_memory import check_recordings

    model = RunSession.from_file(HOPPER, generated=generated).model
    check_recordings(model, RunOptions(duration=10.0), copies=4)  # fits
    with pytest.raises(UsageError, match=r"a batch of 1000000 copies of 1000 s: their recordings"):
        check_recordings(model, RunOptions(duration=1000.0), copies=1_000_000)


def test_the_cli_run_is_the_session_run(generated: Path, tmp_path: Path) -> None:
    settings = ["speed=0.5m/s", "speed=1m/s@0.1s"]
    argv = ["run", str(HOPPER), "--controller", "hop", "--time", "0.2"]
    argv += [x for s in settings for x in ("--set", s)]
    assert main([*argv, "--generated", str(generated), "--out", str(tmp_path / "cli")]) == 0
    session = RunSession.from_file(HOPPER, generated=generated)
    run = session.run("hop", settings, options=RunOptions(duration=0.2))
    assert run.status == "ok"
    assert run.write(tmp_path / "api") == tmp_path / "api"
    for name in ("trajectory.npz", "trajectory.csv", "run.json"):
        assert (tmp_path / "cli" / name).read_bytes() == (tmp_path / "api" / name).read_bytes()
    info = json.loads((tmp_path / "api" / "run.json").read_text())
    from_run = os.path.relpath(generated, tmp_path / "api")  # where it was written
    folder = {"from_run": from_run, "absolute": str(generated)}
    assert info.pop("generated") == folder and info == run.info()
    assert list(info)[:9] == [
        "legdsl",
        "source",
        "creature",
        "source_sha256",
        "creature_fingerprint",
        "controller_fingerprint",
        "options",
        "controller",
        "settings",
    ]
    assert "hopper (" in run.summary()


def test_a_session_rejects_a_path_without_a_controller_and_unknown_controllers(
    generated: Path,
) -> None:
    session = RunSession.from_file(HOPPER, generated=generated)
    with pytest.raises(UsageError, match="a path is followed by a controller"):
        session.run(paths=["circle(center = (0, 5) m, radius = 5 m, turn = left)"])
    with pytest.raises(UsageError, match="has no such controller .it has hop"):
        session.run("trot")
    with pytest.raises(UsageError, match="no such controller; did you mean 'hop'"):
        session.run("hopp")
    with pytest.raises(UsageError, match="no input or parameter 'sped'; did you mean 'speed'"):
        session.run("hop", ["sped=1m/s"])
    with pytest.raises(UsageError, match="choose a controller with --controller"):
        session.run(settings=["speed=1m/s"])
    with pytest.raises(UsageError, match="'speed' is a controller input"):
        session.run(settings="speed=1m/s")  # one setting alone, not a list of characters


def test_a_passive_session_run_has_no_controller_fields(generated: Path) -> None:
    run = RunSession.from_file(HOPPER, generated=generated).run(options=RunOptions(duration=0.05))
    info = run.info()
    assert info["controller"] is None and run.machine is None
    assert not {"inputs", "params", "paths", "path_reports"} & set(info)
    # its summary says no controller ran, and how to choose one (a newcomer's run without
    # --controller fell with no word why)
    assert re.search(
        r"controller +none, a passive run: choose one with --controller hop", run.summary()
    )
    controlled = RunSession.from_file(HOPPER, generated=generated).run(
        "hop", options=RunOptions(duration=0.05)
    )
    assert "passive" not in controlled.summary()


def test_a_long_step_without_a_control_interval_runs_the_controller_every_step(
    generated: Path,
) -> None:
    """--dt 10ms alone (or the API's dt=): the default control interval, 2 ms, is never below
    the step (a --control-dt asked below it is refused, tests/faults/test_user_errors.py)."""
    from legdsl.pipeline.scaled import run_options

    model = check_file(CREATURES / "hopper.leg")[0]
    assert run_options(model, dt=0.01).control_dt == 0.01
    assert run_options(model, dt=0.001).control_dt == 0.002
    assert run_options(model, dt=0.01, control_dt=0.02).control_dt == 0.02
    import legdsl

    run = legdsl.load(CREATURES / "hopper.leg", generated=generated).run("hop", time=0.2, dt=0.005)
    assert run.info["options"]["control_dt"] == 0.005


def test_run_json_gives_the_control_interval_as_run(generated: Path) -> None:
    """1.1 ms at a 0.4 ms step runs every 3 steps: run.json keeps the option as given and says
    the interval run, as it does the record rate's (200 Hz: every 13 steps, 5.2 ms)."""
    run = RunSession.from_file(HOPPER, generated=generated).run(
        "hop", options=RunOptions(duration=0.05, dt=0.0004, control_dt=0.0011)
    )
    info = run.info()
    assert info["options"]["control_dt"] == 0.0011
    assert info["control_interval"] == 0.0012
    assert info["record_interval"] == 0.0052
    states = [e["t"] for e in run.result.events if e["kind"] == "state"]
    assert all(round(t / 0.0012, 6).is_integer() for t in states)  # entered at ticks only


def test_a_run_that_falls_says_where_its_controller_was(generated: Path) -> None:
    """A table waiting in one state for an event that never comes (a liftoff with the feet
    still down) fell with no word of it: the summary names the state and when it was entered."""
    sess = RunSession.from_file(CREATURES / "quadruped.leg", generated=generated)
    fell = sess.run("bound", ["speed=6m/s"], options=RunOptions(duration=6.0))
    assert fell.result.status == "fell"
    last = [e for e in fell.result.events if e["kind"] == "state"][-1]
    row = re.search(r"controller state at the end +(\w+), entered at ([\d.]+) s", fell.summary())
    assert row is not None and row[1] == last["state"] and float(row[2]) == round(last["t"], 3)
    held = sess.run("bound", ["speed=2m/s"], options=RunOptions(duration=0.5))
    assert held.result.status == "ok" and "state at the end" not in held.summary()


def test_run_json_hashes_the_file_as_it_was_checked(tmp_path: Path) -> None:
    """A .leg file saved while its run went on: run.json named the edited file's hash beside
    the fingerprint of the creature actually run."""
    import hashlib
    import shutil

    leg = tmp_path / "hopper.leg"
    shutil.copy(CREATURES / "hopper.leg", leg)
    checked = hashlib.sha256(leg.read_bytes()).hexdigest()
    session = RunSession.from_file(leg, generated=GENERATED)
    run = session.run("hop", options=RunOptions(0.05))
    leg.write_text(leg.read_text() + "\n# saved during the run\n")
    info = json.loads((run.write(tmp_path / "run") / "run.json").read_text())
    assert info["source_sha256"] == checked
