"""The sizes docs/compiler.md and docs/language.md give of the shipped files: the generated
dynamics modules' lines and the .leg files' lines, counted in the files, so that a change that
grows or shrinks one updates the doc (compiler.md said 1437 lines when the file had 1809)."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_the_size_table_counts_the_golden_modules_lines() -> None:
    doc = (ROOT / "docs" / "compiler.md").read_text(encoding="utf-8")
    section = doc.split("## Size and speed", 1)[1]
    rows = re.findall(r"^\| (\w+) \| \d+ \| [^|]+ \| (\d+) \|", section, re.M)
    assert [name for name, _ in rows] == ["kangaroo", "biped", "quadruped"]
    for name, lines in rows:
        module = ROOT / "generated" / name / "dynamics.py"
        assert int(lines) == len(module.read_text(encoding="utf-8").splitlines()), name


def test_the_speed_table_counts_the_creatures_lines() -> None:
    """language.md's "Speed" table gives each shipped file's lines (it said 89 for a
    quadruped.leg of 535)."""
    doc = (ROOT / "docs" / "language.md").read_text(encoding="utf-8")
    section = doc.split("## Speed", 1)[1]
    rows = re.findall(r"^\| `(\w+)\.leg` [^|]+ \| (\d+) \|", section, re.M)
    assert [name for name, _ in rows] == ["kangaroo", "biped", "quadruped"]
    for name, lines in rows:
        source = ROOT / "creatures" / f"{name}.leg"
        assert int(lines) == len(source.read_text(encoding="utf-8").splitlines()), name
