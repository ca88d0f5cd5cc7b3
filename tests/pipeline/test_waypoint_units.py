"""A waypoints file's first line with numbers and units ('3 km,4 km') was taken as a header
and that point dropped without a word, where the same text on line 2 was refused. Only a
line of words is a header; coordinates may be metres or lengths with their unit, and any
other field is refused at its line and column, with the line and a caret.

A header's units ('x [cm],y [cm]', the style of the project's own trajectory.csv) were
ignored: 500 read 500 m, a path a hundred times too long, without a word. They are read
(a bare number in the column is in its unit) and checked: a unit that is not a length, one
legdsl does not know, or one column's without the other's is refused at its column. A quoted
first line of numbers ('"3","3"') was taken as a header and its point lost: it is a point.
Every line's mistake (another shape, a repeat, NaN, too far) is told at its line and column
with the line, a caret and what to write (it was told without a column)."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.ir.waypoints import read_waypoints
from legdsl.lang.errors import UsageError


def waypoints(tmp_path: Path, text: str) -> Path:
    csv = tmp_path / "wp.csv"
    csv.write_text(text)
    return csv


def refused(tmp_path: Path, text: str) -> tuple[str, int, int]:
    """The message, and the line and column its caret is under (checked against the line)."""
    with pytest.raises(UsageError) as e:
        read_waypoints(waypoints(tmp_path, text), "route")
    message = str(e.value)
    head, line, caret = message.splitlines()
    where = head.split(": ", 1)[0]
    n, col = (int(v) for v in where.split(":")[-2:])
    assert line.strip() == text.splitlines()[n - 1].strip()
    assert caret.index("^") - 4 == col - 1
    return message, n, col


def test_a_first_line_of_numbers_with_units_is_the_first_point(tmp_path: Path) -> None:
    spec = read_waypoints(waypoints(tmp_path, "3 km,4 km\n5,0\n5,5\n"), "route")
    assert spec.points == ((3000.0, 4000.0), (5.0, 0.0), (5.0, 5.0))
    spec = read_waypoints(waypoints(tmp_path, "0,0\n50 cm, 2m\n"), "route")
    assert spec.points == ((0.0, 0.0), (0.5, 2.0))


def test_a_quoted_first_line_of_numbers_is_the_first_point(tmp_path: Path) -> None:
    spec = read_waypoints(waypoints(tmp_path, '"3","3"\n5,0\n5,5\n'), "route")
    assert spec.points == ((3.0, 3.0), (5.0, 0.0), (5.0, 5.0))
    spec = read_waypoints(waypoints(tmp_path, '"x";"y"\n"0";"0"\n" 5 cm";"0"\n'), "route")
    assert spec.points == ((0.0, 0.0), (0.05, 0.0))


@pytest.mark.parametrize(
    ("text", "said", "at"),
    [
        ("0,0\n1,abc\n", "'abc' is not a number", (2, 3)),
        ("0 0;\n1,1\n", "'0 0' is not a number", (1, 1)),
        ("0 0\n5,0\n", "x and y are apart by a space, and a waypoint line is 'x,y'", (1, 3)),
        ("0,0\n5\n", "this line has x alone", (2, 2)),
        ("0,0\n5,\n", "y is missing", (2, 3)),
        ("0,0,0\n5,0,0\n", "this line has 3 fields", (1, 5)),
        ("x,y\n0,0\nx,y\n5,5\n", "only the file's first line may be a header", (3, 1)),
        ("0,0\n5,0\n 5,0\n", "repeats the one before it (line 2)", (3, 2)),
        ("0,0\nnan,0\n", "x is 'nan', not a finite number", (2, 1)),
        ("0,0\n1, inf\n", "y is 'inf', not a finite number", (2, 4)),
        ("0,0\n1e300,0\n", "x is more than 1e+09 m from the origin", (2, 1)),
        ("3 s,4 km\n5,0\n", "'3 s' is a time (s), and a waypoint is a length", (1, 1)),
        ("0,0\n5, 0 kg\n", "'0 kg' is a mass (kg)", (2, 4)),
        ("0,0\n1,2 furlong\n", "'2 furlong' has the unknown unit 'furlong'", (2, 3)),
    ],
)
def test_a_line_that_is_no_point_is_refused_at_its_column(
    tmp_path: Path, text: str, said: str, at: tuple[int, int]
) -> None:
    message, n, col = refused(tmp_path, text)
    assert said in message and (n, col) == at, message
    assert message.startswith(f"{tmp_path / 'wp.csv'}:{n}:{col}: ")


@pytest.mark.parametrize("header", ["x,y", "x1,y1", "east; north", "x [m],y [m]", '"x","y"'])
def test_a_first_line_of_words_is_a_header(tmp_path: Path, header: str) -> None:
    spec = read_waypoints(waypoints(tmp_path, f"{header}\n0,0\n5,0\n"), "route")
    assert spec.points == ((0.0, 0.0), (5.0, 0.0))


@pytest.mark.parametrize(
    ("header", "points"),
    [
        ("x [cm],y [cm]", ((0.0, 0.0), (5.0, 0.0), (5.0, 5.0))),
        ("x [mm]; y [mm]", ((0.0, 0.0), (0.5, 0.0), (0.5, 0.5))),
        ("east (km),north (km)", ((0.0, 0.0), (5e5, 0.0), (5e5, 5e5))),
    ],
)
def test_a_headers_units_are_its_columns(
    tmp_path: Path, header: str, points: tuple[tuple[float, float], ...]
) -> None:
    spec = read_waypoints(waypoints(tmp_path, f"{header}\n0,0\n500,0\n500,500\n"), "route")
    assert spec.points == points
    # a field's own unit is its own
    spec = read_waypoints(waypoints(tmp_path, "x [cm],y [cm]\n0,0\n5 m,50\n"), "route")
    assert spec.points == ((0.0, 0.0), (5.0, 0.5))


@pytest.mark.parametrize(
    ("header", "said", "col"),
    [
        ("x [s],y [s]", "the header's unit 's' is a time (s), and a waypoint is a length", 4),
        ("x (feet),y (feet)", "the header's unit 'feet' is not one legdsl reads", 4),
        ("x [cm],y", "write 'y [cm]', or take the units out of the header", 8),
    ],
)
def test_a_headers_unit_that_is_no_length_is_refused_at_its_column(
    tmp_path: Path, header: str, said: str, col: int
) -> None:
    message, n, at = refused(tmp_path, f"{header}\n0,0\n5,0\n")
    assert said in message and (n, at) == (1, col), message


def test_a_file_with_no_points_says_so(tmp_path: Path) -> None:
    with pytest.raises(UsageError, match=r"got 0 \(the file is empty\)"):
        read_waypoints(waypoints(tmp_path, ""), "route")
    with pytest.raises(UsageError, match=r"at least 2 points, got 1;"):
        read_waypoints(waypoints(tmp_path, "x,y\n0,0\n"), "route")
