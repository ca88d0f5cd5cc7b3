"""An actuator setting the controller writes itself, given with --set, --grid or set=: noted
(an outside user's sweep of the hopper's hip servo gains gave six identical rows, unsaid)."""

from __future__ import annotations

import types
import warnings
from pathlib import Path

import pytest

import legdsl
from legdsl.cli import main
from legdsl.lang.errors import UsageError
from legdsl.sim.machine import overwritten

ROOT = Path(__file__).resolve().parents[2]
HOPPER = ROOT / "creatures" / "hopper.leg"

pytestmark = pytest.mark.usefixtures("hopper_modules")


def test_a_setting_written_from_the_first_tick_or_later_is_told_which() -> None:
    machine = types.SimpleNamespace(
        STATE_NAMES=("FLIGHT", "STANCE", "PUSH"), START=0,
        SETTINGS={(0, 0): (("servo", "kp"),), (0, 1): (("servo", "kp"), ("spring", "rest")),
                  (0, 2): (("servo", "kp"), ("spring", "rest"))},
        PLACES={(0, 1): (("leg", ("x",), ("servo",)),)},
    )  # fmt: skip
    assert overwritten("servo.kv", "c", machine) is None
    said = overwritten("servo.kp", "c", machine)
    assert said is not None and "sets servo.kp itself in every state, from its first tick" in said
    said = overwritten("spring.rest", "c", machine)
    assert said == ("controller 'c' sets spring.rest itself in states STANCE, PUSH: a value "
                    "given holds only until the run first enters one")  # fmt: skip
    said = overwritten("servo.setpoint", "c", machine)  # by a place
    assert said is not None and "in state STANCE:" in said


def test_a_sweep_of_a_gain_the_controller_sets_is_noted(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    argv = ["sweep", str(HOPPER), "--controller", "hop", "--grid", "hip_servo.kp=0,150",
            "--grid", "leg_spring.k=3000,3500", "--time", "0.2", "--from", "0", "--jobs", "1",
            "--out", str(tmp_path / "out"), "--generated", str(tmp_path / "generated")]  # fmt: skip
    assert main(argv) == 0
    err = capsys.readouterr().err
    assert ("legdsl: note: --grid hip_servo.kp: controller 'hop' sets hip_servo.kp itself in "
            "every state, from its first tick, so a value given has no effect; give one to the "
            "parameter it is set from, swing_kp") in err  # fmt: skip
    # (it named none: 'give one to the parameter it sets it from')
    assert "leg_spring.k:" not in err  # the controller leaves the spring's stiffness alone


def test_legdsl_run_and_the_api_note_it_too(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    argv = ["run", str(HOPPER), "--controller", "hop", "--set", "hip_servo.kv=5N*m*s/rad",
            "--time", "0.05", "-o", str(tmp_path / "run"),
            "--generated", str(tmp_path / "generated")]  # fmt: skip
    assert main(argv) == 0
    assert ("legdsl: note: --set hip_servo.kv=5N*m*s/rad: controller 'hop' sets hip_servo.kv "
            "itself in every state") in capsys.readouterr().err  # fmt: skip
    hopper = legdsl.load(HOPPER, generated=tmp_path / "generated")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        hopper.run(controller="hop", set={"hip_servo.kv": "5 N*m*s/rad"}, time=0.05)
    assert any("sets hip_servo.kv itself in every state" in str(w.message) for w in caught)


def test_an_unknown_controller_is_told_not_looked_into(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The note looked up the controller before the run had checked its name: a misspelt
    --controller (seed 21016 of the random API calls) was an internal error (StopIteration)."""
    argv = ["run", str(HOPPER), "--controller", "hopx", "--set", "hip_servo.kp=10N*m/rad",
            "--time", "0.1", "--out", str(tmp_path / "r"),
            "--generated", str(tmp_path / "generated")]  # fmt: skip
    assert main(argv) == 2
    assert "has no such controller; did you mean 'hop'?" in capsys.readouterr().err
    hopper = legdsl.load(HOPPER, generated=tmp_path / "generated")
    with pytest.raises(UsageError, match="has no such controller"):
        hopper.run(controller="hopx", time=0.1)


def test_run_copies_notes_a_varied_setting_the_controller_writes(tmp_path: Path) -> None:
    """vary= of hip_servo.kp (hop sets it from its first tick) gave identical copies, unsaid,
    where set= of it was noted; the note comes at the caller's line, as set='s does."""
    hopper = legdsl.load(HOPPER, generated=tmp_path / "generated")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        hopper.run_copies(2, "hop", vary={"hip_servo.kp": ([60, 300], "N*m/rad")}, time=0.05)
    said = [str(w.message) for w in caught if "hip_servo.kp" in str(w.message)]
    assert said == [
        "vary hip_servo.kp: controller 'hop' sets hip_servo.kp itself in every state, from its "
        "first tick, so a value given has no effect; give one to the parameter it is set "
        "from, swing_kp"
    ]
    assert all(w.filename == __file__ for w in caught if "hip_servo.kp" in str(w.message))
    with warnings.catch_warnings(record=True) as caught:  # a setting hop leaves alone: unsaid
        warnings.simplefilter("always")
        hopper.run_copies(2, "hop", vary={"leg_spring.k": ([3000, 3500], "N/m")}, time=0.05)
    assert not [w for w in caught if "leg_spring.k" in str(w.message)]


def test_the_parameters_a_setting_is_set_from_are_named() -> None:
    """Through the records it reads too: the hopper's leg_spring.rest is a record's
    (thrust_stroke), made from its stroke."""
    from legdsl.check.source import check_model
    from legdsl.sim.machine import set_from

    model = check_model(str(HOPPER), None)
    assert set_from(model, "hop", "hip_servo.kp") == ["swing_kp"]
    assert "stroke" in set_from(model, "hop", "leg_spring.rest")
    assert set_from(model, "hop", "hip_motor.force") == ["kp", "kv"]
