"""Options given as numpy numbers (a notebook's ``for dt in np.linspace(...)``) ran, but the
run could not be saved (run.json: "Object of type float32 is not JSON serializable"); they are
read as floats now, and an option of the wrong type is a ``UsageError`` naming it."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT

import legdsl
from legdsl.lang.errors import UsageError

POGO = ROOT / "tests" / "good" / "outside" / "insect_pogo.leg"


@pytest.fixture(scope="module")
def pogo(generated: Path) -> legdsl.api.Creature:
    return legdsl.load(POGO, generated=generated)


def test_numpy_numbers_as_options_save(pogo, tmp_path: Path) -> None:
    run = pogo.run(controller="hop", time=0.02, dt=np.float32(5e-5), record_rate=np.int32(400),
                   drop=np.int64(0), fall_height=np.float64(0.01))  # fmt: skip
    saved = json.loads((run.save(tmp_path / "r") / "run.json").read_text())["options"]
    assert saved["dt"] == pytest.approx(5e-5) and saved["record_rate"] == 400.0
    assert saved["drop"] == 0.0 and saved["fall_height"] == 0.01


@pytest.mark.parametrize("value", [True, [2e-4], "x"])
def test_an_option_of_the_wrong_type_is_a_usage_error(pogo, value) -> None:
    with pytest.raises(UsageError, match=r"dt"):
        pogo.run(controller="hop", time=0.02, dt=value)


def test_zero_dimensional_arrays_are_their_numbers(pogo, tmp_path: Path) -> None:
    """time=, dt=, fall_tilt= and metrics(start=) refused np.array(0.02) ("not
    array(0.02)"), which api.md's "a numpy one too" and numpy's reductions give; a 0-d array
    of a real number is that number, one of True/False or a complex one still refused."""
    run = pogo.run(controller="hop", time=np.array(0.02), dt=np.array(5e-5),
                   fall_tilt=np.array(1.2), record_rate=np.array(400))  # fmt: skip
    saved = json.loads((run.save(tmp_path / "r") / "run.json").read_text())["options"]
    assert saved["dt"] == 5e-5 and saved["fall_tilt"] == 1.2 and saved["duration"] == 0.02
    assert run.metrics(start=np.array(0.0), end=np.array(0.02)).t_to <= 0.02
    for wrong in (np.array(True), np.array(0.02 + 0j)):
        with pytest.raises(UsageError, match=r"time= is seconds"):
            pogo.run(controller="hop", time=wrong)
