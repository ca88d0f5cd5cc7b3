"""The headers of the generated files say what is true of them: docs/compiler.md says sympy
is named in every header, and only the .py files named it (dynamics.c, dynamics.h,
dynamics_some.c and control_*.c did not); dynamics_some.c's header copied dynamics.c's 'Each
function writes its result ... into out', though its functions write only the parts asked for."""

from __future__ import annotations

from pathlib import Path

import pytest
import sympy

ROOT = Path(__file__).resolve().parents[2]
FILES = sorted(
    p
    for p in (ROOT / "generated").glob("*/*")
    if p.suffix in (".py", ".c", ".h") and p.stem != "__init__"
)


@pytest.mark.parametrize("path", FILES, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_every_header_names_sympy(path: Path) -> None:
    head = "\n".join(path.read_text(encoding="utf-8").split("\n")[:2])
    assert f"sympy {sympy.__version__}" in head


@pytest.mark.parametrize("creature", sorted(p.parent.name for p in FILES))
def test_the_some_twins_header_says_they_write_the_parts_asked_for(creature: str) -> None:
    text = (ROOT / "generated" / creature / "dynamics_some.c").read_text(encoding="utf-8")
    header = text.split("*/", 1)[0]
    assert "writes its result" not in header
    assert "writes the parts of its result that want asks for" in header
    assert "leaving the rest of out as it was" in header
