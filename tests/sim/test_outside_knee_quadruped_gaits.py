"""The knee quadruped's other gaits written from the docs (tests/good/outside/knee_quadruped_gaits.leg):
knee_quadruped.leg's creature with a pace (its trot extended with the lateral pairs) and a bound
(the shipped bound's table with the standard library's knee actions), docs/quadruped.md, "A
quadruped with knees". Each holds 1 m/s with its pairs landing together, and runs the same on
both backends."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import ROOT
from runtime_helpers import assert_same, needs_c_compiler

from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions

LEG = ROOT / "tests" / "good" / "outside" / "knee_quadruped_gaits.leg"

pytestmark = needs_c_compiler

# the pairs each gait's virtual legs are, as indices of (fl, fr, rl, rr), and the pairs that
# must not be down together (the two virtual legs take turns)
PAIRS = {
    "pace": ((0, 2), (1, 3)),  # the lateral pairs: fl with rl, fr with rr
    "bound": ((0, 1), (2, 3)),  # the front pair, the rear pair
}


@pytest.fixture(scope="module")
def generated(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """One compile for the runs of the tests below (each compile of the C step takes seconds)."""
    return tmp_path_factory.mktemp("generated")


@pytest.mark.parametrize("gait", ["pace", "bound"])
def test_the_knee_quadruped_paces_and_bounds_at_1_m_s(generated: Path, gait: str) -> None:
    """5 s at 1 m/s: no fall, the speed over 2 to 5 s within 15%, each pair's feet down
    together and the two pairs taking turns (docs/quadruped.md has 10 s runs)."""
    sess = RunSession.from_file(LEG, generated=generated)
    run = sess.run(gait, ["speed=1m/s"], options=RunOptions(duration=5.0), backend="c").result
    assert run.status == "ok", run.message
    tr = run.trajectory
    later = tr.t >= 2.0
    mean = (tr.com[later][-1, 0] - tr.com[later][0, 0]) / (tr.t[later][-1] - tr.t[later][0])
    assert mean == pytest.approx(1.0, rel=0.15)
    down = tr.contact.astype(bool)[later]
    (a1, a2), (b1, b2) = PAIRS[gait]
    assert (down[:, a1] == down[:, a2]).mean() > 0.9
    assert (down[:, b1] == down[:, b2]).mean() > 0.9
    # the pairs take turns; the bound's cycle is irregular (some strides' stances overlap:
    # all four feet down 20% of 2 to 5 s, docs/quadruped.md), the pace's is not
    assert (down[:, a1] & down[:, b1]).mean() < (0.3 if gait == "bound" else 0.05)


def test_the_knee_quadruped_bounds_the_same_on_both_backends(generated: Path) -> None:
    sess = RunSession.from_file(LEG, generated=generated)
    opts = RunOptions(duration=2.0)
    python = sess.run("bound", ["speed=1m/s"], options=opts, backend="python").result
    c = sess.run("bound", ["speed=1m/s"], options=opts, backend="c").result
    assert python.status == "ok", python.message
    assert_same(python, c)
