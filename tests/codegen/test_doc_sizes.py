"""docs/compiler.md's "Size and speed" table gives each shipped creature's generated
dynamics module in lines: the count of the golden file, so a change of the printer that
grows or shrinks it updates the doc (the table said 1437 lines when the file had 1809)."""

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
