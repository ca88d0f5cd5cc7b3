"""A controller's default, a ``Quantity`` as ``load`` gives it, goes back into ``set=`` as it
is (a notebook copies one controller's value into another run): it used to be refused as
"not a text"; it keeps its dimension, so a wrong one is still refused."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import ROOT

import legdsl
from legdsl.lang.errors import UsageError

POGO = ROOT / "tests" / "good" / "outside" / "insect_pogo.leg"


@pytest.fixture(scope="module")
def pogo(generated: Path) -> legdsl.api.Creature:
    return legdsl.load(POGO, generated=generated)


def test_quantities_go_into_set(pogo) -> None:
    hop = pogo.controllers["hop"]
    given = {"height": hop.inputs["height"], "kv": hop.params["kv"],
             "k_trim": hop.params["k_trim"], "speed@10ms": hop.inputs["speed"]}  # fmt: skip
    settings = pogo.run(controller="hop", set=given, time=0.02).info["settings"]
    assert settings["inputs"] == {"height": float(hop.inputs["height"])}
    assert settings["params"] == {"kv": float(hop.params["kv"]), "k_trim": 0.5}
    assert settings["schedule"] == [{"t": 0.01, "input": "speed", "value": 0.25}]


def test_a_quantity_of_the_wrong_dimension_is_refused(pogo) -> None:
    with pytest.raises(UsageError, match=r"speed is a velocity \(m/s\), but 0.07m is a length"):
        pogo.run(controller="hop", set={"speed": pogo.controllers["hop"].inputs["height"]})


def test_an_angle_goes_in_radians(generated: Path) -> None:
    quad = legdsl.load(ROOT / "tests/good/outside/knee_quadruped.leg", generated=generated)
    stand = quad.controllers["trot"].params["stand"]
    run = quad.run(controller="trot", set={"stand": stand}, time=0.01)
    assert run.info["settings"]["params"] == {"stand": float(stand)}


@pytest.mark.parametrize(
    ("given", "told"),
    [
        ({"set": {"speed": float("nan")}}, "set 'speed': nan is not a finite number; give"),
        ({"set": {"speed": "nan m/s"}}, "set 'speed': 'nan m/s' is not a finite number; give"),
        ({"set": {"kv": "-inf N*m*s/rad"}}, "set 'kv': '-inf N*m*s/rad' is not a finite number"),
        ({"switch": {float("nan"): "hop"}}, "run(): switch= maps times to controllers"),
    ],
)
def test_a_value_that_is_no_finite_number_is_told_as_written(pogo, given, told) -> None:
    """A NaN or an infinity from Python was told in the command line's words about text the
    user never wrote ('--set 'speed=nanm/s'', '--switch nans=hop')."""
    with pytest.raises(UsageError) as caught:
        pogo.run(controller="hop", time=0.02, **given)
    assert str(caught.value).startswith(told), caught.value
