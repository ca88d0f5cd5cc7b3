"""A controller taking over while the feet of one of its roles disagree (``legdsl.sim.handover``):
a role bound to several legs (the trot's diagonals, the bound's pairs, the hexapod's tripods)
counts as down while any of its feet is, so a state whose facts hold may have that role only
partly down, at an edge of its stance the contacts cannot tell (landing or leaving). A
handover at a liftoff waits for the role's feet to agree."""

from __future__ import annotations

import json
import math
from pathlib import Path

from conftest import CREATURES, ROOT

from legdsl.check.source import check_model
from legdsl.pipeline.session import RunSession
from legdsl.sim.handover import Clock, Fact, Pair, cycle, on_liftoff, take_over
from legdsl.sim.run_loop import RunOptions

QUADRUPED = CREATURES / "quadruped.leg"
HEXAPOD = ROOT / "tests" / "good" / "outside" / "hexapod.leg"


def _active(ctl, pair: Pair) -> tuple[str, ...]:
    return dict(ctl.bindings[pair.binding])["active"]


def test_a_trot_waits_for_a_diagonal_to_lift_off_whole() -> None:
    """The contacts of the quadruped's gallop at 2.744 s (``--switch 2.2s=trot``): toe_fl has
    just lifted, toe_fr is down, the rear pair is up. The trot's diagonal (fr, rl) is down
    through toe_fr alone, which lifts 7.6 ms later; the trot took over at once, in LOADING
    of (fr, rl), and lost a step. It waits for toe_fr, then starts in its FLIGHT."""
    model = check_model(QUADRUPED)
    trot = model.controller("trot")
    pairs = cycle(model, trot)
    t = 2.744
    feet = {
        "toe_fl": Clock(False, 2.6828, t), "toe_fr": Clock(True, 2.6928, 2.4796),
        "toe_rl": Clock(False, 2.5712, 2.6892), "toe_rr": Clock(False, 2.5652, 2.6756),
    }  # fmt: skip
    stance = take_over(pairs, feet, lambda p: False)
    assert trot.state_names[stance.state] == "LOADING" and _active(trot, stance) == ("fr", "rl")
    assert stance.facts[0] == Fact(frozenset({"toe_fr", "toe_rl"}), True)  # toe_fr alone
    assert not on_liftoff(pairs, feet, t)
    later = 2.752
    feet["toe_fr"] = Clock(False, 2.6928, later)
    assert on_liftoff(pairs, feet, later)
    chosen = take_over(pairs, feet, lambda p: False)
    assert trot.state_names[chosen.state] == "FLIGHT" and _active(trot, chosen) == ("fl", "rr")


def test_a_bound_waits_for_a_pair_landing_a_foot_at_a_time() -> None:
    """The other edge: the gallop's front pair landing one foot at a time (toe_fl down, toe_fr
    about to land) as toe_rl lifts; the bound's front stance holds through toe_fl alone."""
    model = check_model(QUADRUPED)
    bound = model.controller("bound")
    pairs = cycle(model, bound)
    t = 2.69
    feet = {
        "toe_fl": Clock(True, 2.6828, 2.4616), "toe_fr": Clock(False, 2.3784, 2.4796),
        "toe_rl": Clock(False, 2.5712, t), "toe_rr": Clock(False, 2.5652, 2.6756),
    }  # fmt: skip
    assert not on_liftoff(pairs, feet, t)
    feet["toe_fr"] = Clock(True, 2.6952, 2.4796)  # both front feet down: its front stance
    assert on_liftoff(pairs, feet, t)
    chosen = take_over(pairs, feet, lambda p: False)
    assert bound.state_names[chosen.state] == "LOADING" and _active(bound, chosen) == ("fl", "fr")


def test_a_tripod_waits_for_all_three_feet() -> None:
    model = check_model(HEXAPOD)
    tripod = model.controller("tripod")
    pairs = cycle(model, tripod)
    t = 1.5
    up, down = Clock(False, 1.0, 1.2), Clock(True, 1.3, 1.1)
    feet = {"toe_fl": Clock(False, 1.1, t), "toe_mr": up, "toe_rl": up,  # (fl, mr, rl) lifted
            "toe_fr": up, "toe_ml": down, "toe_rr": up}  # fmt: skip
    assert not on_liftoff(pairs, feet, t)  # (fr, ml, rr) down through toe_ml alone
    feet |= {"toe_fr": down, "toe_rr": down}
    assert on_liftoff(pairs, feet, t)
    chosen = take_over(pairs, feet, lambda p: False)
    assert _active(tripod, chosen) == ("fr", "ml", "rr")


def test_split_is_about_touchdown_facts_over_several_feet() -> None:
    """The rule reads facts and clocks only, planar or not: a liftoff fact that holds has every
    foot up, and one foot is never split."""
    from legdsl.sim.handover import split

    a, b = Clock(True, 1.0, math.nan), Clock(False, 0.5, 0.8)
    feet = {"a": a, "b": b}
    assert split(Fact(frozenset({"a", "b"}), True), feet)
    assert not split(Fact(frozenset({"a", "b"}), False), feet)
    assert not split(Fact(frozenset({"a"}), True), feet)
    assert not split(Fact(frozenset({"a", "b"}), True), {"a": a, "b": a})


def test_the_gallop_hands_the_trot_a_whole_flight(tmp_path: Path) -> None:
    """``--switch 2.2s=trot`` from the gallop: the trot takes over when no role of the state it
    starts in is partly down (before: at 2.744 s in LOADING of (fr, rl), toe_fr still down)."""
    session = RunSession.from_file(QUADRUPED)
    run = session.run(
        "gallop",
        ["speed=4m/s", "speed=2m/s@2.2s"],
        options=RunOptions(duration=2.9),
        switches=["2.2s=trot"],
    )
    info = json.loads((run.write(tmp_path) / "run.json").read_text())
    (seg,) = info["segments"][1:]
    down: set[str] = set()
    for e in sorted(
        (e for e in info["events"] if e["kind"] in ("touchdown", "liftoff")), key=lambda e: e["t"]
    ):
        if e["t"] <= seg["from"] + 1e-9:
            (down.add if e["kind"] == "touchdown" else down.discard)(e["contact"])
    trot = session.model.controller("trot")
    roles = {r: tuple(v) for r, v in seg["roles"].items()}
    (start,) = [p for p in cycle(session.model, trot)
                if trot.state_names[p.state] == seg["state"] and dict(trot.bindings[p.binding]) == roles]  # fmt: skip
    for fact in start.facts:  # every foot of each fact as the fact says
        assert all((c in down) == fact.down for c in fact.feet), (seg, fact, down)
    assert seg["from"] > 2.744 and seg["state"] == "FLIGHT"
