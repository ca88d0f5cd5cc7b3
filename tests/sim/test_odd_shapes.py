"""Creatures of shapes the shipped ones are not: each runs the same on both backends and is
measured, or is refused with a message (never a traceback, never a run that stops at once)."""

from __future__ import annotations

from pathlib import Path

import pytest
from runtime_helpers import assert_same

from legdsl.cli import main
from legdsl.pipeline.session import RunSession
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
