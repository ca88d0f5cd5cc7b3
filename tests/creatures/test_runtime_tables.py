"""The biped gallop's rows of docs/runtime.md's tables "How much a run depends on its last bits"
and "How robust the shipped gaits are" come out of the scripts the doc names
(docs/scripts/last_bits.py, robustness.py), line for line: the gallop was retuned after the
tables were made and its rows (+0.3%, copies within 1 mm to 10 s) no longer held. The other
rows take a minute and a half together; rerun them with the scripts when a change moves a gait.
"""

from __future__ import annotations

import sys
from pathlib import Path

import pytest
from conftest import ROOT
from doc_tables import table
from runtime_helpers import needs_c_compiler

sys.path.insert(0, str(ROOT / "docs" / "scripts"))
import last_bits  # noqa: E402
import robustness  # noqa: E402

pytestmark = needs_c_compiler
DOC = "docs/runtime.md"


def _line(row: dict[str, str]) -> str:
    return "| " + " | ".join(row.values()) + " |"


@pytest.fixture
def scripts_root(generated: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The scripts read ROOT/creatures and ROOT/generated: the shipped creatures, and a copy of
    the modules (a stale one is compiled there, never in the repo)."""
    (tmp_path / "creatures").symlink_to(ROOT / "creatures")
    (tmp_path / "generated").symlink_to(generated)
    for script in (last_bits, robustness):
        monkeypatch.setattr(script, "ROOT", tmp_path)


@pytest.mark.usefixtures("scripts_root")
def test_the_biped_gallops_last_bits_rows() -> None:
    rows = [r for r in table(DOC, "| run | moved by k ulps") if r["run"].startswith("biped gallop")]
    assert [r["moved by k ulps"] for r in rows] == [
        last_bits.WHAT["start"],
        last_bits.WHAT["speed"],
    ]
    made = [last_bits.measure("biped", "gallop", 1.5, 10.0, 32, nudge) for nudge in last_bits.WHAT]
    got = last_bits.table(made).splitlines()[2:]
    assert got == [_line(r.cells) for r in rows], rows[0].where


@pytest.mark.usefixtures("scripts_root")
def test_the_biped_gallops_robustness_row() -> None:
    (row,) = [
        r for r in table(DOC, "| gait (20 s) |") if r["gait (20 s)"].startswith("biped gallop")
    ]
    got = robustness.table([robustness.measure("biped", "gallop", 1.5, (), threads=2)])
    assert got.splitlines()[2] == _line(row.cells), row.where
