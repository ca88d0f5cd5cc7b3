"""docs/language.md stays true: its complete examples check, its quoted errors are real."""

from __future__ import annotations

import re
from pathlib import Path

from legdsl.check.source import check_file
from legdsl.lang.syntax_errors import friendly_errors
from legdsl.lang.units import UNITS

ROOT = Path(__file__).resolve().parents[2]
DOC = (ROOT / "docs" / "language.md").read_text(encoding="utf-8")


def test_leg_examples_in_the_reference_check(tmp_path: Path) -> None:
    blocks = re.findall(r"^```leg\n(.*?)^```", DOC, flags=re.S | re.M)
    assert blocks
    for i, block in enumerate(blocks):
        path = tmp_path / f"example{i}.leg"
        path.write_text(block, encoding="utf-8")
        assert check_file(path)


def test_quoted_errors_are_in_the_bad_input_corpus() -> None:
    quoted = re.findall(r"^> error: (.*)$", DOC, flags=re.M)
    assert len(quoted) >= 40
    corpus = {
        line.split(": error: ", 1)[1]
        for path in (ROOT / "tests" / "bad").glob("*.expected")
        for line in path.read_text(encoding="utf-8").splitlines()
    }
    assert [q for q in quoted if q not in corpus] == []


def test_every_unit_and_every_friendly_message_is_documented() -> None:
    assert [u for u in UNITS if f"`{u}`" not in DOC] == []
    assert [m for m, _ in friendly_errors() if f"> error: {m}\n" not in DOC] == []


def test_the_standard_library_table_gives_every_action_with_its_parameters() -> None:
    """docs/controllers.md names each action of stdlib/raibert.leg with the parameters it
    takes, in order (a user calls it from that table)."""
    library = (ROOT / "src" / "legdsl" / "stdlib" / "raibert.leg").read_text(encoding="utf-8")
    actions = {
        name: [p.strip() for p in params.split(",")]
        for name, params in re.findall(r"^action\s+(\w+)\s*\(([^)]*)\)", library, flags=re.M)
    }
    table = (ROOT / "docs" / "controllers.md").read_text(encoding="utf-8")
    documented = {
        name: [p.strip() for p in params.split(",")]
        for name, params in re.findall(r"`(\w+)\(([^)`]*)\)`", table)
        if name in actions
    }
    assert documented == actions


def test_the_action_example_checks_in_the_hopper(tmp_path: Path) -> None:
    """The example under "### Actions" checks in a controller of the shipped hopper, with
    the alias and the names it reads (it added a length to an angle)."""
    example = re.search(r"### Actions\n\n((?:    .*\n)+)", DOC)
    assert example is not None
    action = example.group(1).replace("action place_foot(", "action place_foot_doc(")
    hopper = (ROOT / "creatures" / "hopper.leg").read_text(encoding="utf-8")
    hopper = hopper.replace("hip_motor = hip_motor\n", "hip_motor = hip_motor, hip = hip_servo\n")
    hopper = hopper.replace("  roles active = main\n", "  roles active = main\n" + action)
    placed = "place_foot(active, speed_aim + speed_trim, k_speed, stance_guess)"
    hopper = hopper.replace(placed, "place_foot_doc(active)")
    assert "place_foot_doc(active)" in hopper and "hip = hip_servo" in hopper
    path = tmp_path / "hopper.leg"
    path.write_text(hopper, encoding="utf-8")
    assert check_file(path)
