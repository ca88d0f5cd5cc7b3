"""docs/runtime.md's Options table lists every option of ``legdsl run --help`` (it left out
--controller, --creature, --path, --backend, --generated and --animate); its example of a run
whose creature changed is the message the readers give (it lacked the --time the message has);
and docs/compiler.md counts the shipped creatures whose modules are checked in (it said three
of four)."""

from __future__ import annotations

import argparse
import re
import shutil
from pathlib import Path

import pytest
from conftest import CREATURES, ROOT

from legdsl.cli import _parser, main

NUMBERS = {3: "three", 4: "four", 5: "five", 6: "six"}


def _doc(name: str) -> str:
    return (ROOT / "docs" / name).read_text(encoding="utf-8")


def test_the_options_table_has_a_row_for_each_option_of_run() -> None:
    (sub,) = [a for a in _parser()._actions if isinstance(a, argparse._SubParsersAction)]
    flags = {s for a in sub.choices["run"]._actions for s in a.option_strings}
    section = _doc("runtime.md").split("\n## Options\n", 1)[1].split("\n## ", 1)[0]
    firsts = [line.split(" | ", 1)[0] for line in section.splitlines() if line.startswith("| `")]
    listed = {m for first in firsts for m in re.findall(r"--[a-z-]+", first)}
    assert flags - {"-h", "--help", "-o"} - listed == set()


def test_compiler_md_counts_the_shipped_creatures() -> None:
    names = sorted(p.stem for p in CREATURES.glob("*.leg"))
    said = f"The {NUMBERS[len(names)]} shipped creatures' modules ({', '.join(names)})"
    assert said in " ".join(_doc("compiler.md").split())


def test_the_changed_creature_example_is_the_message_given(
    generated: Path,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:
    (example,) = [line.strip() for line in _doc("runtime.md").splitlines()
                  if "has changed since the run in runs/hopper was recorded" in line]  # fmt: skip
    command = re.search(r"\(legdsl (run .*?)\)$", example)
    assert command is not None, example
    monkeypatch.chdir(tmp_path)
    (tmp_path / "creatures").mkdir()
    shutil.copy(CREATURES / "hopper.leg", tmp_path / "creatures")
    argv = command.group(1).split()
    # the modules in ./generated, the default: the command given then names no --generated
    shutil.copytree(generated / "hopper", tmp_path / "generated" / "hopper")
    assert main(argv) == 0
    leg = tmp_path / "creatures" / "hopper.leg"
    leg.write_text(leg.read_text().replace("mass 10 kg", "mass 11 kg", 1))
    capsys.readouterr()
    assert main(["metrics", "runs/hopper"]) == 2
    assert example in capsys.readouterr().err.splitlines()
