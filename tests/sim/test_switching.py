"""Changing controllers during a run (``--switch``): where the new controller starts
(``legdsl.sim.handover``), what it carries over, and a short biped run -> gallop -> run."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from conftest import CREATURES

from legdsl.check.source import check_model
from legdsl.cli import main
from legdsl.lang.errors import LegError, UsageError
from legdsl.pipeline.session import RunSession
from legdsl.sim.handover import Clock, Fact, cycle, on_liftoff, take_over
from legdsl.sim.run_loop import RunOptions
from legdsl.sim.switching import FLIGHT_WAIT, HANDOVER_WAIT

BIPED = CREATURES / "biped.leg"
NAN = math.nan


@pytest.fixture(scope="module")
def biped():
    return check_model(BIPED)


def _facts(pairs, state: str, binding: int, names) -> tuple[Fact, ...]:
    return next(p.facts for p in pairs if names[p.state] == state and p.binding == binding)


def test_each_state_knows_which_feet_are_down(biped) -> None:
    run = biped.controller("run")
    pairs = cycle(biped, run)
    names = run.state_names
    assert [(names[p.state], p.binding) for p in pairs][:6] == [
        ("FLIGHT", 0), ("LOADING", 0), ("COMPRESSION", 0), ("THRUST", 0), ("UNLOADING", 0),
        ("FLIGHT", 1),
    ]  # fmt: skip
    left, right = frozenset({"toe_l"}), frozenset({"toe_r"})
    # in FLIGHT under binding 0 (active = left) the right leg has just lifted off, the left before
    assert _facts(pairs, "FLIGHT", 0, names) == (Fact(right, False), Fact(left, False))
    assert _facts(pairs, "THRUST", 0, names) == (Fact(left, True), Fact(right, False))
    gallop = biped.controller("gallop")
    gpairs = cycle(biped, gallop)
    assert len(gpairs) == 4  # one binding: first = left, second = right
    assert _facts(gpairs, "DOUBLE", 0, gallop.state_names) == (Fact(right, True), Fact(left, True))


def _feet(left: tuple[bool, float, float], right: tuple[bool, float, float]) -> dict[str, Clock]:
    return {"toe_l": Clock(*left), "toe_r": Clock(*right)}


def test_the_state_that_matches_the_feet_down(biped) -> None:
    run = biped.controller("run")
    pairs = cycle(biped, run)
    names = run.state_names

    def start(feet, holding=()):
        p = take_over(pairs, feet, lambda p: names[p.state] in holding)
        return names[p.state], p.binding

    # both up, the right lifted last: binding 0, whose active (left) leg lands next
    assert start(_feet((False, 1.0, 1.2), (False, 1.3, 1.5))) == ("FLIGHT", 0)
    assert start(_feet((False, 1.3, 1.5), (False, 1.0, 1.2))) == ("FLIGHT", 1)
    # the right down: its stance, in the last state whose event holds (mid-thrust: THRUST)
    right_down = _feet((False, 1.0, 1.2), (True, 1.4, 1.2))
    assert start(right_down, ("LOADING", "COMPRESSION", "THRUST")) == ("THRUST", 1)
    assert start(right_down) == ("LOADING", 1)  # no event holds: the stretch's first state
    # both down (run never has both down): the leg that landed last is the active one
    assert start(_feet((True, 1.0, NAN), (True, 1.1, NAN))) == ("LOADING", 1)
    gallop = biped.controller("gallop")
    g = cycle(biped, gallop)
    only_right = _feet((False, 1.0, 1.2), (True, 1.1, NAN))
    assert gallop.state_names[take_over(g, only_right, lambda p: False).state] == "SINGLE_2"


def test_a_controller_takes_over_as_a_foot_lifts_off(biped) -> None:
    gallop, run = cycle(biped, biped.controller("gallop")), cycle(biped, biped.controller("run"))
    t = 2.0
    # both up, either foot just lifted: the gallop's FLIGHT (both up) begins
    assert on_liftoff(gallop, _feet((False, 1.5, 1.7), (False, 1.8, t)), t)
    assert on_liftoff(gallop, _feet((False, 1.8, t), (False, 1.5, 1.7)), t)
    # the right just lifted with the left down: SINGLE_1 (left down, right up), its swing
    assert on_liftoff(gallop, _feet((True, 1.95, 1.7), (False, 1.8, t)), t)
    # no foot lifted off at this tick: not yet, whatever matches
    assert not on_liftoff(gallop, _feet((False, 1.5, 1.7), (False, 1.8, 1.9)), t)
    assert not on_liftoff(run, _feet((True, t, 1.7), (False, 1.5, 1.8)), t)
    # the run: the left lifted off with the right down is the right's stance, the left's swing
    assert on_liftoff(run, _feet((False, 1.8, t), (True, 1.9, 1.7)), t)
    # both down after a liftoff (the other landed in the same tick): its stance knows the
    # lifted leg is up, which no longer holds
    assert not on_liftoff(run, _feet((True, 1.9, t), (True, t, 1.7)), t)


@pytest.fixture(scope="module")
def session() -> RunSession:
    return RunSession.from_file(BIPED)


SWITCHED = (["speed=1.5m/s", "speed=1.2m/s@1.5s"], ["1.5s=gallop", "3s=run"])


def _switched(session: RunSession, duration: float = 4.0):
    settings, switches = SWITCHED
    return session.run("run", settings, options=RunOptions(duration=duration), switches=switches)


def test_a_switched_run_changes_controller_in_a_consistent_state(session, tmp_path: Path) -> None:
    run = _switched(session)
    assert run.status == "ok"
    out = run.write(tmp_path)
    info = json.loads((out / "run.json").read_text())
    assert info["switches"] == [{"t": 1.5, "controller": "gallop"}, {"t": 3.0, "controller": "run"}]
    segs = info["segments"]
    assert [s["controller"] for s in segs] == ["run", "gallop", "run"]
    # each takes over at the first liftoff after its switch's time at which one of its states
    # matches the feet (the facts are checked below)
    assert [s.get("asked") for s in segs[1:]] == [1.5, 3.0]
    for k, seg in enumerate(segs[1:], 1):
        assert seg["asked"] < seg["from"] < seg["asked"] + HANDOVER_WAIT
        assert segs[k - 1]["to"] == seg["from"]
        tick = info["options"]["control_dt"]
        lifted = [e for e in info["events"]
                  if e["kind"] == "liftoff" and seg["from"] - tick < e["t"] <= seg["from"]]  # fmt: skip
        assert lifted, seg  # a foot left the ground since the last control tick
    assert segs[1]["inputs"]["speed"] == 1.2  # the command given with the switch applies
    assert segs[2]["inputs"]["speed"] == 1.2  # and is kept by the next controller
    tr = run.result.trajectory
    k = int(np.searchsorted(tr.t, 1.52))  # the command went with the switch: run kept 1.5 m/s
    assert tr.speed_command[k] == pytest.approx(1.5 if tr.t[k] < segs[1]["from"] else 1.2)
    assert tr.state_names[0] == "run.FLIGHT" and "gallop.DOUBLE" in tr.state_names
    for seg in segs[1:]:
        k = int(np.searchsorted(tr.t, seg["from"] - 1e-9))
        state = tr.state_names[tr.state[k]]
        assert state.split(".")[0] == seg["controller"]
        down = {c for c, on in zip(tr.contact_names, tr.contact[k], strict=True) if on}
        # the state it starts in has the feet down that are down
        pairs = cycle(session.model, session.model.controller(seg["controller"]))
        names = session.model.controller(seg["controller"]).state_names
        entered = [p for p in pairs if names[p.state] == seg["state"] and
                   dict(session.model.controller(seg["controller"]).bindings[p.binding]) ==
                   {r: tuple(v) for r, v in seg["roles"].items()}]  # fmt: skip
        assert entered, seg
        for fact in entered[0].facts:
            assert bool(fact.feet & down) == fact.down, (seg, fact, down)
    # records carried where the names match, with the values the old controller had
    first = run.machine.finished[0][1]
    old = dict(zip(first.module.RECORDS, first.records, strict=True))
    carried = segs[1]["records_carried"]
    assert set(carried) == {"step_speed", "speed_trim", "lifted", "lifted_x", "lifted_y",
                            "predicted_apex"}  # fmt: skip
    assert carried == pytest.approx({k: old[k] for k in carried})
    assert carried["lifted"] > 0.5  # a time in the run, not a fresh record's 0
    switches = [e for e in info["events"] if e["kind"] == "switch"]
    assert [e["controller"] for e in switches] == ["gallop", "run"]


def _down_at(events: list[dict], t: float) -> set[str]:
    """The feet down at time ``t``, from a run's touchdown and liftoff events."""
    down: set[str] = set()
    for e in sorted(
        (e for e in events if e["kind"] in ("touchdown", "liftoff")), key=lambda e: e["t"]
    ):
        if e["t"] > t + 1e-9:
            break
        (down.add if e["kind"] == "touchdown" else down.discard)(e["contact"])
    return down


def test_a_switch_waits_for_a_flight_with_the_mass_rising(session) -> None:
    """Within ``FLIGHT_WAIT`` of its time a switch takes over only as a flight begins, every foot
    up and the centre of mass rising (the new controller places its own feet first); the
    biped's run and gallop both have such flights."""
    run = _switched(session)
    info, tr = run.info(), run.result.trajectory
    for seg in info["segments"][1:]:
        assert seg["from"] < seg["asked"] + FLIGHT_WAIT, seg
        assert _down_at(info["events"], seg["from"]) == set(), seg
        k = int(np.searchsorted(tr.t, seg["from"] - 1e-9))
        assert tr.com_vel[k, 2] > 0, seg  # the sample at the takeover: rising


def test_a_switched_run_is_deterministic(session) -> None:
    a = _switched(session, 2.5).result.trajectory
    b = _switched(session, 2.5).result.trajectory
    assert np.array_equal(a.q, b.q) and np.array_equal(a.state, b.state)


def test_switch_mistakes_are_user_errors(session, capsys) -> None:
    with pytest.raises(UsageError, match=r"'biped' has no controller 'trot' \(it has run, gallop,"):
        session.run("run", switches=["2s=trot"])
    with pytest.raises(UsageError, match="no controller 'galop'; did you mean 'gallop'"):
        session.run("run", switches=["2s=galop"])
    with pytest.raises(UsageError, match="give its unit"):
        session.run("run", switches=["2=gallop"])
    with pytest.raises(UsageError, match="in seconds"):
        session.run("run", switches=["2m=gallop"])
    with pytest.raises(UsageError, match="--controller"):
        session.run(None, switches=["2s=gallop"])
    with pytest.raises(UsageError, match="after the start"):
        session.run("run", switches=["0s=gallop"])
    code = main(["run", str(BIPED), "--controller", "run", "--switch", "1s=trot", "--time", "1"])
    assert code == 2
    assert "no controller 'trot'" in capsys.readouterr().err


def test_a_change_after_the_end_of_the_run_is_noted(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """An input change timed after --time happened never, silently."""
    from legdsl.pipeline.scenes import too_late
    from legdsl.sim.run_loop import RunOptions

    notes = too_late(["speed=2m/s@5s", "speed=1m/s@500ms", "k=2"], RunOptions(duration=2.0))
    assert notes == [
        "--set speed=2m/s@5s comes after the run's end (2 s) and has no effect; give a longer "
        "--time to see it",
    ]  # a switch that never took over is told after the run (tests/cli/test_cli_switch_late.py)
    # after the last tick (1.998 s at the 2 ms control interval) nothing reads it either
    late = too_late(["speed=2m/s@1.999s", "speed=2m/s@1.998s"], RunOptions(duration=2.0))
    assert late == [
        "--set speed=2m/s@1.999s comes after the controller's last tick (1.998 s of the 2 s "
        "run) and has no effect; give a longer --time to see it"
    ]
    argv = ["run", str(CREATURES / "hopper.leg"), "--controller", "hop", "--time", "0.1",
            "--set", "speed=1m/s@0.2s", "--out", str(tmp_path / "r")]  # fmt: skip
    assert main(argv) == 0
    assert (
        "legdsl: note: --set speed=1m/s@0.2s comes after the run's end" in capsys.readouterr().err
    )


# Small tables of their own (the shipped file has controllers of these gaits too).
TROT = """
controller pairs_trot {
  roles active = (fl, rr), idle = (fr, rl)
  table {
    state FLIGHT on liftoff(active): swap active idle; active.spring.rest = 0 m
    state STANCE on touchdown(active): active.spring.rest = 1 cm
  }
}
controller pairs_bound {
  roles front = (fl, fr), rear = (rl, rr)
  table {
    state GATHERED on liftoff(front): rear.spring.rest = 0 m
    state REAR on touchdown(rear): rear.spring.rest = 1 cm
    state EXTENDED on liftoff(rear): front.spring.rest = 0 m
    state FRONT on touchdown(front): front.spring.rest = 1 cm
  }
}
"""


def test_a_role_bound_to_a_group_is_down_when_any_member_is(tmp_path: Path) -> None:
    path = tmp_path / "quadruped.leg"
    path.write_text((CREATURES / "quadruped.leg").read_text() + TROT)
    model = check_model(path)
    trot = model.controller("pairs_trot")
    pairs = cycle(model, trot)
    diagonal = frozenset({"toe_fl", "toe_rr"})
    stance = next(p for p in pairs if trot.state_names[p.state] == "STANCE" and p.binding == 0)
    assert stance.facts[0] == Fact(diagonal, True)  # touchdown(active): any of fl, rr down
    up = math.nan
    feet = {  # only rr of the fl+rr pair is down (it landed first), the other pair is up
        "toe_fl": Clock(False, 1.0, 1.2), "toe_rr": Clock(True, 1.5, 1.2),
        "toe_fr": Clock(False, 1.3, 1.45), "toe_rl": Clock(False, 1.3, 1.45),
    }  # fmt: skip
    chosen = take_over(pairs, feet, lambda p: False)
    assert trot.state_names[chosen.state] == "STANCE"
    assert dict(trot.bindings[chosen.binding])["active"] == ("fl", "rr")
    # the bound: the rear pair down alone is its rear stance, whichever member
    bound = model.controller("pairs_bound")
    rear_down = dict(feet, toe_rr=Clock(False, 1.0, 1.2), toe_rl=Clock(True, 1.5, up))
    chosen = take_over(cycle(model, bound), rear_down, lambda p: False)
    assert bound.state_names[chosen.state] == "REAR"
    all_up = {k: Clock(False, 1.0, t) for k, t in
              (("toe_fl", 1.2), ("toe_fr", 1.2), ("toe_rl", 1.6), ("toe_rr", 1.6))}  # fmt: skip
    chosen = take_over(cycle(model, bound), all_up, lambda p: False)
    assert bound.state_names[chosen.state] == "EXTENDED"  # the rear pair lifted off last


def test_own_records_start_at_zero_when_a_controller_takes_over(tmp_path: Path) -> None:
    path = tmp_path / "biped.leg"
    text = BIPED.read_text()
    gallop = "controller gallop {\n"
    assert gallop in text
    path.write_text(text.replace(gallop, gallop + "  own speed_trim, predicted_apex\n"))
    model = check_model(path)
    assert model.controller("gallop").own == ("speed_trim", "predicted_apex")
    assert model.controller("run").own == ()
    settings, switches = SWITCHED
    run = RunSession.from_file(path).run(
        "run", settings, options=RunOptions(duration=2.5), switches=switches
    )
    (seg,) = run.machine.segment_info(2.5)[1:]
    assert set(seg["records_carried"]) == {"step_speed", "lifted", "lifted_x", "lifted_y"}
    # the gallop's speed_trim started at 0 (not at the run's): each FLIGHT entry since
    # integrated at most k_trim * trim_band into it
    old = dict(zip(run.machine.first.module.RECORDS, run.machine.first.records, strict=True))
    new = dict(zip(run.machine.current.module.RECORDS, run.machine.current.records, strict=True))
    steps = [e for e in run.machine.current.events if e["state"] == "FLIGHT"]
    most = len(steps) * seg["params"]["k_trim"] * seg["params"]["trim_band"]
    assert abs(new["speed_trim"]) <= most + 1e-12 and old["speed_trim"] != 0


def test_own_names_a_record_of_the_controller(tmp_path: Path) -> None:
    path = tmp_path / "biped.leg"
    gallop = "controller gallop {\n"
    path.write_text(BIPED.read_text().replace(gallop, gallop + "  own speed_trm\n"))
    with pytest.raises(LegError) as info:
        check_model(path)
    (d,) = info.value.diagnostics
    assert d.span.line == BIPED.read_text().split(gallop)[0].count("\n") + 2
    assert d.message.startswith("'own speed_trm': controller 'gallop' records no 'speed_trm'")
    assert "did you mean 'speed_trim'" in d.message


def test_a_setting_for_one_controller(session) -> None:
    """``--set CONTROLLER.NAME=V`` gives that controller alone a parameter (over a plain
    ``--set NAME=V``) or an input default (under a command); mistakes point at the word."""
    settings = ["k_speed=70ms", "gallop.k_speed=50ms", "gallop.height=0.9m", "run.height=0.8m"]
    run = session.run("run", settings, options=RunOptions(duration=1.2), switches=["0.5s=gallop"])
    first, second = run.info()["segments"]
    assert first["params"]["k_speed"] == pytest.approx(0.07)
    assert second["params"]["k_speed"] == pytest.approx(0.05)
    assert (first["inputs"]["height"], second["inputs"]["height"]) == pytest.approx((0.8, 0.9))
    assert run.info()["settings"]["by_controller"]["gallop"] == pytest.approx(
        {"k_speed": 0.05, "height": 0.9}
    )
    commanded = session.run(
        "run", ["gallop.height=0.9m", "height=0.8m"], options=RunOptions(duration=1.2),
        switches=["0.5s=gallop"],
    )  # fmt: skip
    assert commanded.info()["segments"][1]["inputs"]["height"] == pytest.approx(0.8)
    alone = session.run("run", ["run.k_speed=60ms"], options=RunOptions(duration=0.1))
    assert alone.info()["params"]["k_speed"] == pytest.approx(0.06)
    for text, words, caret in (
        ("galop.k_speed=50ms", "no controller or actuator 'galop'; did you mean 'gallop'", "^^^^^"),
        ("gallop.k_sped=50ms", "controller gallop has no input or parameter 'k_sped'", "^^^^^^"),
        ("gallop_human.k_speed=50ms", "controller 'gallop_human' does not run here", "^" * 12),
        ("gallop.height=1m@1s", "gallop.height is controller gallop's own value", "^^^"),
        ("gallop.k_speed=5cm", "gallop.k_speed is a time (s), but 5cm is a length", ""),
    ):
        with pytest.raises(UsageError) as err:
            session.run("run", [text], options=RunOptions(duration=0.1), switches=["0.5s=gallop"])
        assert words in str(err.value) and caret in str(err.value), str(err.value)
