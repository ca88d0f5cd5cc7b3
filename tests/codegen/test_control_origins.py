"""The generated control modules name the .leg line of every value they compute: each
function's docstring lists its targets with the statement's place, the state's row first,
then each action it was inlined through. Every place named is a statement in that file."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from legdsl.check.values import STDLIB

ROOT = Path(__file__).resolve().parents[2]
MODULES = sorted((ROOT / "generated").glob("*/control_*.py"))
PLACE = re.compile(r"(?P<file>[^\s:>]+):(?P<line>\d+):(?P<col>\d+)")


def _text(file: str) -> list[str]:
    path = STDLIB / file.removeprefix("stdlib/") if file.startswith("stdlib/") else ROOT / file
    return path.read_text(encoding="utf-8").split("\n")


@pytest.mark.parametrize("module", MODULES, ids=lambda p: f"{p.parent.name}/{p.stem}")
def test_every_value_names_its_statement(module: Path) -> None:
    text = module.read_text(encoding="utf-8")
    functions = re.findall(r'def (\w+)\(s, u, p, r, tis\):\n    """(.*?)"""', text, re.S)
    assert functions
    for name, doc in functions:
        first, _, rest = doc.partition("\n")
        listed = [line.strip() for line in rest.split("From the .leg file:")[-1].splitlines()
                  if line.strip()]  # fmt: skip
        if name.startswith("action_"):
            targets = first.split(": ", 1)[1].rstrip(".")
            expected = [] if targets == "nothing" else re.split(r", (?![^()]*\))", targets)
            assert [re.split(r"\s{2,}", row)[0] for row in listed] == expected, name
        for row in listed:
            places = PLACE.findall(row)
            assert places, row
            for file, line, col in places:
                source = _text(file)[int(line) - 1]
                word = source[int(col) - 1 :]
                assert re.match(r"[A-Za-z_]", word), f"{row}: {file}:{line}:{col} is {word!r}"
