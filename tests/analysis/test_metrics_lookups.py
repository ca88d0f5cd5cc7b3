"""What a notebook user is told on asking for what a run's metrics do not have: an unknown
metric (it was a bare KeyError), a leg named twice in a group (it was counted twice), a
window time in a wrong unit (its example had a stray space: "start= 100s")."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest
from anim_runs import creature_run

from legdsl.analysis.metrics import compute_metrics
from legdsl.analysis.results import MetricsError
from legdsl.lang.errors import UsageError
from legdsl.pipeline.options import read_seconds
from legdsl.sim.trajectory import Trajectory


def test_an_unknown_metric_is_named_with_the_nearest_and_the_list(tmp_path: Path) -> None:
    metrics = compute_metrics(Trajectory.load(creature_run("quadruped", tmp_path / "run")))
    with pytest.raises(KeyError) as lookup:  # still a KeyError, as a lookup's
        metrics.value("runing_speed")
    said = str(lookup.value)
    assert said.startswith("no metric 'runing_speed'; did you mean 'running_speed'? (the run has ")
    assert isinstance(lookup.value, MetricsError)


def test_a_leg_named_twice_in_a_group_is_refused(tmp_path: Path) -> None:
    tr = Trajectory.load(creature_run("quadruped", tmp_path / "run"))
    with pytest.raises(MetricsError, match=r"group 'a' names fl twice: give each leg once "):
        compute_metrics(tr, groups={"a": ["fl", "fl", "rr"]})


def test_a_window_time_of_the_api_is_told_without_a_stray_space() -> None:
    with pytest.raises(UsageError) as wrong:
        read_seconds("start=", "100 kg")
    assert str(wrong.value).endswith("write e.g. start=100s")


def test_a_run_without_legs_groups_its_contacts(tmp_path: Path) -> None:
    """A run without legs measures each contact as a leg of its own (``--leg CONTACT``), but a
    group of its contacts was refused, "no leg named ... (legs: none)": the virtual leg of
    several contacts (a legless rig's feet) could not be had. It stands while any touches."""
    tr = Trajectory.load(creature_run("quadruped", tmp_path / "run"))
    legless = dataclasses.replace(tr, leg_names=(), leg_feet=(), leg_length=tr.leg_length[:, :0],
                                  leg_spring_energy=tr.leg_spring_energy[:, :0])  # fmt: skip
    front = [tr.contact_names[tr.leg_feet[tr.leg_names.index(leg)]] for leg in ("fl", "fr")]
    grouped = compute_metrics(legless, groups={"front": front}, leg="front")
    as_legs = compute_metrics(tr, groups={"front": ["fl", "fr"]}, leg="front")
    assert grouped.value("stride_duration") == as_legs.value("stride_duration")
    with pytest.raises(MetricsError, match=r"group 'a' names .* twice: give each contact once"):
        compute_metrics(legless, groups={"a": [front[0], front[0]]})
    with pytest.raises(MetricsError, match=r"group 'a': no contact named fl \(contacts: "):
        compute_metrics(legless, groups={"a": ["fl"]})
