"""``run_copies`` tells the notes ``legdsl run`` prints after a run (a speed command not
followed, a state held for seconds) as ``run`` and ``run_many`` do: it said nothing, though
each copy's ``info["notes"]`` (and run.json) held them. Each distinct note is one
``LegdslWarning`` at the caller's line, saying which copies it concerns."""

from __future__ import annotations

import warnings
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from conftest import ROOT

import legdsl
from legdsl.api import LegdslWarning, notes


def test_each_distinct_note_of_the_copies_is_warned_once_at_the_callers_line(
    generated: Path,
) -> None:
    quadruped = legdsl.load(ROOT / "creatures" / "quadruped.leg", generated=generated)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        copies = quadruped.run_copies(3, "trot", set={"full": "0.6 m"},
                                      vary={"speed": ([2, 2, 3], "m/s")}, time=5)  # fmt: skip
    said = [str(w.message) for w in caught if issubclass(w.category, LegdslWarning)]
    assert all(Path(w.filename) == Path(__file__) for w in caught)
    first, last = copies[0].info["notes"], copies[2].info["notes"]
    assert copies[1].info["notes"] == first and last != first
    distinct = dict.fromkeys(first + last)
    assert len(said) == len(distinct)  # once each, not once per copy
    for note in first:
        assert (f"copies 0, 1 (2 of 3): {note}" in said) == (note not in last)
    assert any("speed command was 2.00 m/s" in s and s.startswith("copies 0, 1 (2 of 3)")
               for s in said)  # fmt: skip
    assert any("speed command was 3.00 m/s" in s and s.startswith("copy 2 of 3: ") for s in said)


def test_many_distinct_notes_are_told_a_few_and_the_rest_counted(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    from legdsl.pipeline import run_notes

    monkeypatch.setattr(run_notes, "run_notes", lambda run: [f"note {run}"] if run else [])
    told: list[str] = []
    session = SimpleNamespace(tell=lambda kind, text: told.append(f"{kind}: {text}"))
    status = np.array(["ok"] * 11 + ["fell"])  # copy 0's run notes nothing, 11 fell
    batch = type("Batch", (), {"__len__": lambda self: 12, "status": status,
                               "run": lambda self, k: k})()  # fmt: skip
    notes.after_copies(session, batch)
    assert told[:5] == [f"note: copy {k} of 12: note {k}" for k in range(1, 6)]
    assert told[5:] == ["note: 5 more notes, on copies 6, 7, 8, 9, 10 (5 of 12): each copy's "
                        "are in copies[k].info['notes']"]  # fmt: skip
