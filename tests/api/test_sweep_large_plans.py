"""A sweep of 1,000,000 runs resumed printed nothing for 32 s (reading and writing its plan:
sweep.json indented throughout took Python's JSON encoder seconds), where docs/api.md promises
a log a line every 10 s from the start, a stall included."""

from __future__ import annotations

import json
import threading
import time

import pytest

from legdsl.api.sweep_notes import Preparing, plan_text


def test_a_plan_is_said_while_it_is_read_until_the_first_progress(
    capsys: pytest.CaptureFixture[str],
) -> None:
    said: list[tuple[int, int]] = []
    preparing = Preparing(1_000_000, lambda done, total, left: said.append((done, total)), 0.05)
    time.sleep(0.3)
    preparing.progress(1128, 1_000_000, None)
    err = capsys.readouterr().err
    assert "legdsl: sweep: reading its plan of 1,000,000 runs (0 s)" in err
    assert said == [(1128, 1_000_000)]
    assert not any(t.name == "legdsl-sweep-preparing" for t in threading.enumerate())
    time.sleep(0.2)
    assert capsys.readouterr().err == ""  # no line after the first progress


def test_a_plans_text_is_its_json_with_a_run_a_line() -> None:
    plan = {"file": 'a "runs": []', "set": ["x=1"], "runs": [{"a": 1.0, "b": 0.1}] * 3,
            "simulation": {"dt": None}}  # fmt: skip
    text = plan_text(plan)
    assert json.loads(text) == plan
    assert '\n    {"a": 1.0, "b": 0.1},\n' in text
