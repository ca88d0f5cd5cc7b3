"""The outside knee quadruped's gait changes (tests/good/outside/knee_quadruped_scenes.leg;
docs/quadruped.md, "A quadruped with knees", "Changing gait"). Its bound and gallop enter
FLIGHT ``on liftoff(active) or touchdown(idle)``: the handover reads an ``or`` by its first
alternative, so their tables have a flight to take over in (before, they had no liftoff fact
and a controller took over from them at once, in a stance of either pair)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from conftest import ROOT

from legdsl.check.source import check_model
from legdsl.pipeline.session import RunSession
from legdsl.sim.handover import cycle, lands_on, lifts_off
from legdsl.sim.run_loop import RunOptions

SCENES = ROOT / "tests" / "good" / "outside" / "knee_quadruped_scenes.leg"


@pytest.fixture(scope="module")
def session(tmp_path_factory: pytest.TempPathFactory) -> RunSession:
    """One session (its generated code compiled once) for the runs below."""
    return RunSession.from_file(SCENES, generated=tmp_path_factory.mktemp("generated"))


def test_the_bound_and_gallop_flights_are_liftoffs() -> None:
    """FLIGHT ``on liftoff(active) or touchdown(idle)`` knows the pair that left is up."""
    model = check_model(SCENES)
    for name in ("bound", "gallop"):
        ctl = model.controller(name)
        pairs = cycle(model, ctl)
        assert lifts_off(pairs), name
        flights = [p for p in pairs if ctl.state_names[p.state] == "FLIGHT"]
        assert flights and all(not p.facts[0].down for p in flights), name


def test_the_trot_lands_a_diagonal_after_its_flight() -> None:
    """``lands_on``: after each FLIGHT the trot lands the other diagonal, the gallop after its
    rear pair's liftoff the front pair (so it may take over with the front pair about to land,
    the trot may not)."""
    model = check_model(SCENES)
    feet = {"fl": "toe_fl", "fr": "toe_fr", "rl": "toe_rl", "rr": "toe_rr"}
    for name, left, lands in (
        ("trot", {"fl", "rr"}, {"fr", "rl"}),
        ("trot", {"fr", "rl"}, {"fl", "rr"}),
        ("gallop", {"rl", "rr"}, {"fl", "fr"}),
    ):
        ctl = model.controller(name)
        pairs = cycle(model, ctl)
        (k,) = [
            k
            for k, p in enumerate(pairs)
            if ctl.state_names[p.state] == "FLIGHT"
            and p.facts[0].feet == frozenset(feet[f] for f in left)
        ]
        assert lands_on(pairs, k) == frozenset(feet[f] for f in lands), name


def _switched(
    session: RunSession, tmp_path: Path, start: str, speeds: list[str], switch: str, time: float
) -> tuple[dict, float]:
    """A run of ``start`` switched once (C backend): the new controller's segment from
    run.json, and its speed from 3 s after it took over to the end."""
    run = session.run(
        start, speeds, options=RunOptions(duration=time), switches=[switch], backend="c"
    )
    assert run.result.status == "ok", run.result.message
    info = json.loads((run.write(tmp_path / "out") / "run.json").read_text())
    (seg,) = info["segments"][1:]
    tr = run.result.trajectory
    later = tr.t >= seg["from"] + 3.0
    t, x = tr.t[later], tr.com[later][:, 0]
    return seg, float((x[-1] - x[0]) / (t[-1] - t[0]))


def test_the_gallop_takes_over_from_the_bound_in_a_flight(
    session: RunSession, tmp_path: Path
) -> None:
    """The bound at 2.5 m/s from standing, switched to the gallop at 3 m/s at 3 s (the scene
    switches at 12 s, after the trot; this keeps the test short): the gallop waits for a
    liftoff into a flight (3.094 s), does not fall, and runs within 5% of 3 m/s from 3 s
    after it took over (3.057 m/s measured)."""
    seg, speed = _switched(
        session, tmp_path, "bound", ["speed=2.5m/s", "speed=3m/s@3s"], "3s=gallop", 9.0
    )
    assert seg["controller"] == "gallop" and seg["state"] == "FLIGHT" and seg["from"] > 3.0
    assert abs(speed - 3.0) < 0.15, speed


def test_the_trot_takes_over_from_the_gallop_in_its_long_flight(
    session: RunSession, tmp_path: Path
) -> None:
    """The gallop at 3 m/s from standing, switched to the trot at 1.5 m/s at 4.6 s (the scene
    switches at 18 s; this keeps the test short). The gallop's rear pair leaves at 4.876 s
    with its front feet 0 and 12 ms from the ground: the trot taking over there (as it did)
    fell at 5.24 s. It now waits for a flight whose feet it does not land on are 0.12 s of
    free fall from the ground at least (the front pair's liftoff at 4.950 s), does not fall,
    and runs within 5% of 1.5 m/s from 3 s after it took over (1.529 m/s measured)."""
    seg, speed = _switched(
        session, tmp_path, "gallop", ["speed=3m/s", "speed=1.5m/s@4.6s"], "4.6s=trot", 8.6
    )
    assert seg["controller"] == "trot" and seg["state"] == "FLIGHT", seg
    assert seg["from"] > 4.9, seg["from"]
    assert abs(speed - 1.5) < 0.075, speed
