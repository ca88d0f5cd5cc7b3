"""trajectory.csv against docs/runtime.md ("What a run writes"): the columns without a unit in
their name are the coordinates (whose unit is their joint's, as the doc says), the contact
flags and the state; the arrays of trajectory.npz the CSV leaves out are the ones the doc names;
and each value is the double to 9 significant digits. The doc said "units in the column names"
and "the same samples", and named neither the bare coordinates, the arrays left out nor the
rounding."""

from __future__ import annotations

import csv
import re
from pathlib import Path

import numpy as np
import pytest
from conftest import CREATURES, ROOT

from legdsl.analysis.series_units import series_unit
from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions
from legdsl.sim.trajectory import ARRAYS

# the CSV's columns of each array of trajectory.npz, by their names' form
WRITTEN = {
    "t": r"t \[s\]", "q": r"q\.\w+", "v": r"v\.\w+", "contact": r"\w+\.contact",
    "force": r"\w+\.f[xyz] \[N\]", "com": r"com\.[xyz] \[m\]", "com_vel": r"com\.v[xyz] \[m/s\]",
    "root_rpy": r"root\.(roll|pitch|yaw) \[rad\]", "leg_length": r"\w+\.length \[m\]",
    "kinetic": r"kinetic \[J\]", "potential": r"potential \[J\]", "elastic": r"elastic \[J\]",
    "state": r"state|state_name", "speed_command": r"speed_command \[m/s\]",
    "work_positive": r"\w+\.work_positive \[J\]", "work_negative": r"\w+\.work_negative \[J\]",
}  # fmt: skip


def _doc_bullet() -> str:
    text = (ROOT / "docs" / "runtime.md").read_text(encoding="utf-8")
    return text[text.index("* `trajectory.csv`:") :].split("\n* ", 1)[0]


@pytest.fixture(scope="module")
def session(generated: Path) -> RunSession:
    return RunSession.from_file(CREATURES / "hopper.leg", generated=generated)


@pytest.fixture(scope="module")
def written(session: RunSession, tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("hopper")
    session.run("hop", options=RunOptions(duration=0.3)).write(out)
    return out


def test_the_columns_without_a_unit_are_the_ones_the_doc_names(
    written: Path, session: RunSession
) -> None:
    header = next(csv.reader((written / "trajectory.csv").open()))
    bare = [c for c in header if "[" not in c]
    assert all(re.fullmatch(r"[qv]\.\w+|\w+\.contact|state|state_name", c) for c in bare), bare
    units = {series_unit(session.model, c) for c in bare if c[:2] in ("q.", "v.")}
    assert units == {"m", "rad", "m/s", "rad/s"}  # the joint's, as the doc says
    bullet = _doc_bullet()
    for said in ("`q.NAME` in m and `v.NAME` in m/s for a slide", "in rad and rad/s for a hinge"):
        assert said in bullet


def test_the_arrays_the_csv_leaves_out_are_named_and_its_values_rounded_as_said(
    written: Path,
) -> None:
    header = next(csv.reader((written / "trajectory.csv").open()))
    kept = {a for a in ARRAYS if any(re.fullmatch(WRITTEN.get(a, "-"), c) for c in header)}
    left_out = sorted(set(ARRAYS) - kept)
    assert left_out == ["leg_spring_energy", "root_pos"]
    bullet = _doc_bullet()
    assert all(f"`{name}`" in bullet for name in left_out)
    assert "9 significant digits" in bullet
    rows = list(csv.reader((written / "trajectory.csv").open()))[1:]
    z = np.load(written / "trajectory.npz")
    column = header.index("com.x [m]")
    for row, x in zip(rows, z["com"][:, 0], strict=True):
        assert row[column] == (repr(int(x)) if float(x).is_integer() else f"{x:.9g}")
