"""Paths no one wrote, through the path follower: random polylines (repeated points, very short
segments, hairpins, self-crossing, two points, collinear, far and near), circles of tiny and huge
radius either way round, squares, polygons, and CSV waypoint files (blank lines, a header,
Windows line endings, a byte-order mark), starting behind, on or far from the creature.

Each is followed by the biped's ``run`` (every fourth by the 3D quadruped's ``trot``, every
fifth by the creature scaled by 0.5 or 4 as ``--scale`` runs it) for a short run on both
backends: the run ends ok, fell or diverged (never an internal error), the C and Python runs are
the same bit for bit, and the path's geometry (run.json's ``paths``, the top view's and the
exports' points, the projection of the track) is finite. A path the language refuses is told at
a caret or in one line that says how to fix it.

    LEGDSL_RANDOM_PATHS=100 LEGDSL_RANDOM_PATH_SEED=0 pytest tests/sim/test_random_paths.py
"""

from __future__ import annotations

import dataclasses
import json
import math
import os
from pathlib import Path

import numpy as np
import pytest
from conftest import CREATURES, GENERATED
from runtime_helpers import assert_same, legdsl_in_process, needs_c_compiler
from seeded import told_with_seed

from legdsl.export.motion import path_points
from legdsl.ir.paths import PathSpec
from legdsl.lang.errors import UsageError
from legdsl.pipeline.path_option import parse_path_option
from legdsl.pipeline.session import Run, RunSession
from legdsl.sim.path_tracking import PathGeometry
from legdsl.sim.run_loop import RunOptions

pytestmark = needs_c_compiler

COUNT = int(os.environ.get("LEGDSL_RANDOM_PATHS", "2"))
FIRST = int(os.environ.get("LEGDSL_RANDOM_PATH_SEED", "0"))
SEEDS = range(FIRST, FIRST + COUNT)
DURATION = 1.0
STATUSES = ("ok", "fell", "diverged")


# ---------------------------------------------------------------- drawing


def _num(v: float) -> str:
    return repr(float(v))


def _scale(rng: np.random.Generator) -> float:
    """A path's size: near (1 mm) to far (1 km), now and then very short or very long."""
    return float(rng.choice([1e-3, 0.05, 1.0, 5.0, 40.0, 1e3, 10 ** rng.uniform(-9, 6)]))


def _offset(rng: np.random.Generator) -> np.ndarray:
    """Where the path starts: on the creature (the origin), behind it, beside it or far away."""
    where = rng.choice(["on", "behind", "beside", "far"])
    if where == "on":
        return np.zeros(2)
    if where == "behind":
        return np.array([-rng.uniform(0.1, 5.0), 0.0])
    if where == "beside":
        return np.array([0.0, rng.uniform(-3.0, 3.0)])
    return rng.uniform(-1.0, 1.0, 2) * 10 ** rng.uniform(3, 9)


def _polyline_points(rng: np.random.Generator) -> list[tuple[float, float]]:
    scale = _scale(rng)
    kind = rng.choice(
        ["random", "hairpin", "cross", "two", "collinear", "short", "repeat", "far_short"]
    )
    if kind == "far_short":  # a short last segment after a kilometre or up to 2e9 m of path
        far = 10 ** rng.uniform(3, 9)
        tiny = rng.normal(size=2) * 10 ** rng.uniform(-11.5, -6)
        return [(-far, 0.0), (0.0, 0.0), (float(tiny[0]), float(tiny[1]))]
    if kind == "two":
        pts = rng.normal(size=(2, 2)) * scale
    elif kind == "hairpin":  # out and back: a 180 degree turn, the return beside or on it
        a, b = np.zeros(2), rng.normal(size=2) * scale
        back = np.array([-(b[1]), b[0]]) * rng.choice([0.0, 1e-9, 1e-3])
        pts = np.array([a, b, a + back])
    elif kind == "cross":  # a bow tie
        pts = np.array([[0, 0], [1, 1], [1, 0], [0, 1]], float) * scale
    elif kind == "collinear":  # along one line, sometimes doubling back on it
        direction = rng.normal(size=2)
        ts = np.cumsum(rng.uniform(-0.5, 1.0, rng.integers(3, 7)))
        pts = np.outer(ts, direction) * scale
    elif kind == "short":  # very short segments between ordinary ones
        pts = rng.normal(size=(rng.integers(3, 6), 2)) * scale
        i = int(rng.integers(0, len(pts) - 1))
        tiny = rng.normal(size=2) * 10 ** rng.uniform(-11.5, -4)
        pts = np.insert(pts, i + 1, pts[i] + tiny, axis=0)
    elif kind == "repeat":  # a point again later on (not right after itself)
        pts = rng.normal(size=(rng.integers(3, 6), 2)) * scale
        pts = np.vstack([pts, pts[:1], pts[1:2] * 0.5])
    else:
        pts = rng.normal(size=(rng.integers(2, 9), 2)) * scale
    pts = pts + _offset(rng)
    return [(float(x), float(y)) for x, y in pts]


def _distinct(pts: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """The points without a repeat of the one before (the language refuses those)."""
    out = [pts[0]]
    for p in pts[1:]:
        if math.dist(p, out[-1]) > 1e-11:
            out.append(p)
    return out


def _lookahead(rng: np.random.Generator) -> str:
    if rng.random() < 0.6:
        return ""
    return f", lookahead = {_num(10 ** rng.uniform(-4, 3))} m"


def draw_path(seed: int) -> tuple[str, str | None]:
    """A path text for ``--path`` and, for a waypoints file, that file's text."""
    rng = np.random.default_rng(seed)
    shape = rng.choice(["polyline", "polyline", "circle", "square", "polygon", "csv"])
    if shape == "circle":
        c = _offset(rng)
        radius = 10 ** rng.uniform(-11.9, 9) if rng.random() < 0.5 else rng.uniform(0.5, 20)
        turn = rng.choice(["left", "right"])
        text = (f"circle(center = ({_num(c[0])}, {_num(c[1])}) m, radius = {_num(radius)} m, "
                f"turn = {turn}{_lookahead(rng)})")  # fmt: skip
        return text, None
    if shape == "square":
        c = _offset(rng) / 2  # its corners within 1e9 m (a side is at most 1e8 m)
        side = min(_scale(rng), 1e8)
        turn = rng.choice(["left", "right"])
        text = (f"square(corner = ({_num(c[0])}, {_num(c[1])}) m, side = {_num(side)} m, "
                f"turn = {turn}{_lookahead(rng)})")  # fmt: skip
        return text, None
    pts = _distinct(_polyline_points(rng))
    if shape == "polygon":
        while len(pts) > 2 and math.dist(pts[0], pts[-1]) <= 1e-11:
            pts.pop()
        if len(pts) < 3:
            pts = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)]
    if len(pts) < 2:
        pts = [pts[0], (pts[0][0] + 1.0, pts[0][1])]
    if shape == "csv":
        return "waypoints.csv", _csv(rng, pts)
    listed = ", ".join(f"({_num(x)}, {_num(y)}) m" for x, y in pts)
    return f"{shape}({listed}{_lookahead(rng)})", None


def _csv(rng: np.random.Generator, pts: list[tuple[float, float]]) -> str:
    """The points as a waypoints file, written as a spreadsheet or an editor might."""
    forms = ["{x!r},{y!r}", " {x!r} ; {y!r} ", "\t{x!r},\t{y!r}", "{x!r},{y!r}  # a note"]
    lines = [str(rng.choice(forms)).format(x=x, y=y) for x, y in pts]
    if rng.random() < 0.5:
        lines.insert(0, "x,y")
    for _ in range(int(rng.integers(0, 3))):
        lines.insert(int(rng.integers(1, len(lines) + 1)), rng.choice(["", "   ", "# a note"]))
    newline = "\r\n" if rng.random() < 0.5 else "\n"
    text = newline.join(lines) + (newline if rng.random() < 0.5 else "")
    return ("\ufeff" if rng.random() < 0.2 else "") + text


# ---------------------------------------------------------------- running


@pytest.fixture(scope="module")
def sessions() -> dict[str, RunSession]:
    return {
        name: RunSession.from_file(CREATURES / f"{name}.leg", generated=GENERATED)
        for name in ("biped", "quadruped")
    }


def _finite_geometry(spec: PathSpec, run: Run) -> None:
    """run.json's paths, the top view's and the exports' points, the track's projection."""
    info = run.info()
    json.dumps(info["paths"], allow_nan=False)
    json.dumps(info["path_reports"], allow_nan=False)
    (written,) = [PathSpec.from_json(p) for p in info["paths"]]
    assert dataclasses.replace(written, name="") == spec  # named by the controller's path
    # its text reads back as the path (it was rounded to 6 digits: 1000.0001 m read 1000 m)
    again = parse_path_option(info["paths"][0]["text"])
    assert (again.points, again.center, again.radius, again.turn, again.lookahead) == (
        spec.points,
        spec.center,
        spec.radius,
        spec.turn,
        spec.lookahead,
    )
    geometry = PathGeometry(spec)
    assert math.isfinite(geometry.length) and geometry.length > 0
    s = np.linspace(0.0, geometry.length, 400)  # as the top view draws it
    assert np.isfinite([geometry.at(float(v)) for v in s]).all()
    assert np.isfinite(path_points(spec, ())).all()
    com = run.result.trajectory.com
    hits = [geometry.project(float(x), float(y)) for x, y in com[:: max(1, len(com) // 50), :2]]
    assert np.isfinite([(h.s, h.x, h.y, h.heading, h.lateral) for h in hits]).all()


def follow(sessions: dict[str, RunSession], seed: int, tmp: Path) -> None:
    text, csv = draw_path(seed)
    if csv is not None:
        (tmp / text).write_bytes(csv.encode("utf-8"))
        text = str(tmp / text)
    spec = parse_path_option(text)
    name, controller, settings = ("biped", "run", ["speed=1.5m/s"])
    if seed % 4 == 3:
        name, controller, settings = ("quadruped", "trot", [])
    # every fifth for the creature scaled (--scale): the path given at that size
    scale = [None, None, None, None, 0.5, None, None, None, None, 4.0][seed % 10]
    sess = sessions[name]
    opts = RunOptions(duration=DURATION)
    python, c = (
        sess.run(controller, settings, [spec], options=opts, scale=scale, backend=backend)
        for backend in ("python", "c")
    )
    assert python.status in STATUSES, python.result.message
    assert "internal error" not in python.result.message
    assert_same(python.result, c.result)
    _finite_geometry(spec, python)


@pytest.mark.parametrize("seed", SEEDS)
def test_a_random_path_is_followed_the_same_on_both_backends(
    sessions: dict[str, RunSession], seed: int, tmp_path: Path
) -> None:
    text, csv = draw_path(seed)
    with told_with_seed(
        f"random path seed {seed}",
        f"LEGDSL_RANDOM_PATHS=1 LEGDSL_RANDOM_PATH_SEED={seed}",
        lambda: f"--path {text}" + (f"\nwaypoints file: {csv!r}" if csv else ""),
    ):
        follow(sessions, seed, tmp_path)


# ---------------------------------------------------------------- hand-picked

HAND_PICKED = [
    # a last segment (1e-8 m) lost in the arclength after 1e9 m of path: the look-ahead at
    # the end divided by zero and the run "diverged" at 0 s on both backends
    "polyline((-1e9, 0) m, (0, 0) m, (1e-8, 0) m)",
    "polygon((-1e9, 0) m, (0, 0) m, (1e-8, 0) m, (0, 1) m)",
    # the smallest circle there is, with the longest look-ahead: 1e21 rad round it
    "circle(center = (0, 0) m, radius = 1.1e-12 m, turn = right, lookahead = 1e9 m)",
    "circle(center = (1e9, -1e9) m, radius = 1e9 m, turn = left)",
    "square(corner = (999999999, 1e9) m, side = 1e-6 m, turn = right)",
]


@pytest.mark.parametrize("text", HAND_PICKED)
def test_a_hand_picked_path_is_followed_the_same_on_both_backends(
    sessions: dict[str, RunSession], text: str
) -> None:
    spec = parse_path_option(text)
    opts = RunOptions(duration=0.5)
    runs = [
        sessions["biped"].run("run", ["speed=1.5m/s"], [spec], options=opts, backend=backend)
        for backend in ("python", "c")
    ]
    assert runs[0].status == "ok", runs[0].result.message
    assert_same(runs[0].result, runs[1].result)
    _finite_geometry(spec, runs[0])


@pytest.mark.parametrize(
    "text", ["square(corner = (0, 0) m, side = 2e-12 m)", "polyline((0, 0) m, (2e-12, 0) m)"]
)
def test_a_path_for_the_scaled_creature_keeps_its_sides(
    sessions: dict[str, RunSession], text: str
) -> None:
    """Given for the creature 4 times the size, its 2e-12 m sides are 5e-13 m for the model:
    under SAME_POINT, which the tracker dropped to no segment at all (an internal error)."""
    spec = parse_path_option(text)
    opts = RunOptions(duration=0.05)
    runs = [
        sessions["biped"].run("run", [], [spec], options=opts, scale=4.0, backend=backend)
        for backend in ("python", "c")
    ]
    assert runs[0].status == "ok", runs[0].result.message
    assert_same(runs[0].result, runs[1].result)
    json.dumps(runs[0].info(), allow_nan=False)


def test_the_top_view_draws_a_path_far_and_small(tmp_path: Path) -> None:
    path = "polyline((-1e9, 0) m, (0, 0) m, (1e-8, 0) m)"
    argv = ["run", str(CREATURES / "biped.leg"), "--controller", "run", "--path", path]
    argv += ["--time", "0.2", "--generated", str(GENERATED), "--out", str(tmp_path / "run")]
    assert legdsl_in_process(argv)[0] == 0
    assert legdsl_in_process(["plot", str(tmp_path / "run"), "--top"]) == (0, "")
    assert (tmp_path / "run" / "top.png").stat().st_size > 0


# ---------------------------------------------------------------- refused


REFUSED = [  # (the --path text, what the message must say)
    ("polyline((0, 0) m)", "at least 2 points"),
    ("polygon((0, 0) m, (1, 0) m)", "at least 3 points"),
    ("polyline((0, 0) m, (0, 0) m, (1, 0) m)", "remove the repeat"),
    ("circle(center = (0, 5) m, radius = -5 m)", "must be positive"),
    ("circle(center = (0, 5) s, radius = 5 m)", "center"),
    ("circle(center = (0, 5) m, radius = 5 m, turn = up)", "left (counter-clockwise)"),
    ("square(corner = (0, 0) m, side = 8 kg)", "side"),
    ("polyline((0, 0) m, (2e9, 0) m)", "within 1e+09 m"),
    # a radius or side under 1e-12 m is a point: 5e-324 m diverged with a math domain error
    ("circle(center = (0, 0) m, radius = 5e-324 m)", "must be more than 1e-12 m"),
    ("square(corner = (0, 0) m, side = 1e-13 m)", "must be more than 1e-12 m"),
    # a side lost in the rounding of a far corner: one point, an internal error
    ("square(corner = (1e9, 0) m, side = 1e-8 m)", "give a longer side or a nearer corner"),
    # its corners past 1e9 m, where a polygon's are refused (and its text, a polygon, was)
    ("square(corner = (1e9, 0) m, side = 1 m)", "give a shorter side or a corner nearer"),
    # a look-ahead past 1e9 m: NaN ahead of a small circle (diverged at 0 s)
    ("circle(center = (0, 0) m, radius = 1e-9 m, lookahead = 1e300 m)", "at most 1e+09 m"),
    ("ellipse(center = (0, 0) m)", "unknown path shape"),
    # a path's point is (x, y) on the ground: it said "(x, z) in a planar creature"
    ("circle(center = (0, 0, 0) m, radius = 1 m)", "2 components (x, y on the ground), got 3"),
    ("polyline((0, 0) m, (1, 2, 3) m)", "2 components (x, y on the ground), got 3"),
    # it said "must be a number with a unit of no unit"
    ("polyline((0, 0) m, (nan, 0) m)", "(the unit is after ')') must be a number\n"),
    ("", "empty value"),
    ("route = ", "gives no path"),
]


@pytest.mark.parametrize(("text", "said"), REFUSED)
def test_a_path_the_language_refuses_is_told_with_its_place(
    text: str, said: str, tmp_path: Path
) -> None:
    argv = ["run", str(CREATURES / "biped.leg"), "--controller", "run", "--path", text]
    argv += ["--time", "0.01", "--generated", str(GENERATED), "--out", str(tmp_path / "run")]
    code, err = legdsl_in_process(argv)
    assert code == 2, err
    assert said in err, err
    assert "Traceback" not in err and "internal error" not in err, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 or (lines[0].startswith("--path:1:") and "^" in lines[-1]), err


WAYPOINTS_REFUSED = [  # (a waypoints file, what the message must say, and where: line:col)
    ("x,y\r\n1,2\r\n", "at least 2 points", None),
    ("\n\n# nothing\n", "give one 'x,y' line (metres) per point", None),
    ("0,0\n1,0\n1,0\n", "repeats the one before it", "3:1"),
    ("0,0\n1,nan\n", "not a finite number", "2:3"),
    ("0,0\n1,2,3\n", "this line has 3 fields", "2:5"),
    ("0,0,0\n1,1\n2,2\n", "this line has 3 fields", "1:5"),  # numbers only: not a header
    ("0 0\n5,0\n5,5\n", "apart by a space", "1:3"),  # so too with spaces (it was dropped)
    ("0\t0;\n5,0\n5,5\n", "'0\t0' is not a number", "1:1"),
    ("0,0\n5e9,0\n", "from the origin", "2:1"),
]


@pytest.mark.parametrize(("content", "said", "where"), WAYPOINTS_REFUSED)
def test_a_waypoints_file_the_runtime_refuses_is_told_at_its_place(
    content: str, said: str, where: str | None, tmp_path: Path
) -> None:
    """Told in one line where the file has too few points, else at the line and column (it
    was one line without a column), with the line and a caret under the column."""
    (tmp_path / "w.csv").write_bytes(content.encode())
    with pytest.raises(UsageError) as told:
        parse_path_option(str(tmp_path / "w.csv"))
    message = str(told.value)
    assert said in message, message
    if where is None:
        assert "\n" not in message
        return
    head, line, caret = message.splitlines()
    n, col = (int(v) for v in where.split(":"))
    assert head.startswith(f"{tmp_path / 'w.csv'}:{where}: ")
    assert line[4:] == content.splitlines()[n - 1] and caret.index("^") == 4 + col - 1


@pytest.mark.parametrize(
    ("name", "content"),
    [
        ("w.csv", "# my route, exported\r\n\r\nx,y\r\n0,0\r\n1,0\r\n"),  # header after a note
        ("W.CSV", "0,0\n1,0\n"),  # was parsed as a shape: "unexpected '.'"
        ("route.tsv", "0;0\n1;0\n"),  # any file without a shape's '('
    ],
)
def test_a_waypoints_file_is_read_as_a_spreadsheet_writes_it(
    name: str, content: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    (tmp_path / name).write_bytes(content.encode())
    monkeypatch.chdir(tmp_path)
    assert parse_path_option(name).points == ((0.0, 0.0), (1.0, 0.0))


def test_a_device_given_as_waypoints_is_told_so() -> None:
    """It said "no such file /dev/null": it is there, and is no file of waypoints."""
    with pytest.raises(UsageError, match="/dev/null is a character device, not a file of way"):
        parse_path_option("/dev/null")


def test_a_directory_given_as_waypoints_is_told_so(tmp_path: Path) -> None:
    (tmp_path / "d.csv").mkdir()
    with pytest.raises(UsageError, match="is a directory; give a file of 'x,y' lines"):
        parse_path_option(str(tmp_path / "d.csv"))
