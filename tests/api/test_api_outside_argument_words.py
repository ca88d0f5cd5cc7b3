"""An outside user's report on the API's words: refusals and notes told a Python caller the
command line's flags (``--dt 0.4s is longer than the run (--time 0.3s)``, ``--integrator``,
``--switch 1s=gallop``, ``give a longer --time``), a scene refusing controller= gave no way
out, ``run_many`` refused a wrong run only after the runs before it had run (and named no
run), ``fall_tilt=None`` and ``integrator=None`` were refused where ``dt=None`` meant the
default, ``metrics().value(3)`` was difflib's TypeError and ``path=`` refused a
``pathlib.Path``."""

from __future__ import annotations

import re
import warnings
from pathlib import Path
from typing import Any

import pytest
from conftest import CREATURES

import legdsl
from legdsl.api.notes import LegdslWarning
from legdsl.lang.errors import UsageError


@pytest.fixture(scope="module")
def hopper(generated: Path) -> legdsl.api.Creature:
    return legdsl.load(CREATURES / "hopper.leg", generated=generated)


@pytest.fixture(scope="module")
def biped(generated: Path) -> legdsl.api.Creature:
    return legdsl.load(CREATURES / "biped.leg", generated=generated)


WORDS = [
    (
        {"dt": "0.4"},
        "run(): dt=0.4 is longer than the run (time=0.3); give time=0.4 or more, "
        "or a dt=0.3 or less (seconds)",
    ),
    (
        {"record_rate": "0.5 Hz"},
        "run(): record_rate=0.5 records only the start of a 0.3 s run; give record_rate=3.33 "
        "or more (Hz), or 0 to record every step",
    ),
    ({"fall_tilt": "3.5 rad"}, "run(): fall_tilt=3.5 (radians: 200.5 deg) is past upside down"),
    ({"time": 0}, "run(): time=0.0: must be a finite number more than zero"),
    ({"integrator": "RK4"}, "run(): integrator='RK4': use integrator='euler' or integrator='rk4'"),
    ({"drop": -1.0}, "run(): drop=-1.0: must be a finite number, zero or more"),
    ({"control_dt": "0.1 ms"}, "run(): control_dt=0.0001 is shorter than the integration step"),
]


@pytest.mark.parametrize(("given", "said"), WORDS, ids=[str(g) for g, _ in WORDS])
def test_an_option_is_refused_in_the_arguments_words(
    hopper: legdsl.api.Creature, given: dict[str, Any], said: str
) -> None:
    with pytest.raises(UsageError) as refused:
        hopper.run(**{"controller": "hop", "time": 0.3, **given})
    assert str(refused.value).startswith(said) and "--" not in str(refused.value)


def test_a_switch_at_the_start_is_refused_in_the_arguments_words(
    biped: legdsl.api.Creature,
) -> None:
    with pytest.raises(UsageError) as refused:
        biped.run(controller="run", time=0.3, switch={0: "gallop"})
    assert str(refused.value) == (
        "run(): switch={0: 'gallop'}: a switch comes after the start; to start with gallop, "
        "give controller='gallop', else give a time after 0, e.g. switch={'1s': 'gallop'}"
    )


def test_a_change_after_the_end_is_noted_in_the_arguments_words(
    hopper: legdsl.api.Creature,
) -> None:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        hopper.run(controller="hop", time=0.3, set={"speed@5s": "1 m/s"})
    told = [str(w.message) for w in caught if issubclass(w.category, LegdslWarning)]
    assert told == [
        "set={'speed@5s': '1m/s'} comes after the run's end (0.3 s) and has no effect; "
        "give a longer time= to see it"
    ]


def test_a_scene_refusing_controller_says_to_leave_it_out(biped: legdsl.api.Creature) -> None:
    with pytest.raises(UsageError, match=re.escape(
        "run(): scene run_gallop_run starts with controller run; leave out controller= "
        "(or give another scene=)"
    )):  # fmt: skip
        biped.run(scene="run_gallop_run", controller="gallop", time=0.3)


BAD_RUNS = [
    ({"set": {"speed": "1 kg"}}, "set['speed'] = '1kg': speed is a velocity (m/s)"),
    ({"tim": 0.3}, "no option 'tim'"),
    ({"time": -1}, "time=-1.0: must be a finite number more than zero"),
]


@pytest.mark.parametrize(("bad", "said"), BAD_RUNS, ids=[str(b) for b, _ in BAD_RUNS])
def test_run_many_checks_every_run_before_any_runs(
    hopper: legdsl.api.Creature, monkeypatch: pytest.MonkeyPatch, bad: dict[str, Any], said: str
) -> None:
    ran: list[int] = []
    session_run = hopper.session.run
    monkeypatch.setattr(hopper.session, "run", lambda **k: ran.append(1) or session_run(**k))
    runs = [{"controller": "hop", "time": 0.1}] * 2 + [{"controller": "hop", "time": 0.1, **bad}]
    with pytest.raises(UsageError) as refused:
        for _ in hopper.run_many(runs, threads=1):
            ran.append(1)
    assert ran == [] and str(refused.value).startswith(f"run_many(): runs[2]: {said}")


def test_none_is_the_default_for_every_option(hopper: legdsl.api.Creature) -> None:
    run = hopper.run(controller="hop", time=0.1, fall_tilt=None, integrator=None, dt=None,
                     drop=None, fall_height=None, record_rate=None, control_dt=None)  # fmt: skip
    assert run.status == "ok"
    assert run.info["options"]["integrator"] == "euler"
    assert run.info["options"]["fall_tilt"] == pytest.approx(1.0471975511965976)


def test_a_metric_named_by_a_number_is_refused_saying_what_value_takes(
    hopper: legdsl.api.Creature,
) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        metrics = hopper.run(controller="hop", time=0.3).metrics()
    with pytest.raises(KeyError, match=r"no metric 3: a metric is named by a text, e\.g\. "):
        metrics.value(3)


def test_path_takes_a_pathlib_path(biped: legdsl.api.Creature, tmp_path: Path) -> None:
    waypoints = tmp_path / "wp.csv"
    waypoints.write_text("0,0\n5,0\n5,5\n")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        run = biped.run(controller="run", time=0.05, path=waypoints)
    assert run.status == "ok"
