"""Creatures of shapes the shipped ones are not: each runs the same on both backends and is
measured, or is refused with a message (never a traceback, never a run that stops at once)."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import CREATURES, GENERATED
from runtime_helpers import assert_same

from legdsl.cli import main
from legdsl.codegen.c import build
from legdsl.pipeline.session import RunSession
from legdsl.sim import c_library
from legdsl.sim.c_backend import available
from legdsl.sim.run_loop import RunOptions

WELDED = """
creature welded {
  spatial
  body base fixed at (0 m, 0 m, 1 m) { mass 1 kg  inertia (0.01, 0.01, 0.01) kg*m^2  length 0.3 m }
  body arm on base via fixed weld at tip { mass 1 kg  inertia (0.01, 0.01, 0.01) kg*m^2 }
}
"""


@pytest.mark.skipif(available() is not None, reason=f"needs a C compiler: {available()}")
def test_a_creature_with_no_degrees_of_freedom_runs_and_is_measured(tmp_path: Path) -> None:
    leg = tmp_path / "welded.leg"
    leg.write_text(WELDED, encoding="utf-8")
    sess = RunSession.from_file(leg, generated=tmp_path / "gen")
    opts = RunOptions(duration=0.05)
    python = sess.run(None, [], options=opts, backend="python").result
    c = sess.run(None, [], options=opts, backend="c").result
    assert python.status == "ok", python.message  # was: diverged at t = 0 on an empty max()
    assert_same(python, c)
    out = tmp_path / "run"
    assert main(["run", str(leg), "--backend", "c", "--generated", str(tmp_path / "gen"),
                 "--time", "0.05", "--out", str(out)]) == 0  # fmt: skip
    assert main(["metrics", str(out)]) == 0  # was: exit 70 on an empty q


def test_the_energy_of_a_giant_is_printed_in_powers_of_ten(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    leg = tmp_path / "giant.leg"
    leg.write_text(
        "creature giant {\n  planar\n  body b free { mass 1e200 kg  inertia 1e200 kg*m^2 "
        " initial x = 0 m, z = 1 m, pitch = 0 deg }\n}\n",
        encoding="utf-8",
    )
    argv = ["run", str(leg), "--backend", "python", "--generated", str(tmp_path / "gen")]
    assert main([*argv, "--time", "0.01", "--out", str(tmp_path / "run")]) == 0
    line = next(x for x in capsys.readouterr().out.splitlines() if "total energy" in x)
    assert "9.81e+200 J ->" in line and len(line) < 100  # was: 200 digits and '.000'


@pytest.mark.skipif(available() is not None, reason=f"needs a C compiler: {available()}")
def test_a_long_unit_compiles_at_o1_and_runs_bit_for_bit(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """gcc -O3 took 200 s and 1.5 GB on an 82-DOF chain's dynamics.c: a unit that long builds
    at -O1, which must give the same doubles (the hopper's units made 'long' here)."""
    for known in ("_LOADED", "_BY_STAT", "_TRUSTED"):  # as in a new process: nothing loaded
        monkeypatch.setattr(c_library, known, {})
    monkeypatch.setenv("LEGDSL_CACHE", str(tmp_path / "cache"))
    monkeypatch.setattr(build, "LARGE_UNIT", 20_000)
    commands: list[list[str]] = []
    start = build._start
    monkeypatch.setattr(
        build,
        "_start",
        lambda c, cc, work, started: commands.append(c) or start(c, cc, work, started),
    )
    sess = RunSession.from_file(CREATURES / "hopper.leg", generated=GENERATED)
    opts = RunOptions(duration=0.3)
    c = sess.run("hop", ["speed=1m/s"], options=opts, backend="c").result
    python = sess.run("hop", ["speed=1m/s"], options=opts, backend="python").result
    assert_same(python, c)
    levels = {Path(cmd[-1]).name: cmd[1] for cmd in commands if "-c" in cmd}
    assert levels["dynamics.c"] == "-O1" and levels["dynamics_some.c"] == "-O3", levels


@pytest.mark.skipif(available() is not None, reason=f"needs a C compiler: {available()}")
def test_a_creature_with_a_ground_and_no_contacts_runs_on_both_backends(tmp_path: Path) -> None:
    leg = tmp_path / "nocon.leg"
    leg.write_text(
        "creature nocon {\n  planar\n  body b free { mass 1 kg  inertia 0.01 kg*m^2 "
        " initial x = 0 m, z = 1 m, pitch = 0 deg }\n"
        "  ground { normal spring(k = 3e4 N/m)  tangent spring(k = 2e4 N/m) }\n}\n",
        encoding="utf-8",
    )
    sess = RunSession.from_file(leg, generated=tmp_path / "gen")
    opts = RunOptions(duration=0.05)
    python = sess.run(None, [], options=opts, backend="python").result
    c = sess.run(None, [], options=opts, backend="c").result
    assert python.status == "ok", python.message  # was: diverged at t = 0 recording no forces
    assert_same(python, c)
