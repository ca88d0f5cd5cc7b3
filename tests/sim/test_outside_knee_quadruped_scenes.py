"""The outside knee quadruped's gait changes (tests/good/outside/knee_quadruped_scenes.leg;
docs/quadruped.md, "A quadruped with knees", "Changing gait"). Its bound and gallop enter
FLIGHT ``on liftoff(active) or touchdown(idle)``: the handover reads an ``or`` by its first
alternative, so their tables have a flight to take over in (before, they had no liftoff fact
and a controller took over from them at once, in a stance of either pair)."""

from __future__ import annotations

import json
from pathlib import Path

from conftest import ROOT

from legdsl.check.source import check_model
from legdsl.pipeline.session import RunSession
from legdsl.sim.handover import cycle, lifts_off
from legdsl.sim.run_loop import RunOptions

SCENES = ROOT / "tests" / "good" / "outside" / "knee_quadruped_scenes.leg"


def test_the_bound_and_gallop_flights_are_liftoffs() -> None:
    """FLIGHT ``on liftoff(active) or touchdown(idle)`` knows the pair that left is up."""
    model = check_model(SCENES)
    for name in ("bound", "gallop"):
        ctl = model.controller(name)
        pairs = cycle(model, ctl)
        assert lifts_off(pairs), name
        flights = [p for p in pairs if ctl.state_names[p.state] == "FLIGHT"]
        assert flights and all(not p.facts[0].down for p in flights), name


def test_the_gallop_takes_over_from_the_bound_in_a_flight(tmp_path: Path) -> None:
    """The bound at 2.5 m/s from standing, switched to the gallop at 3 m/s at 3 s (the scene
    switches at 12 s, after the trot; this keeps the test short): the gallop waits for a
    liftoff into a flight (3.094 s), does not fall, and runs within 5% of 3 m/s from 3 s
    after it took over (3.057 m/s measured)."""
    session = RunSession.from_file(SCENES, generated=tmp_path / "generated")
    run = session.run(
        "bound",
        ["speed=2.5m/s", "speed=3m/s@3s"],
        options=RunOptions(duration=9.0),
        switches=["3s=gallop"],
        backend="c",
    )
    assert run.result.status == "ok", run.result.message
    info = json.loads((run.write(tmp_path / "out") / "run.json").read_text())
    (seg,) = info["segments"][1:]
    assert seg["controller"] == "gallop" and seg["state"] == "FLIGHT" and seg["from"] > 3.0
    tr = run.result.trajectory
    later = tr.t >= seg["from"] + 3.0
    t, x = tr.t[later], tr.com[later][:, 0]
    speed = (x[-1] - x[0]) / (t[-1] - t[0])
    assert abs(speed - 3.0) < 0.15, speed
