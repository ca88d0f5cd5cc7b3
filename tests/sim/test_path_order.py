"""A path is followed in its order: a stretch it comes back along, a lap then an exit, a closed
path that repeats a side, a creature that backs up or is knocked off (the tracker, fed positions
by hand); the biped running out and back on both backends; and the note for a lookahead too long
for the path's turns."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from conftest import CREATURES, GENERATED
from runtime_helpers import assert_same, needs_c_compiler

from legdsl.analysis.path_report import path_report
from legdsl.cli import main
from legdsl.ir.paths import PathSpec, square_corners
from legdsl.pipeline.session import RunSession
from legdsl.sim.path_tracking import PathGeometry, PathTracker, lookahead_note, track
from legdsl.sim.run_loop import RunOptions

OUT_AND_BACK = PathSpec("route", "polyline", ((0.0, 0.0), (6.0, 0.0), (0.0, 0.0)))
LAP_THEN_EXIT = PathSpec(
    "route", "polyline",
    ((0.0, 0.0), (4.0, 0.0), (4.0, 4.0), (0.0, 4.0), (0.0, 0.0), (4.0, 0.0), (4.0, -4.0)),
)  # fmt: skip
# the outside user's hexagon, its first side run again at the end
HEXAGON_AND_A_SIDE = PathSpec(
    "route", "polyline",
    ((0, 0), (4, 0), (6, 2), (4, 4), (0, 4), (-2, 2), (0, 0), (4, 0)),
)  # fmt: skip


def _along(spec: PathSpec, step: float, off: tuple[float, float] = (0.0, 0.0)):
    """Points every ``step`` along the whole path, shifted by ``off`` (a creature beside it)."""
    geo = PathGeometry(spec)
    n = int(geo.length / step)
    return [(x + off[0], y + off[1]) for x, y, _ in (geo.at(k * step) for k in range(n + 1))]


def _follow(spec: PathSpec, points: list[tuple[float, float]]) -> list[dict[str, float]]:
    tracker = PathTracker(spec)
    return [dict(tracker.update(x, y)) for x, y in points]


def test_out_and_back_turns_round_and_counts_the_way_back() -> None:
    """Out along x beside the path, round in a U short of its end, back 0.6 m to the side: the
    way back is the path's second half (heading -x, the runner on its right), progress on to 12."""
    out = [(k * 0.01, 0.05) for k in range(560)]
    turn = [(5.6 + 0.3 * math.sin(k * math.pi / 100), 0.35 - 0.3 * math.cos(k * math.pi / 100))
            for k in range(100)]  # fmt: skip
    back = [(5.6 - k * 0.01, 0.65) for k in range(561)]
    seen = _follow(OUT_AND_BACK, out + turn + back)
    end = seen[-1]
    assert end["progress"] == pytest.approx(12.0)
    assert end["heading"] == pytest.approx(math.pi)
    assert end["lateral"] == pytest.approx(-0.65)  # right of the way back
    # progress never steps back, nor jumps on by more than the turn's chord
    steps = [b["progress"] - a["progress"] for a, b in zip(seen, seen[1:], strict=False)]
    assert min(steps) > -1e-9 and max(steps) < 0.8
    # the report's tracker is the same: the same progress from the same points
    _, progress = track(OUT_AND_BACK, *zip(*(out + turn + back), strict=True))
    assert progress[-1] == end["progress"]


def test_a_creature_standing_at_the_turn_stays_where_it_is() -> None:
    """Still, on a stretch the path comes back along: the same reading, not the other pass."""
    seen = _follow(OUT_AND_BACK, [(5.5, 0.1)] * 20)
    assert {v["progress"] for v in seen} == {5.5}
    assert {v["heading"] for v in seen} == {0.0}


def test_a_lap_then_the_exit_is_taken() -> None:
    seen = _follow(LAP_THEN_EXIT, _along(LAP_THEN_EXIT, 0.01, (0.03, -0.02)))
    # along the side run twice, the second time is the second pass (before: the first again)
    steps = [b["progress"] - a["progress"] for a, b in zip(seen, seen[1:], strict=False)]
    assert min(steps) >= 0.0 and max(steps) < 0.1
    assert seen[1800]["progress"] == pytest.approx(18.0, abs=0.05)
    end = seen[-1]
    assert end["progress"] == pytest.approx(24.0)
    assert (end["x"], end["y"]) == pytest.approx((4.0, -4.0))
    assert end["ahead_heading"] == pytest.approx(-math.pi / 2)


def test_a_path_that_repeats_its_first_side_counts_it() -> None:
    geo = PathGeometry(HEXAGON_AND_A_SIDE)
    seen = _follow(HEXAGON_AND_A_SIDE, _along(HEXAGON_AND_A_SIDE, 0.02, (0.0, 0.1)))
    assert seen[-1]["progress"] == pytest.approx(geo.length, abs=0.02)
    # halfway along the repeated side it is on the repeat, not the first pass
    at = _follow(
        HEXAGON_AND_A_SIDE, _along(HEXAGON_AND_A_SIDE, 0.02)[: int((geo.length - 2) / 0.02) + 1]
    )
    assert at[-1]["progress"] == pytest.approx(geo.length - 2.0, abs=0.02)


def test_laps_of_a_closed_path_that_comes_back_along_a_side_keep_counting() -> None:
    """A polygon going round a square, out along its first side again and back to the start
    (a closed path with a stretch run both ways), for two laps and a half."""
    spec = PathSpec(
        "route", "polygon", ((0.0, 0.0), (4.0, 0.0), (4.0, 4.0), (0.0, 4.0), (0.0, 0.0), (4.0, 0.0)),
        closed=True,
    )  # fmt: skip
    geo = PathGeometry(spec)
    assert geo.length == pytest.approx(24.0)
    lap = _along(spec, 0.01, (0.01, 0.03))[:-1]
    seen = _follow(spec, lap + lap + lap[: len(lap) // 2])
    assert seen[0]["progress"] == pytest.approx(0.01)  # at the start, not the pass back to it
    assert seen[-1]["progress"] - seen[0]["progress"] == pytest.approx(2.5 * 24.0, abs=0.05)


def test_backing_up_and_being_knocked_off() -> None:
    """Backing up counts back; knocked 3 m to the side, the nearest point is where it was;
    far off, the projection slides along the path to what is nearest there."""
    spec = PathSpec("route", "polyline", ((0.0, 0.0), (10.0, 0.0), (10.0, 10.0)))
    tracker = PathTracker(spec)
    for k in range(51):
        tracker.update(k * 0.1, 0.0)
    assert tracker.update(4.0, 0.0)["progress"] == pytest.approx(4.0)  # 1 m back at once
    knocked = tracker.update(4.5, 3.0)
    assert (knocked["progress"], knocked["x"], knocked["lateral"]) == pytest.approx((4.5, 4.5, 3.0))
    for y in (6.0, 9.0):  # it runs on up past the corner, far to the side of the first leg
        v = tracker.update(4.5 + y / 3, y)
    assert v["heading"] == pytest.approx(math.pi / 2) and v["x"] == 10.0
    assert v["progress"] == pytest.approx(19.0)


# ------------------------------------------------------------------ runs
@needs_c_compiler
def test_the_biped_runs_out_and_back_the_same_on_both_backends() -> None:
    """2.5 m out, back to the start: it turns round, and progress reaches the whole 5 m."""
    sess = RunSession.from_file(CREATURES / "biped.leg", generated=GENERATED)
    path = "polyline((0, 0) m, (2.5, 0) m, (0, 0) m)"
    opts = RunOptions(duration=5.0)
    python = sess.run("run", ["speed=1.5m/s"], [path], options=opts, backend="python")
    c = sess.run("run", ["speed=1.5m/s"], [path], options=opts, backend="c")
    assert_same(python.result, c.result)
    (report,) = c.path_reports
    assert report["progress"] > 4.0  # of 5 m (before: under 2.5, the way out only)
    com = c.result.trajectory.com
    assert com[:, 0].max() > 2.0 and com[-1, 0] < 1.0
    # the report's progress is its tracker's over the run's samples
    spec = PathSpec("route", "polyline", ((0.0, 0.0), (2.5, 0.0), (0.0, 0.0)))
    again = path_report(c.result.trajectory, spec)
    assert again["progress"] == report["progress"]


# ------------------------------------------------------------------ the lookahead's note
def test_a_lookahead_too_long_for_the_turns_is_noted() -> None:
    tight = lookahead_note(PathSpec("route", "circle", center=(0.0, 0.3), radius=0.3))
    assert tight is not None and "191 deg" in tight and "'lookahead = 0.3 m' or less" in tight
    assert lookahead_note(PathSpec("route", "circle", center=(0.0, 1.0), radius=1.0)) is None
    small = PathSpec("route", "square", square_corners((0.0, 0.0), 0.5, 1), closed=True)
    told = lookahead_note(small)
    assert (
        told is not None and "180 deg" in told and "shorter than its longest side (0.5 m)" in told
    )
    square = PathSpec("route", "square", square_corners((0.0, 0.0), 2.0, 1), closed=True)
    assert lookahead_note(square) is None  # a side longer than the lookahead
    # one tight turn, even a hairpin, is taken: an open path is not noted
    assert lookahead_note(OUT_AND_BACK) is None


def test_the_note_is_told_before_the_run(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    status = main(
        [
            "run", str(CREATURES / "biped.leg"), "--controller", "run", "--set", "speed=1.5m/s",
            "--path", "circle(center = (0, 0.3) m, radius = 0.3 m)", "--time", "0.01",
            "--out", str(tmp_path / "run"), "--generated", str(GENERATED),
        ]
    )  # fmt: skip
    assert status == 0
    err = capsys.readouterr().err
    assert "note: path route: its lookahead (1 m) is longer than its radius (0.3 m)" in err
