"""A quadruped with a flexing spine written from the docs (tests/good/outside/spine_quadruped.leg):
the shipped quadruped's trunk in two halves on a pitch hinge with a spring-damper, the front
legs on the front half (the free root), the rear legs on the rear half. The shipped trot,
extended, trots it at 2 m/s, its diagonal pairs landing together while the spine flexes; the
hip points the controller reads move with the spine; and the run is the same on both
backends, bit for bit."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import OUTSIDE, outside_session
from runtime_helpers import assert_same, needs_c_compiler

from legdsl.analysis.pairs import hip_positions, pair_groups
from legdsl.check.source import check_file
from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions

LEG = OUTSIDE / "spine_quadruped.leg"

pytestmark = needs_c_compiler


@pytest.fixture(scope="module")
def session() -> RunSession:
    return outside_session(LEG.name)


def test_the_pairs_are_found_from_hips_on_either_half() -> None:
    """The rear hips hang from the rear half: their points add the spine's offset."""
    (model,) = check_file(LEG)
    hips = hip_positions(model)
    assert hips["rl"] == pytest.approx((-0.615, 0.12)) and hips["fl"] == pytest.approx(
        (0.165, 0.12)
    )
    assert pair_groups(hips, "front/rear") == {"front": ["fl", "fr"], "rear": ["rl", "rr"]}


def test_it_trots_at_2_m_s_flexing_its_spine(session: RunSession) -> None:
    run = session.run("trot", ["speed=2m/s"], options=RunOptions(duration=8.0), backend="c").result
    assert run.status == "ok", run.message
    tr = run.trajectory
    start = int(np.searchsorted(tr.t, 3.0))
    vx = (tr.com[-1, 0] - tr.com[start, 0]) / (tr.t[-1] - tr.t[start])
    assert abs(vx - 2.0) < 0.1
    assert np.abs(tr.root_rpy[start:, 1]).max() < np.radians(5)
    spine = np.degrees(tr.q[start:, tr.q_names.index("spine")])
    assert 0.5 < spine.max() - spine.min() < 10  # it flexes, within its limits
    names = list(tr.contact_names)
    down = {s: tr.contact[start:, names.index(f"toe_{s}")] != 0 for s in ("fl", "fr", "rl", "rr")}
    for a, b in (("fl", "rr"), ("fr", "rl")):  # the diagonal pairs land together
        landings = np.flatnonzero(np.diff(down[a].astype(np.int8)) == 1) + 1
        assert landings.size >= 6
        assert all(down[b][k - 5 : k + 6].any() for k in landings)
    # hip to foot of a rear leg, its hip on the rear half: within the leg's slide
    rear = tr.leg_length[start:, list(tr.leg_names).index("rl")]
    assert rear.min() > 0.6 and rear.max() < 0.9


def test_the_run_is_the_same_on_both_backends(session: RunSession) -> None:
    opts = RunOptions(duration=2.0)
    python = session.run("trot", ["speed=2m/s"], options=opts, backend="python").result
    c = session.run("trot", ["speed=2m/s"], options=opts, backend="c").result
    assert python.status == "ok", python.message
    assert_same(python, c)
