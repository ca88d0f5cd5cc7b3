"""docs/metrics.md against the command: its synopsis and option table list every option of
``legdsl metrics`` (--table2 and --friction-edge were missing), and the JSON names it gives
are the keys ``--json`` writes (it said ``summaries`` for ``summary``)."""

from __future__ import annotations

import argparse
import re
from pathlib import Path

from test_min_stance import scuffed_run

from legdsl.analysis.metrics import compute_metrics
from legdsl.cli import _parser
from legdsl.sim.trajectory import Trajectory

DOC = (Path(__file__).resolve().parents[2] / "docs" / "metrics.md").read_text(encoding="utf-8")


def metrics_options() -> set[str]:
    (subs,) = [a for a in _parser()._actions if isinstance(a, argparse._SubParsersAction)]
    parser = subs.choices["metrics"]
    return {o for a in parser._actions for o in a.option_strings if o.startswith("--")} - {"--help"}


def test_the_synopsis_and_the_option_table_list_every_option() -> None:
    synopsis = DOC[DOC.index("    legdsl metrics DIR") : DOC.index("| option | meaning |")]
    table = DOC[DOC.index("| option | meaning |") : DOC.index("Values are printed")]
    for option in sorted(metrics_options()):
        assert re.search(rf"\[{option}[\] ]", synopsis), f"{option} is not in the synopsis"
        assert f"| `{option}" in table, f"{option} is not in the option table"


def test_the_json_names_the_doc_gives_are_the_keys_written() -> None:
    run: Trajectory = scuffed_run()
    data = compute_metrics(run, min_stance=20.0).to_dict()
    named = re.findall(r"`--json`'s\s+`(\w+)`", DOC) + re.findall(r"\(JSON `(\w+)`\)", DOC)
    named += re.findall(r"JSON has [^.;]*? (?:as|in) `(\w+)`", DOC)
    assert {"summary", "strides", "scuff_note", "option_notes"} <= set(named), named
    for key in named:
        assert key in data, f"docs/metrics.md names the JSON key {key!r}; --json has {list(data)}"
    for dotted in re.findall(r"`(\w+\.\w+)` in JSON", DOC):
        outer, inner = dotted.split(".")
        assert inner in data[outer], dotted
