"""Paths to follow: the geometry (legdsl/paths.py), the `path` declaration, `legdsl run --path`,
and the biped following an L-shaped path for a few strides."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import pytest
from conftest import CREATURES, ROOT

from legdsl.analysis.path_report import path_report
from legdsl.check.source import check_file, check_model
from legdsl.cli import main
from legdsl.ir.paths import PathSpec, square_corners
from legdsl.ir.waypoints import read_waypoints
from legdsl.lang.errors import LegError, UsageError
from legdsl.lower.control import lower_controller
from legdsl.pipeline.path_option import parse_path_option
from legdsl.sim.machine import resolve_paths
from legdsl.sim.path_tracking import PathGeometry, PathTracker
from legdsl.sim.trajectory import Trajectory

BIPED = CREATURES / "biped.leg"
LEFT_CIRCLE = PathSpec("route", "circle", center=(0.0, 5.0), radius=5.0, turn=1)
RIGHT_CIRCLE = PathSpec("route", "circle", center=(0.0, -5.0), radius=5.0, turn=-1)
SQUARE = PathSpec("route", "square", square_corners((0.0, 0.0), 8.0, 1), closed=True)


# ------------------------------------------------------------------ geometry
def test_circle_distance_sign_and_tangent() -> None:
    geo = PathGeometry(LEFT_CIRCLE)
    assert geo.length == pytest.approx(2 * math.pi * 5)
    start = geo.project(0.0, 0.0)  # the circle's start, heading +x
    assert (start.s, start.x, start.y, start.heading, start.lateral) == pytest.approx(
        (0.0, 0.0, 0.0, 0.0, 0.0), abs=1e-12
    )
    inside = geo.project(0.0, 0.3)  # to the left of a counter-clockwise circle
    assert inside.lateral == pytest.approx(0.3)
    outside = geo.project(5.4, 5.0)  # a quarter on, outside: to the right
    assert outside.lateral == pytest.approx(-0.4)
    assert outside.s == pytest.approx(2 * math.pi * 5 / 4)
    assert outside.heading == pytest.approx(math.pi / 2)  # going +y there
    # clockwise: outside is to the left, and a quarter on heads -y
    right = PathGeometry(RIGHT_CIRCLE)
    assert right.project(0.0, 0.3).lateral == pytest.approx(0.3)
    assert right.project(0.0, -0.3).lateral == pytest.approx(-0.3)
    assert right.project(5.0, -5.0).heading == pytest.approx(-math.pi / 2)
    x, y, heading = right.at(2 * math.pi * 5 / 4)
    assert (x, y, heading) == pytest.approx((5.0, -5.0, -math.pi / 2))


def test_polyline_distance_sign_progress_and_ends() -> None:
    geo = PathGeometry(PathSpec("p", "polyline", ((0.0, 0.0), (4.0, 0.0), (4.0, 3.0))))
    assert geo.length == pytest.approx(7.0)
    p = geo.project(2.0, 0.5)
    assert (p.s, p.x, p.y, p.lateral, p.heading) == pytest.approx((2.0, 2.0, 0.0, 0.5, 0.0))
    p = geo.project(4.5, 1.0)  # right of the second leg, which heads +y
    assert (p.s, p.lateral, p.heading) == pytest.approx((5.0, -0.5, math.pi / 2))
    assert geo.at(5.0) == pytest.approx((4.0, 1.0, math.pi / 2))
    assert geo.at(99.0)[:2] == pytest.approx((4.0, 3.0))  # an open path clamps at its end
    # past the start, the lateral error is the distance to the first segment's line
    assert geo.project(-1.0, -0.2).lateral == pytest.approx(-0.2)


def test_square_corners_and_wrap_around() -> None:
    assert square_corners((1.0, 2.0), 8.0, 1) == ((1, 2), (9, 2), (9, 10), (1, 10))
    assert square_corners((0.0, 0.0), 8.0, -1)[2] == (8.0, -8.0)
    geo = PathGeometry(SQUARE)
    assert geo.length == pytest.approx(32.0)
    assert geo.at(33.0) == pytest.approx((1.0, 0.0, 0.0))  # closed: wraps
    assert geo.at(31.0) == pytest.approx((0.0, 1.0, -math.pi / 2))
    # progress is unwrapped: going round past the start keeps counting
    tracker = PathTracker(SQUARE)
    for s in [*range(0, 32), 32.5, 33.0, 34.0]:
        x, y, _ = geo.at(float(s))
        values = tracker.update(x, y)
    assert values["progress"] == pytest.approx(34.0)
    assert values["given"] == 1.0
    # the look-ahead point (1 m by default) turns the corner before the creature does
    values = tracker.update(7.5, 0.0)
    assert (values["ahead_x"], values["ahead_y"]) == pytest.approx((8.0, 0.5))
    assert values["ahead_heading"] == pytest.approx(math.pi / 2)
    assert values["heading"] == pytest.approx(0.0)


@pytest.mark.parametrize("spec", [LEFT_CIRCLE, RIGHT_CIRCLE, SQUARE])
def test_run_json_says_a_circle_is_closed_as_its_report_does(spec: PathSpec) -> None:
    """run.json's paths[].closed was false for a circle, where its path_reports[].closed
    (the tracker's: a circle goes round) was true; it reads back as the same path."""
    data = spec.as_json()
    assert data["closed"] is PathGeometry(spec).closed is True
    assert PathSpec.from_json(data) == spec
    line = PathSpec("route", "polyline", ((0.0, 0.0), (1.0, 0.0)))
    assert line.as_json()["closed"] is False and PathSpec.from_json(line.as_json()) == line


def test_no_path_reads_zero() -> None:
    values = PathTracker(PathSpec("route", "none")).update(3.0, 4.0)
    assert values["given"] == 0.0 and values["lateral"] == 0.0


# ------------------------------------------------------------------ language and command line
def test_path_declarations_are_checked_into_the_controller(tmp_path: Path) -> None:
    source = tmp_path / "walker.leg"
    text = (ROOT / "tests" / "bad" / "path_unknown_member.leg").read_text()
    text = text.replace("route.lateal", "route.lateral").replace(
        "path route = circle(center = (0, 5) m, radius = 5 m)",
        "path route = polygon((0, 0) m, (10, 0) m, (10, 10) m, lookahead = 2 m)\n  path spare",
    )
    source.write_text(text)
    (model,) = check_file(source)
    route, spare = model.controllers[0].paths
    assert route.shape == "polygon" and route.closed and route.lookahead == 2.0
    assert route.points == ((0, 0), (10, 0), (10, 10))
    assert spare.shape == "none"
    lowered = lower_controller(model, model.controllers[0])
    assert "path.route.lateral" in lowered.sensors


def test_an_action_may_pass_its_let_to_another_action_with_roles(tmp_path: Path) -> None:
    """control_lower's swap pass walks into actions: it must know their `let` values."""
    source = tmp_path / "swapper.leg"
    text = (ROOT / "tests" / "bad" / "path_unknown_member.leg").read_text()
    text = text.replace("path route = circle(center = (0, 5) m, radius = 5 m)", "roles a = main")
    text = text.replace(
        "state FLIGHT on route.lateal > 1 m: leg_spring.rest = 0.1 m",
        "state FLIGHT on trunk.z > 1 m: outer(a)",
    )
    text = text.replace(
        "controller hop {",
        "action inner(l, r) { l.spring.rest = r }\n"
        "action outer(l) { let r = 2 * trunk.z; inner(l, r) }\ncontroller hop {",
    )
    source.write_text(text)
    (model,) = check_file(source)
    lowered = lower_controller(model, model.controllers[0])
    (setting,) = lowered.bodies[(0, 0)].settings
    assert setting.actuator == "leg_spring" and "body_trunk_z" in str(setting.value)


def test_path_option_parses_like_the_file(tmp_path: Path) -> None:
    spec = parse_path_option("route=circle(center = (0, 5) m, radius = 500 cm, turn = right)")
    assert (spec.name, spec.shape, spec.center, spec.radius, spec.turn) == (
        "route", "circle", (0.0, 5.0), 5.0, -1,
    )  # fmt: skip
    spec = parse_path_option("square(corner = (0, 0) m, side = 8 m)")
    assert spec.name == "" and spec.closed and spec.points[2] == (8.0, 8.0)
    with pytest.raises(LegError) as err:
        parse_path_option("route=circle(center = (0, 5) m, radius = -5 m)")
    rendered = err.value.render()
    assert rendered.startswith("--path:1:")
    assert "'radius' must be positive" in rendered
    _, line, caret = rendered.splitlines()
    assert caret.index("^") == line.index("-5 m")  # the caret under the radius, in the option
    # the friendly syntax errors hold in an option as in a file (one parser, one state table)
    with pytest.raises(LegError, match="a ',' is missing before 'radius'"):
        parse_path_option("circle(center = (0, 5) m radius = 5 m)")
    csv = tmp_path / "waypoints.csv"
    csv.write_text("x,y\n0,0\n5, 0\n5,5  # the corner\n")
    spec = parse_path_option(f"route={csv}")
    assert spec == read_waypoints(csv, "route")
    assert spec.points == ((0.0, 0.0), (5.0, 0.0), (5.0, 5.0))
    csv.write_text("0,0\n5\n")
    with pytest.raises(UsageError, match="waypoints.csv:2:2: this line has x alone"):
        parse_path_option(str(csv))
    for empty in ("", "  ", "route="):  # was 'unexpected end of the file' at '--path:1:1'
        with pytest.raises(UsageError, match="gives no path: write a shape"):
            parse_path_option(empty)


def test_a_waypoints_file_that_is_not_utf8_text_is_a_usage_error(tmp_path: Path) -> None:
    csv = tmp_path / "waypoints.csv"
    csv.write_bytes(b"\xff\xfe\x00\x01")  # it was an internal error (UnicodeDecodeError)
    with pytest.raises(UsageError, match="save it as UTF-8 text"):
        read_waypoints(csv, "route")
    csv.write_bytes(b"\xef\xbb\xbf0,0\n5,0\n")  # a byte-order mark hid the first point
    assert read_waypoints(csv, "route").points == ((0.0, 0.0), (5.0, 0.0))


@pytest.mark.parametrize(
    ("shape", "says", "at"),
    [
        ("polyline((0, 0) m, (1e-13, 0) m)", "is the point before it again", "(1e-13"),
        ("polygon((0, 0) m, (1, 0) m, (1, 1) m, (1e-13, 0) m)", "closes itself", "polygon"),
        ("polyline((0, 0) m, (1e200, 0) m)", "within 1e+09 m of the origin", "(1e200"),
        ("circle(center = (0, 5) m, radius = 1e300 m)", "at most 1e+09 m", "1e300"),
        ("square(corner = (-1e10, 0) m, side = 1 m)", "within 1e+09 m", "(-1e10"),
    ],
)
def test_a_degenerate_or_far_path_is_an_error_at_its_place(shape: str, says: str, at: str) -> None:
    """A segment shorter than the tracker keeps was an internal error (AssertionError: no
    segment left); a point past about 1e154 m projected every point onto the segment's start
    (its squared length overflowed), and a radius of 1e300 m made a path of infinite length."""
    with pytest.raises(LegError) as err:
        parse_path_option(shape)
    rendered = err.value.render()
    assert says in rendered
    _, line, caret = rendered.splitlines()
    assert caret.index("^") == line.index(at)


@pytest.mark.parametrize(
    ("rows", "says"),
    [
        ("0,0\n1e-13,0\n", "waypoints.csv:2:1: this point repeats"),
        ("0,0\n1e300,0\n", "waypoints.csv:2:1: x is more than 1e+09 m"),
    ],
)
def test_a_degenerate_or_far_waypoint_is_a_usage_error(
    tmp_path: Path, rows: str, says: str
) -> None:
    csv = tmp_path / "waypoints.csv"
    csv.write_text(rows)
    with pytest.raises(UsageError, match=re.escape(says)):
        read_waypoints(csv, "route")


def test_path_option_names_a_declared_path() -> None:
    model = check_model(BIPED)
    circle = parse_path_option("circle(center = (0, 5) m, radius = 5 m)")
    (route,) = resolve_paths(model, "run", [circle])
    assert route.name == "route" and route.shape == "circle"
    (route,) = resolve_paths(model, "run", [])
    assert route.shape == "none"
    with pytest.raises(UsageError, match="no path 'road'"):
        resolve_paths(model, "run", [parse_path_option("road=polyline((0, 0) m, (1, 0) m)")])


def test_a_path_given_twice_is_refused() -> None:
    """The later would win silently, as two --set of one name would (found by
    tests/sim/test_random_run_options.py): with and without the path's name."""
    model = check_model(BIPED)
    circle = parse_path_option("circle(center = (0, 5) m, radius = 5 m)")
    named = parse_path_option("route=square(corner = (0, 0) m, side = 8 m)")
    for twice in ([circle, circle], [circle, named]):
        with pytest.raises(UsageError, match="path route of controller run is given twice"):
            resolve_paths(model, "run", twice)


# ------------------------------------------------------------------ the biped
def test_the_biped_follows_an_l_shaped_path(
    generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A few strides along x, a 90-degree corner at (5, 0), a few strides along y."""
    out = tmp_path / "run"
    status = main(
        [
            "run", str(BIPED), "--controller", "run", "--set", "speed=1.5m/s",
            "--path", "polyline((0, 0) m, (5, 0) m, (5, 10) m)",
            "--time", "7.5", "--out", str(out), "--generated", str(generated),
        ]
    )  # fmt: skip
    assert status == 0
    printed = capsys.readouterr().out
    assert "lateral deviation RMS (from 3 s)" in printed
    info = json.loads((out / "run.json").read_text())
    assert info["status"] == "ok"
    assert info["paths"][0]["points"] == [[0, 0], [5, 0], [5, 10]]
    (report,) = info["path_reports"]
    assert report["lateral_rms"] < 0.15
    assert report["lateral_max"] < 0.3
    assert report["progress"] > 8.0  # round the corner and 3 m up the second leg
    assert not report["closed"]  # an open path is covered in part, not in laps:
    assert f"({report['laps']:.3f} of its 15.000 m)" in printed
    tr = Trajectory.load(out)
    assert abs(tr.com[-1, 0] - 5.0) < 0.3 and tr.com[-1, 1] > 3.0
    assert math.degrees(tr.root_rpy[-1, 2]) == pytest.approx(90, abs=15)  # heading +y
    # the report is the trajectory's: recomputed from it, the same numbers
    again = path_report(tr, PathSpec.from_json(info["paths"][0]))
    assert again["lateral_rms"] == pytest.approx(report["lateral_rms"])
    assert main(["metrics", str(out), "--from", "3"]) == 0
    shown = capsys.readouterr().out
    assert f"lateral deviation RMS (from 3 s)         {report['lateral_rms']:.3f} m" in shown
    # and `legdsl plot` adds the top view for a run that followed a path
    assert main(["plot", str(out)]) == 0
    assert (out / "top.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
