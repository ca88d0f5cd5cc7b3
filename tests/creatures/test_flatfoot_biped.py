"""A 3D biped on flat feet written from the docs (tests/good/outside/flatfoot_biped.leg): the
shipped biped's legs with an ankle and a foot of three contacts (heel, mid-sole: the leg's
foot, toe), all three the leg's soles. The shipped `run` with the apex, the thrust's end and
the speed trim changed runs it at 1 m/s; it lands heel first, and the heel's landing is the
leg's touchdown; and the run is the same on both backends, bit for bit."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import ROOT
from runtime_helpers import assert_same, needs_c_compiler

from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions

LEG = ROOT / "tests" / "good" / "outside" / "flatfoot_biped.leg"

pytestmark = needs_c_compiler


@pytest.fixture(scope="module")
def session(tmp_path_factory: pytest.TempPathFactory) -> RunSession:
    return RunSession.from_file(LEG, generated=tmp_path_factory.mktemp("flatfoot_generated"))


def test_it_runs_at_1_m_s_heel_first(session: RunSession) -> None:
    run = session.run("run", ["speed=1m/s"], options=RunOptions(duration=8.0), backend="c").result
    assert run.status == "ok", run.message
    tr = run.trajectory
    assert np.abs(tr.root_rpy[:, :2]).max() < np.radians(15)
    start = int(np.searchsorted(tr.t, 3.0))
    vx = (tr.com[-1, 0] - tr.com[start, 0]) / (tr.t[-1] - tr.t[start])
    assert abs(vx - 1.0) < 0.05
    names = list(tr.contact_names)
    for side in ("l", "r"):  # every touchdown of the sole comes after its heel's
        heel = tr.contact[start:, names.index(f"heel_{side}")] != 0
        sole = tr.contact[start:, names.index(f"sole_{side}")] != 0
        landings = np.flatnonzero(np.diff(sole.astype(np.int8)) == 1) + 1
        assert landings.size >= 4
        assert all(heel[k - 1] for k in landings)


def test_the_run_is_the_same_on_both_backends(session: RunSession) -> None:
    opts = RunOptions(duration=2.0)
    python = session.run("run", ["speed=1m/s"], options=opts, backend="python").result
    c = session.run("run", ["speed=1m/s"], options=opts, backend="c").result
    assert python.status == "ok", python.message
    assert_same(python, c)


def test_touchdown_is_the_first_sole_landing_on_both_backends(session: RunSession) -> None:
    """LOADING (entered at touchdown(active)) comes at the control tick of the heel strike,
    before the mid-sole (the leg's foot point) lands."""
    opts = RunOptions(duration=0.3, record_rate=0)
    python = session.run("run", ["speed=1m/s"], options=opts, backend="python").result
    c = session.run("run", ["speed=1m/s"], options=opts, backend="c").result
    assert_same(python, c)
    tr = python.trajectory
    names = list(tr.contact_names)
    soles = [names.index(f"{part}_{side}") for side in "lr" for part in ("sole", "heel", "toe")]
    assert tr.leg_soles == (tuple(soles[:3]), tuple(soles[3:]))
    first_sole = tr.t[np.flatnonzero(tr.contact[:, soles].any(axis=1))[0]]
    feet = [names.index("sole_l"), names.index("sole_r")]
    first_foot = tr.t[np.flatnonzero(tr.contact[:, feet].any(axis=1))[0]]
    loading = next(e["t"] for e in python.events if e.get("state") == "LOADING")
    assert first_sole <= loading < first_sole + 0.002 + 1e-9  # the next control tick
    assert loading < first_foot
