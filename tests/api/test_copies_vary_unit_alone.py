"""``run_copies``' ``vary=`` glued its unit onto each value as text: ``([1.0, 2.0], '1 m/s')``
ran speeds 1.01 and 2.02 m/s while the copies' info recorded 1.01 and 2.01, and 'e-1 m/s' ran
a tenth of the values, as an outside user found. The unit is read as a unit alone now, a
number in it refused; an unknown unit is told in vary='s words (it was
``set["'speed"] = "3.6km/h'"``), and a value without its unit is shown the parameter's own."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import legdsl
from legdsl.lang.errors import UsageError

HOPPER = Path(__file__).resolve().parents[2] / "creatures" / "hopper.leg"
pytestmark = pytest.mark.usefixtures("hopper_modules")


@pytest.mark.parametrize(
    ("vary", "said"),
    [
        ({"speed": ([1.0, 2.0], "1 m/s")}, "vary speed: '1 m/s' is not a unit: the unit is read alone"),
        ({"speed": ([1.0, 2.0], "e-1 m/s")}, "vary speed: 'e-1 m/s' is not a unit"),
        ({"full": ([0.7, 0.8], "2 m")}, "vary full: '2 m' is not a unit"),
        ({"speed": ([3.6, 7.2], "km/h")},
         "vary speed: 'km/h' is not a unit legdsl knows: it has no 'h'"),
        ({"speed": ([3.6, 7.2], "/s")}, "vary speed: '/s' is not a unit legdsl knows"),
        ({"k_height": [0.1, 0.2]},
         "vary k_height: give its 2 values and their unit as a pair, e.g. "
         "{'k_height': (values, '')}"),
        ({"speed": [0.1, 0.2]}, "vary speed: give its 2 values and their unit as a pair, e.g. "
         "{'speed': (values, 'm/s')}"),
    ],
)  # fmt: skip
def test_vary_s_unit_is_a_unit_alone(tmp_path: Path, vary: dict, said: str) -> None:
    creature = legdsl.load(str(HOPPER), generated=str(tmp_path / "generated"))
    with pytest.raises(UsageError) as e:
        creature.run_copies(2, "hop", vary=vary, time=0.05)
    assert str(e.value).startswith(said), str(e.value)
    assert "set[" not in str(e.value) and "--set" not in str(e.value)
    if "not a unit" in said:  # the parameter's own unit
        unit = "m" if "full" in vary else "m/s"
        name = next(iter(vary))
        assert str(e.value).endswith(f"e.g. vary={{{name!r}: (values, {unit!r})}}")


def test_what_runs_is_what_is_recorded(tmp_path: Path) -> None:
    creature = legdsl.load(str(HOPPER), generated=str(tmp_path / "generated"))
    copies = creature.run_copies(2, "hop", vary={"speed": (np.array([1.0, 2.0]), "m / s")},
                                 time=0.05)  # fmt: skip
    for k, speed in enumerate([1.0, 2.0]):
        assert copies[k].info["inputs"]["speed"] == speed
        assert float(copies[k]["speed_command"][-1]) == pytest.approx(speed)


def test_a_quoted_set_is_told_as_set_s_entry(tmp_path: Path) -> None:
    creature = legdsl.load(str(HOPPER), generated=str(tmp_path / "generated"))
    with pytest.raises(UsageError) as e:
        creature.run_copies(2, "hop", set={"speed": "3.6 km/h"}, time=0.05)
    assert str(e.value).startswith("run_copies(): set['speed'] = '3.6km/h': 'km/h' is not a")
