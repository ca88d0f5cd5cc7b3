"""Helpers for tests/creatures/test_doc_tables.py: the measurement tables of docs/*.md read
from the docs themselves, the rows rerun on the C backend, and each figure compared with the
doc's at the precision the doc prints it."""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pytest

from legdsl.analysis.metrics import compute_metrics
from legdsl.analysis.results import GaitMetrics
from legdsl.analysis.table2 import virtual_legs
from legdsl.pipeline import scaled
from legdsl.pipeline.session import Run, RunSession

ROOT = Path(__file__).resolve().parents[1]
NUMBER = re.compile(r"[-+]?\d+(?:\.\d+)?")


@dataclass(frozen=True)
class Row:
    """One row of a doc's table: its cells by column header, and where it is."""

    doc: str  # docs/FILE.md
    line: int
    cells: dict[str, str]

    def __getitem__(self, column: str) -> str:
        return self.cells[column]

    @property
    def where(self) -> str:
        return f"{self.doc}:{self.line}"


def _cells(line: str) -> list[str]:
    hidden = line.strip().replace("\\|", "\0").strip("|")  # \| is a pipe inside a cell
    return [c.strip().replace("\0", "|") for c in hidden.split("|")]


def table(doc: str, header: str) -> list[Row]:
    """The rows of the one table in ``doc`` whose header line starts with ``header``."""
    lines = (ROOT / doc).read_text(encoding="utf-8").splitlines()
    starts = [k for k, line in enumerate(lines) if line.startswith(header)]
    assert len(starts) == 1, f"{doc}: {len(starts)} tables start with {header!r}, not one"
    names = _cells(lines[starts[0]])
    rows = []
    for k in range(starts[0] + 2, len(lines)):
        if not lines[k].startswith("|"):
            break
        rows.append(Row(doc, k + 1, dict(zip(names, _cells(lines[k]), strict=True))))
    assert rows, f"{doc}:{starts[0] + 1}: the table has no rows"
    return rows


def numbers(cell: str) -> list[str]:
    """The numbers written in a cell (a Unicode minus read as '-'), without what is in
    brackets (a remark such as '(6.6x less)')."""
    plain = re.sub(r"\([^)]*\)", "", cell.replace("\u2212", "-").replace("*", ""))
    return NUMBER.findall(plain)


def printed_as(doc_number: str, value: float) -> str:
    """``value`` printed to the decimals of ``doc_number``."""
    decimals = len(doc_number.partition(".")[2])
    return f"{value:+.{decimals}f}" if doc_number[0] in "+-" else f"{value:.{decimals}f}"


@dataclass
class Comparison:
    """The figures of one run against one doc row (or several rows, one per quantity)."""

    how: str  # the commands that re-measure it
    wrong: list[str] = field(default_factory=list)

    def number(self, row: Row, column: str, value: float, cell: str | None = None) -> None:
        """The first number of the cell against ``value`` (nothing to compare in an empty cell)."""
        found = numbers(row[column] if cell is None else cell)
        if found:
            self.figures(row, column, [value], found[:1])

    def figures(self, row: Row, column: str, values: Sequence[float], doc: Sequence[str]) -> None:
        ran = [printed_as(d, v) for d, v in zip(doc, values, strict=False)]
        if any(float(r) != float(d) for r, d in zip(ran, doc, strict=False)):  # -0.0 is 0.0
            self.wrong.append(f"{row.where}: {column!r}: the doc says {' / '.join(doc)}, "
                              f"the run gives {' / '.join(ran)}")  # fmt: skip

    def text(self, row: Row, column: str, expected: str) -> None:
        if row[column].replace("\u2212", "-") != expected:
            self.wrong.append(f"{row.where}: {column!r}: the doc says {row[column]!r}, "
                              f"the run gives {expected!r}")  # fmt: skip

    def check(self) -> None:
        if self.wrong:
            pytest.fail("\n".join([*self.wrong, f"re-measure with: {self.how}"]), pytrace=False)


# runs shared by the tests of a session (a table's rows and another's may be the same run)
_SESSIONS: dict[str, RunSession] = {}
_RUNS: dict[tuple[object, ...], Run] = {}


def run_creature(
    generated: Path, creature: str, controller: str, settings: Sequence[str], time: float
) -> Run:
    """``legdsl run creatures/CREATURE.leg --controller ... --set ... --time ... --backend c``."""
    key = (creature, controller, tuple(settings), time)
    if key not in _RUNS:
        if creature not in _SESSIONS:
            source = ROOT / "creatures" / f"{creature}.leg"
            _SESSIONS[creature] = RunSession.from_file(source, generated=generated)
        session = _SESSIONS[creature]
        defaults = scaled.run_options(session.model, None, dt=None, control_dt=None,
                                      record_rate=None)  # fmt: skip
        options = dataclasses.replace(defaults, duration=time)
        _RUNS[key] = session.run(controller, list(settings), options=options, backend="c")
    return _RUNS[key]


def metrics(run: Run, start: float, **options: str) -> GaitMetrics:
    """``legdsl metrics DIR --from START`` (``joint=``, ``against=`` as ``--joint``, ``--against``)."""
    return compute_metrics(run.result.trajectory, t_from=start, events=run.result.events,
                           **options)  # fmt: skip


def table2_metrics(run: Run, creature: str, gait: str, start: float) -> GaitMetrics:
    """``legdsl metrics DIR --from START --table2 GAIT``: a gait of Table 2 measured on virtual
    legs (the bound's front and rear pairs) has them found from the creature's hips, and its
    strides start at the reference pair's touchdowns (legdsl.pipeline.measure.measure_run)."""
    groups, first = virtual_legs(gait, _SESSIONS[creature].model)
    return metrics(run, start, groups=groups, leg=first) if groups else metrics(run, start)


def run_command(creature: str, controller: str, settings: Sequence[str], time: float) -> str:
    sets = "".join(f" --set {s}" for s in settings)
    return (f"legdsl run creatures/{creature}.leg --controller {controller}{sets} "
            f"--time {time:g} --out runs/x")  # fmt: skip


def fell_at(run: Run) -> float | None:
    """When the run fell (None if it did not)."""
    return run.result.sim_time if run.status == "fell" else None


def heading_speed(run: Run, start: float) -> float:
    """The centre of mass's mean speed along the heading at ``start``, from ``start`` to the end
    (docs/scripts/quadruped_matrix.py's "mean speed")."""
    tr = run.result.trajectory
    later = tr.t >= start
    yaw = tr.root_rpy[later, 2]
    com, t = tr.com[later], tr.t[later]
    along = np.cos(yaw[0]) * (com[-1, 0] - com[0, 0]) + np.sin(yaw[0]) * (com[-1, 1] - com[0, 1])
    return float(along / (t[-1] - t[0]))


def pair_spreads(run: Run, partner: dict[str, str], start: float) -> list[float]:
    """At each LOADING after ``start``, how long until the first foot's partner lands (1 s if it
    does not within 60 ms; docs/scripts/quadruped_matrix.py's ``pair_spreads``)."""
    events = run.result.events
    touchdowns = [(e["t"], e["contact"]) for e in events if e["kind"] == "touchdown"]
    spreads = []
    for e in events:
        if e.get("state") != "LOADING" or e["t"] < start:
            continue
        first = next((x for x in touchdowns if abs(x[0] - e["t"]) <= 0.005), None)
        if first is None:
            continue
        lands = [t for t, c in touchdowns if c == partner[first[1]] and abs(t - first[0]) <= 0.06]
        spreads.append(min(abs(t - first[0]) for t in lands) if lands else 1.0)
    return spreads
