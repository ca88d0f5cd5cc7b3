"""The generated control modules name the .leg line of every value they compute: each
function's docstring lists its targets with the statement's place, the state's row first,
then each action it was inlined through. Every place named is a statement in that file."""

from __future__ import annotations

import os
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


def test_the_standard_library_is_named_alike_from_any_copy_of_legdsl(tmp_path: Path) -> None:
    """A compile's spawned workers may import legdsl from another copy than the one that read
    the .leg files (a source tree on the path, a Dask worker's install): the standard library
    is still 'stdlib/NAME' in the generated code. It was the file's bare name from a worker
    whose copy differed, so the goldens depended on which copy a worker had imported."""
    from legdsl.codegen.python.control import shown_file

    source = "creatures/kangaroo.leg"
    for copy in (STDLIB, tmp_path / "site-packages" / "legdsl" / "stdlib"):
        assert shown_file(str(copy.resolve() / "raibert.leg"), source) == "stdlib/raibert.leg"
    elsewhere = tmp_path / "mine" / "stdlib" / "raibert.leg"  # a user's own folder
    assert shown_file(str(elsewhere), source) == os.path.relpath(elsewhere.resolve())
    ours = STDLIB.resolve() / "nothing_of_ours.leg"
    assert shown_file(str(ours), source) == os.path.relpath(ours)


def test_the_docs_example_quotes_the_hoppers_generated_module() -> None:
    """docs/controllers.md shows the origins of the hopper's FLIGHT action: the lines it
    quotes are the generated module's own (a moved line in hopper.leg moves them)."""
    doc = (ROOT / "docs" / "controllers.md").read_text(encoding="utf-8")
    quoted = re.findall(r"^ {12}(\S+ +creatures/hopper\.leg:\S+ > \S+)$", doc, re.M)
    generated = (ROOT / "generated" / "hopper" / "control_hop.py").read_text(encoding="utf-8")
    assert len(quoted) == 2
    for line in quoted:
        assert f"        {line}\n" in generated, line


@pytest.mark.parametrize("module", MODULES, ids=lambda p: f"{p.parent.name}/{p.stem}")
def test_an_event_names_its_condition_not_the_state_keyword(module: Path) -> None:
    """An event's origin named its row's 'state' keyword (kneebiped.leg:55:5), not the
    condition the function computes: it names where the condition starts, which is the
    text its docstring shows."""
    text = module.read_text(encoding="utf-8")
    events = re.findall(r'def event_\w+\(s, u, p, r, tis\):\n    """.*? when: (.*?)\n(.*?)"""',
                        text, re.S)  # fmt: skip
    assert events
    for condition, doc in events:
        row = next(line for line in doc.splitlines() if line.strip().startswith("event "))
        file, line, col = PLACE.findall(row)[0]
        source = _text(file)[int(line) - 1]
        assert source[int(col) - 1 :].startswith(condition[:12]), (row, condition)
        assert not source[int(col) - 1 :].startswith("state "), row
