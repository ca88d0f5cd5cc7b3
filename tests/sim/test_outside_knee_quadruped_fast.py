"""The knee quadruped's bound and gallop with tables kept to their feet
(tests/good/outside/knee_quadruped_fast.leg; docs/quadruped.md, "A quadruped with knees"):
COMPRESSION and THRUST need the active pair's feet down, and the idle pair landing ends the
active pair's stance (the pairs swap), so the table no longer runs a stance while its active
pair is in the air and the other pair, tucked short, carries the trunk. Tuned with the
stride-to-stride spread scored, the bound holds 1 to 3 m/s and the gallop 2 to 3.25 m/s. Above
2.25 m/s the bound tuned at 1 to 2 m/s fell: its front pair left the ground with no upward
speed, skimmed it and touched down again in FLIGHT, where the table waits for the rear pair;
retuned at 1 to 3 m/s with the idle pair's knee damped less in flight (`fold_b`), it holds."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT
from runtime_helpers import needs_c_compiler

from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions

LEG = ROOT / "tests" / "good" / "outside" / "knee_quadruped_fast.leg"

pytestmark = needs_c_compiler


@pytest.fixture(scope="module")
def generated(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """One compile for the runs of the tests below (each compile of the C step takes seconds)."""
    return tmp_path_factory.mktemp("generated")


def _stances(pair: np.ndarray, t: np.ndarray) -> list[tuple[int, float]]:
    """(first sample, duration) of each whole stance of a pair (either foot down)."""
    edges = np.diff(np.r_[0, pair.astype(np.int8), 0])
    starts, ends = np.flatnonzero(edges > 0), np.flatnonzero(edges < 0)
    return [(s, t[e] - t[s]) for s, e in zip(starts, ends, strict=True) if s > 0 and e < len(t)]


def _first_down(down: np.ndarray, starts: list[int], a: int, b: int) -> list[int]:
    """For each stance start, which member touched first: 1 for a, 2 for b, 0 for both."""
    return [
        int(down[k, a]) + 2 * int(down[k, b]) - 3 * int(down[k, a] & down[k, b]) for k in starts
    ]


def _run(generated: Path, gait: str, speed: float):  # type: ignore[no-untyped-def]
    sess = RunSession.from_file(LEG, generated=generated)
    opts = RunOptions(duration=6.0)
    run = sess.run(gait, [f"speed={speed}m/s"], options=opts, backend="c").result
    assert run.status == "ok", run.message
    tr = run.trajectory
    later = tr.t >= 3.0
    t = tr.t[later]
    mean = (tr.com[later][-1, 0] - tr.com[later][0, 0]) / (t[-1] - t[0])
    down = tr.contact.astype(bool)[later]
    front = _stances(down[:, 0] | down[:, 1], t)
    rear = _stances(down[:, 2] | down[:, 3], t)
    return mean, t, down, front, rear


def test_the_fast_bound_bounds_at_1_5_m_s(generated: Path) -> None:
    """6 s at 1.5 m/s: no fall, within 10% from 3 s (10 s runs: 1.524 m/s), each pair's feet
    landing in the same sample, the pairs carrying the trunk in turn, and no brush (every
    pair stance over 40 ms: the old table ran stances of 5 ms and of 0.3 s)."""
    mean, _, down, front, rear = _run(generated, "bound", 1.5)
    assert mean == pytest.approx(1.5, rel=0.1)
    assert len(front) >= 8 and len(rear) >= 8
    for stances in (front, rear):
        assert all(0.04 < d < 0.25 for _, d in stances), stances
    for (a, b), stances in (((0, 1), front), ((2, 3), rear)):
        assert all(f == 0 for f in _first_down(down, [s for s, _ in stances], a, b))
    f, r = down[:, 0] | down[:, 1], down[:, 2] | down[:, 3]
    assert (f & ~r).mean() > 0.2 and (r & ~f).mean() > 0.2


def test_the_fast_bound_bounds_at_3_m_s(generated: Path) -> None:
    """6 s at 3 m/s (the bound tuned at 1 to 2 m/s fell at 3.2 s): no fall, within 5% from 3 s,
    the pairs in turn, and the front pair never touching down again within 40 ms of its
    liftoff (the re-touch in FLIGHT that started every fall)."""
    mean, t, down, front, rear = _run(generated, "bound", 3.0)
    assert mean == pytest.approx(3.0, rel=0.05)
    assert len(front) >= 8 and len(rear) >= 8
    for stances in (front, rear):
        assert all(0.04 < d < 0.25 for _, d in stances), stances
    f, r = down[:, 0] | down[:, 1], down[:, 2] | down[:, 3]
    lifts = np.flatnonzero(np.diff(f.astype(np.int8)) < 0) + 1
    lands = np.flatnonzero(np.diff(f.astype(np.int8)) > 0) + 1
    for k in lifts:
        later = lands[lands > k]
        assert not len(later) or t[later[0]] - t[k] > 0.04, t[k]
    assert (f & ~r).mean() > 0.2 and (r & ~f).mean() > 0.2


def test_the_fast_gallop_gallops_at_2_5_m_s(generated: Path) -> None:
    """6 s at 2.5 m/s: no fall, within 10% from 3 s (it runs about 2.5 m/s), the leading
    member (fl in front, rr behind: a rotary gallop) down first in every stance of its pair,
    the pairs in turn, and no brush (every pair stance over 40 ms)."""
    mean, _, down, front, rear = _run(generated, "gallop", 2.5)
    assert mean == pytest.approx(2.5, rel=0.1)
    assert len(front) >= 8 and len(rear) >= 8
    for stances in (front, rear):
        assert all(0.04 < d < 0.25 for _, d in stances), stances
    assert all(f == 1 for f in _first_down(down, [s for s, _ in front], 0, 1))
    assert all(f == 1 for f in _first_down(down, [s for s, _ in rear], 3, 2))
    f, r = down[:, 0] | down[:, 1], down[:, 2] | down[:, 3]
    assert (f & ~r).mean() > 0.1 and (r & ~f).mean() > 0.1
