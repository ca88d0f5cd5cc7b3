"""Modules a person can read in one sitting: at most about 500 lines, unless the module's
docstring says why it is longer (a line starting with "Long:")."""

from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[2] / "src" / "legdsl"
LIMIT = 520  # "about 500"


def test_no_module_is_long_without_a_reason() -> None:
    long = []
    for path in sorted(PACKAGE.rglob("*.py")):
        text = path.read_text(encoding="utf-8")
        lines = text.count("\n")
        doc = ast.get_docstring(ast.parse(text)) or ""
        if lines > LIMIT and not any(line.startswith("Long:") for line in doc.splitlines()):
            long.append(f"{path.relative_to(PACKAGE.parent)}: {lines} lines")
    assert not long, (
        "modules over ~500 lines without a 'Long:' reason in their docstring:\n" + "\n".join(long)
    )
