"""A waypoints file's first line with numbers and units ('3 km,4 km') was taken as a header
and that point dropped without a word, where the same text on line 2 was refused. Only a
line of words is a header; coordinates may be metres or lengths with their unit, and any
other field is refused at its line and column, with the line and a caret."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.ir.paths import read_waypoints
from legdsl.lang.errors import UsageError


def waypoints(tmp_path: Path, text: str) -> Path:
    csv = tmp_path / "wp.csv"
    csv.write_text(text)
    return csv


def test_a_first_line_of_numbers_with_units_is_the_first_point(tmp_path: Path) -> None:
    spec = read_waypoints(waypoints(tmp_path, "3 km,4 km\n5,0\n5,5\n"), "route")
    assert spec.points == ((3000.0, 4000.0), (5.0, 0.0), (5.0, 5.0))
    spec = read_waypoints(waypoints(tmp_path, "0,0\n50 cm, 2m\n"), "route")
    assert spec.points == ((0.0, 0.0), (0.5, 2.0))


def test_a_line_of_another_shape_is_told_in_one_line(tmp_path: Path) -> None:
    for text in ("0,0\n1,abc\n", "0 0;\n1,1\n"):
        with pytest.raises(UsageError, match=r"line \d is not 'x,y' \(two numbers in metres"):
            read_waypoints(waypoints(tmp_path, text), "route")


@pytest.mark.parametrize("header", ["x,y", "x1,y1", "east; north", "x [m],y [m]"])
def test_a_first_line_of_words_is_a_header(tmp_path: Path, header: str) -> None:
    spec = read_waypoints(waypoints(tmp_path, f"{header}\n0,0\n5,0\n"), "route")
    assert spec.points == ((0.0, 0.0), (5.0, 0.0))


@pytest.mark.parametrize(
    ("text", "said"),
    [
        ("3 s,4 km\n5,0\n", "wp.csv:1:1: '3 s' is a time (s), and a waypoint is a length"),
        ("0,0\n5, 0 kg\n", "wp.csv:2:4: '0 kg' is a mass (kg)"),
        ("0,0\n1,2 furlong\n", "wp.csv:2:3: '2 furlong' has the unknown unit 'furlong'"),
    ],
)
def test_a_field_that_is_no_length_is_refused_at_its_column(
    tmp_path: Path, text: str, said: str
) -> None:
    with pytest.raises(UsageError) as e:
        read_waypoints(waypoints(tmp_path, text), "route")
    message = str(e.value)
    assert said in message
    col = int(said.split(":")[2])
    line, caret = message.splitlines()[-2:]
    assert (
        caret.index("^") - 4 == col - 1
        and line.strip() == text.splitlines()[int(said.split(":")[1]) - 1]
    )
