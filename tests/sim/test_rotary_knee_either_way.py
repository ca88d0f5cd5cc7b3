"""``hop_apex_rotary`` (stdlib/raibert.leg) hops a knee bent either way.

tests/good/outside/knee_hopper.leg bends its knee to positive angles (bent at 40 deg,
straightening towards 0): its spring's torque is negative in compression, so a stroke that
steps the rest angle up bends the knee further in thrust. The library action used to do
that, and the hopper lost height hop by hop and fell, with no message (an outside user's
report). The knee biped, bent to negative angles, is run bit for bit as before by
tests/sim/test_outside_knee_biped.py.
"""

from __future__ import annotations

from pathlib import Path

from conftest import OUTSIDE

from legdsl.analysis.metrics import compute_metrics
from legdsl.analysis.rows import apex_heights
from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions

OWN_THRUST = "thrust(active, bend, -stroke)"  # the file's own, a fixed straightening step
LIBRARY_THRUST = "hop_apex_rotary(active, bend, height + apex_trim, 0 deg, 30 deg)"


def test_hop_apex_rotary_hops_a_knee_bent_to_positive_angles(tmp_path: Path) -> None:
    text = (OUTSIDE / "knee_hopper.leg").read_text(encoding="utf-8")
    assert "initial 40 deg" in text and OWN_THRUST in text  # a knee bent to +40 deg
    path = tmp_path / "knee_hopper.leg"
    path.write_text(text.replace(OWN_THRUST, LIBRARY_THRUST), encoding="utf-8")
    session = RunSession.from_file(path, generated=tmp_path / "generated")
    run = session.run("hop", options=RunOptions(duration=4.0), backend="python").result
    assert run.status == "ok", run.message  # it fell at 1.2 s
    flights = compute_metrics(run.trajectory, t_from=2.0).flights
    apexes = apex_heights(run.trajectory, flights)
    assert len(apexes) >= 5
    assert all(abs(a - 0.60) < 0.01 for a in apexes), apexes  # the asked 60 cm
