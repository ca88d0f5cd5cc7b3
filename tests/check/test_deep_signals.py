"""Signals written with signals, and lets with lets, as deep as the later stages can take.

A signal is resolved before the expression that names it is checked, so a chain of signals
is checked without recursing through their expressions: a chain of 80 was a RecursionError
("nested too deeply", no line, no caret) and now compiles and runs. Past the limits
(``MAX_SIGNAL_CHAIN`` signals, ``MAX_WRITTEN_DEPTH`` levels written out) the error has its
line (tests/bad/control_signal_chain_too_long, control_lets_written_out_too_deep)."""

from __future__ import annotations

import time
from pathlib import Path

import pytest
from conftest import CREATURES

from legdsl.check.control_depth import MAX_ACTION_DEPTH, MAX_WRITTEN_DEPTH, MAX_WRITTEN_SIZE
from legdsl.lang.errors import LegError
from legdsl.pipeline.compile import compile_model
from legdsl.pipeline.generated import write_generated
from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions


def _hopper_with(tmp_path: Path, signals: list[str], aim: str) -> Path:
    text = (CREATURES / "hopper.leg").read_text(encoding="utf-8")
    text = text.replace("  table {", "\n".join(signals) + "\n  table {", 1)
    within_reach = "<= reach, speed,"  # the stride's aim when the command is within reach
    assert within_reach in text
    text = text.replace(within_reach, f"<= reach, {aim},")
    path = tmp_path / "hopper.leg"
    path.write_text(text, encoding="utf-8")
    return path


def test_a_chain_of_80_signals_compiles_and_runs(tmp_path: Path) -> None:
    chain = ["  signal s0 = speed"]
    chain += [f"  signal s{k} = s{k - 1} * 1.0 + 0 m/s" for k in range(1, 80)]
    path = _hopper_with(tmp_path, chain, "s79")
    write_generated(compile_model(path), tmp_path / "generated")
    session = RunSession.from_file(path, generated=tmp_path / "generated")
    run = session.run("hop", ["speed=1m/s"], options=RunOptions(duration=1.0), backend="python")
    assert run.result.status == "ok"
    plain = RunSession.from_file(CREATURES / "hopper.leg", generated=tmp_path / "plain")
    same = plain.run("hop", ["speed=1m/s"], options=RunOptions(duration=1.0), backend="python")
    assert (run.result.trajectory.q == same.result.trajectory.q).all()  # s79 is speed * 1.0 ... + 0


def test_signals_each_used_twice_are_refused_where_written_out_they_pass_the_size(
    tmp_path: Path,
) -> None:
    """Each signal squares the one before as ``s * s``: written out, the 13th has some 33,000
    operators and values, and 30 would take days to check (tripling every two). ``compile``
    refuses the file at that signal's line, as ``check`` does (the bad corpus), in seconds."""
    chain = ["  signal s0 = speed"]
    chain += [f"  signal s{k} = s{k - 1} * s{k - 1} / (1 m/s)" for k in range(1, 30)]
    path = _hopper_with(tmp_path, chain, "s29")
    start = time.perf_counter()
    with pytest.raises(LegError) as refused:
        compile_model(path)
    assert time.perf_counter() - start < 30
    (found,) = refused.value.diagnostics
    text = path.read_text(encoding="utf-8").split("\n")
    assert text[found.span.line - 1] == "  signal s12 = s11 * s11 / (1 m/s)"
    assert f"(more than {MAX_WRITTEN_SIZE:,})" in found.message


def test_actions_as_deep_as_checked_with_an_expression_as_deep_compile_and_run(
    tmp_path: Path,
) -> None:
    """``MAX_ACTION_DEPTH`` actions, each calling the next, the last with a statement
    ``MAX_WRITTEN_DEPTH`` levels deep: the fingerprints, lowering and pickling walk both
    recursively, and the file ``check`` accepts compiles and runs (at 250 actions compile
    met Python's recursion limit; such chains are refused now, tests/bad)."""
    last = MAX_ACTION_DEPTH - 1
    n = (MAX_WRITTEN_DEPTH - 3) // 2  # each let 2 levels; the statement 2 more, and the read
    lets = ["let x0 = l.spring.rest"]
    lets += [f"let x{k} = x{k - 1} * 1.0 + 0 m" for k in range(1, n + 1)]
    actions = [f"  action a{k}(l) {{ a{k + 1}(l) }}" for k in range(last)]
    actions.append(f"  action a{last}(l) {{ {'; '.join(lets)}; l.spring.rest = x{n} * 1.0 + 0 m }}")
    text = (CREATURES / "hopper.leg").read_text(encoding="utf-8")
    text = text.replace("  table {", "\n".join(actions) + "\n  table {", 1)
    text = text.replace("free_hip(active)", "free_hip(active); a0(active)", 1)
    path = tmp_path / "hopper.leg"
    path.write_text(text, encoding="utf-8")
    write_generated(compile_model(path), tmp_path / "generated")
    session = RunSession.from_file(path, generated=tmp_path / "generated")
    run = session.run("hop", ["speed=1m/s"], options=RunOptions(duration=0.3), backend="python")
    assert run.result.status == "ok"
