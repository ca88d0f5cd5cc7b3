"""run.metrics() and legdsl metrics measure on one path: the API had no rows measured on the
creature's geometry (foot clearance at the apex, foot speed at touchdown, margins to the
terrain), nor a note saying why, though its run holds the creature's kinematics."""

from __future__ import annotations

import pickle
from pathlib import Path

import pytest
from conftest import CREATURES

import legdsl
from legdsl.pipeline.measure import measure_run

KINEMATIC = ("apex_foot_clearance", "touchdown_foot_speed")


@pytest.fixture(scope="module")
def run(generated: Path) -> legdsl.api.Run:
    return legdsl.load(CREATURES / "hopper.leg", generated=generated).run(controller="hop", time=2)


def test_run_metrics_has_the_rows_legdsl_metrics_has(
    run: legdsl.api.Run, generated: Path, tmp_path: Path
) -> None:
    fresh = run.metrics(start=0.5)
    keys = [s.key for s in fresh.summaries]
    assert all(k in keys for k in KINEMATIC), keys
    assert fresh.value("apex_foot_clearance") > 0 and fresh.unmeasured == ""
    saved = run.save(tmp_path / "run")
    measured, _ = measure_run(saved, 0.5, generated=generated)
    assert fresh.table() == measured.table()
    assert legdsl.open_run(saved, generated=generated).metrics(start=0.5).table() == fresh.table()


def test_a_run_without_its_kinematics_says_why_the_rows_are_left_out(
    run: legdsl.api.Run, tmp_path: Path
) -> None:
    again = pickle.loads(pickle.dumps(run))
    again._dynamics_file = str(tmp_path / "gone.py")
    m = again.metrics(start=0.5)
    assert not any(s.key in KINEMATIC for s in m.summaries)
    assert m.n_strides == run.metrics(start=0.5).n_strides
    assert m.unmeasured.startswith("the rows measured on the creature's geometry"), m.unmeasured
    assert "run.save(DIR)" in m.unmeasured
