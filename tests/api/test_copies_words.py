"""``run_copies`` told a Python caller its refusals in the command line's words ('--set
speed=1.0kg: ... write e.g. speed=1.0m/s' for vary={'speed': (v, 'kg')}), as an outside user
found: they are in the words of its set= and vary= now."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import legdsl
from legdsl.api.copies_words import reworded
from legdsl.lang.errors import UsageError

HOPPER = Path(__file__).resolve().parents[2] / "creatures" / "hopper.leg"
pytestmark = pytest.mark.usefixtures("hopper_modules")


@pytest.mark.parametrize(
    ("given", "said"),
    [
        ({"set": {"speed": "1.0kg"}},
         "run_copies(): set['speed'] = '1.0kg': speed is a velocity (m/s), but 1.0kg is a mass "
         "(kg); give e.g. set={'speed': '1.0 m/s'}"),
        ({"vary": {"speed": (np.array([1.0, 2.0]), "kg")}},
         "run_copies(): vary['speed'], the value 1.0kg: speed is a velocity (m/s), but 1.0kg is "
         "a mass (kg); give the values' unit, e.g. vary={'speed': (values, 'm/s')}"),
        ({"vary": {"nosuch": (np.array([1.0, 2.0]), "m/s")}},
         "run_copies(): vary['nosuch']: controller hop has no input or parameter 'nosuch'"),
        ({"set": {"speed@2": "1 m/s"}},
         "run_copies(): set['speed@2'] = '1m/s': the time after '@' is in seconds; give its "
         "unit, e.g. set={'speed@2s': '1m/s'}"),
        ({"dtt": 1}, "run_copies(): no option 'dtt'; the options are dt, "),  # was run()'s
        ({"set": {"speed@": "1 m/s"}},
         "set 'speed@': no time after '@': give e.g. set={'speed@4 s': '1 m/s'} (from 4 s on)"),
        ({"set": {"speed@nan s": "1 m/s"}},
         "set 'speed@nan s': the time after '@', 'nan s', is not a finite number; give e.g. "
         "set={'speed@4 s': '1 m/s'}"),  # it was echoed as 'nans'
    ],
)  # fmt: skip
def test_a_refused_setting_is_told_as_the_argument_given(
    tmp_path: Path, given: dict, said: str
) -> None:
    creature = legdsl.load(str(HOPPER), generated=str(tmp_path / "generated"))
    with pytest.raises(UsageError) as e:
        creature.run_copies(2, "hop", time=0.05, **given)
    assert str(e.value).startswith(said)
    assert "--set" not in str(e.value)


def test_the_step_advice_names_the_arguments() -> None:
    told = reworded("actuator 'leg_spring' is too stiff ...: use k below 7e6 N/m, or a step "
                    "below 0.03 ms (--dt, or dt in the simulation block), or a 'max' for it in "
                    "the .leg file (--set cannot give one)", {})  # fmt: skip
    assert "(dt=, or dt in" in told and "(set= cannot give one)" in told
    assert reworded("something else", {}) == "something else"
