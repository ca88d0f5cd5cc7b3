"""A vector's unknown unit, '(0, 5) ft', told as a number's is ('2 ft'): at the unit, with
the vector to write in legdsl's units; it was taken for a decimal comma ('0,0') or a
missing ',' before the unit, or, in a body, for a word too many."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.check.source import check_file
from legdsl.lang.errors import LegError
from legdsl.lang.parser import parse, parse_value

ROOT = Path(__file__).resolve().parents[2]
CREATURE = (ROOT / "tests" / "bad" / "ctl_dim_comparison.leg").read_text().split("controller")[0]
FT = "'ft' is not a unit legdsl knows; it writes lengths in m, cm, mm, km: write "


def _first(text: str, value: bool = False) -> tuple[int, int, str]:
    with pytest.raises(LegError) as info:
        parse_value(text, "--path") if value else parse(text, "f.leg")
    d = info.value.diagnostics[0]
    return d.span.col, d.span.end_col - d.span.col, d.message


@pytest.mark.parametrize(
    ("shape", "col", "message"),
    [
        ("polyline((0,0) ft, (5,0) ft)", 16, FT + "'(0, 0) m'"),  # was: '0,0': a decimal...
        ("polyline((0, 0) ft, (5, 0) ft)", 17, FT + "'(0, 0) m'"),  # was: a ',' is missing
        ("circle(center = (0, 5) ft, radius = 2 m)", 24, FT + "'(0, 1.524) m'"),
        ("polyline((-1.5, 2e1) ft, (5, 0) m)", 22, FT + "'(-0.4572, 6.096) m'"),
    ],
)
def test_a_path_given_on_the_command_line(shape: str, col: int, message: str) -> None:
    assert _first(shape, value=True) == (col, 2, message)


def test_a_misspelt_unit_after_a_vector_is_told_its_spelling() -> None:
    col, width, message = _first("polyline((0, 0) meters, (5, 0) m)", value=True)
    assert (col, width) == (17, 6)
    assert (
        message.startswith("'meters' is not a unit legdsl knows") and "did you mean 'm'" in message
    )


def test_a_path_in_a_file() -> None:
    text = CREATURE + "controller hop {\n  path track = polyline((0,0) ft, (5,0) ft)\n}\n"
    line = CREATURE.count("\n") + 2
    with pytest.raises(LegError) as info:
        parse(text, "f.leg")
    d = info.value.diagnostics[0]
    assert (d.span.line, d.span.col, d.message) == (line, 31, FT + "'(0, 0) m'")


@pytest.mark.parametrize("after", ["\n", "  mass 3 kg\n"])
def test_a_bodys_vector(tmp_path: Path, after: str) -> None:
    """Before the next line's property (read as the unit's value) or the next on its line."""
    text = CREATURE.replace(
        "body trunk free { mass 3 kg  inertia 0.03 kg*m^2 }",
        "body trunk free {\n    inertia (0.03, -0.03, 0.002) kg*ft^2" + after + "    com 0 m\n  }",
    )
    assert "kg*ft^2" in text
    path = tmp_path / "f.leg"
    path.write_text(text)
    with pytest.raises(LegError) as info:
        check_file(path)
    d = info.value.diagnostics[0]
    assert (d.span.line, d.span.col) == (5, 34)
    assert d.message == (
        "'kg*ft^2' is not a unit legdsl knows: it has no 'ft'; it writes lengths in m, cm, mm, "
        "km: write '(0.0027870912, -0.0027870912, 0.0001858061) kg*m^2'"
    )


def test_a_bodys_vector_with_units_run_together(tmp_path: Path) -> None:
    text = CREATURE.replace("inertia 0.03 kg*m^2", "inertia (0.03, 0.03) kgm2  com 0 m")
    path = tmp_path / "f.leg"
    path.write_text(text)
    with pytest.raises(LegError) as info:
        check_file(path)
    message = info.value.diagnostics[0].message
    assert message.startswith("'kgm2' is not a unit legdsl knows"), message
