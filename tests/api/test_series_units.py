"""Run.unit: the SI unit of each recorded series, read from the creature (a hinge's
coordinate in rad, a slide's in m), for a notebook's plot labels."""

from __future__ import annotations

from pathlib import Path

import pytest

import legdsl

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def runs(generated: Path) -> dict[str, legdsl.Run]:
    return {
        name: legdsl.load(ROOT / "creatures" / f"{name}.leg", generated=generated).run(
            controller=None, drop="1 cm", time=0.1
        )
        for name in ("hopper", "quadruped")
    }


def test_every_series_has_its_unit(runs: dict[str, legdsl.Run]) -> None:
    for run in runs.values():
        units = {name: run.unit(name) for name in run.samples}
        assert all(isinstance(u, str) for u in units.values())


@pytest.mark.parametrize(
    ("creature", "name", "unit"),
    [
        ("hopper", "q.hip", "rad"), ("hopper", "q.leg", "m"), ("hopper", "v.leg", "m/s"),
        ("hopper", "q.pitch", "rad"), ("hopper", "v.x", "m/s"), ("hopper", "t", "s"),
        ("quadruped", "q.qw", ""), ("quadruped", "v.wz", "rad/s"), ("quadruped", "v.vx", "m/s"),
        ("quadruped", "q.hip_fl_x", "rad"), ("quadruped", "q.leg_fl", "m"),
        ("quadruped", "force.toe_fl.z", "N"), ("quadruped", "root.yaw", "rad"),
        ("quadruped", "energy.kinetic", "J"), ("quadruped", "contact.toe_fl", ""),
    ],
)  # fmt: skip
def test_a_series_unit(runs: dict[str, legdsl.Run], creature: str, name: str, unit: str) -> None:
    assert runs[creature].unit(name) == unit


def test_a_name_that_is_no_series_is_told_the_nearest(runs: dict[str, legdsl.Run]) -> None:
    with pytest.raises(KeyError, match="did you mean 'q.hip'"):
        runs["hopper"].unit("q.hipp")


def test_a_run_says_which_series_it_has_and_is_not_iterated(runs: dict[str, legdsl.Run]) -> None:
    """``NAME in run`` asks for a series by name, as ``run[NAME]`` reads it; iterating a run
    (``list(run)``, ``dict(run)``) is refused towards ``run.samples``, not told as a series 0."""
    run = runs["hopper"]
    assert "com.x" in run and "q.hip" in run
    assert "no_such" not in run and 0 not in run and "COM.x" not in run
    for iterate in (list, dict, iter):
        with pytest.raises(TypeError, match=r"its series are run\.samples"):
            iterate(run)
