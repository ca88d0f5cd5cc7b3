"""What the gait metrics of a run are: its stances, flights and friction needs, the
averaged rows (``Summary``) and all of them together (``GaitMetrics``), as text and JSON."""

from __future__ import annotations

import difflib
import json
import math
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from legdsl.analysis.ended import ending_note
from legdsl.analysis.plot_ending import Ending
from legdsl.analysis.resolution import ROUND_OFF, label_unit, natural, resolved
from legdsl.figures import figure
from legdsl.files import write_atomic

FRICTION_EDGE = 0.010  # s: the paper's "period of up to 10 ms" at each end of a stance
# why a row of travel or of the root's attitude reads n/a for a creature whose root body is
# welded to the world (``fixed at``): legdsl run's summary gives its mean speed the same reason
WELDED = "its root is welded to the world"


class MetricsError(ValueError):
    """A request the run cannot answer: an unknown leg, group or coordinate, an empty window."""


class UnknownMetric(MetricsError, KeyError):
    """A metric the run's summary has no row for (a KeyError too, as a lookup's)."""

    def __str__(self) -> str:  # the sentence, not KeyError's quoted repr of it
        return str(self.args[0])


@dataclass(frozen=True)
class Stance:
    """One complete stance of a leg, a virtual leg (``kind == "group"``) or a bare contact."""

    unit: str
    kind: str  # "leg", "group" or "contact"
    t_touchdown: float  # s
    t_liftoff: float  # s
    stride: int  # index of the counted stride its touchdown falls in, -1 if none
    leg_length_change: float  # m: leg_length at touchdown less its least in the stance (legs)
    stored_energy: float  # J: leg-spring peak until just before that least, less at touchdown

    @property
    def duration(self) -> float:
        return self.t_liftoff - self.t_touchdown


@dataclass(frozen=True)
class Flight:
    """One complete flight: no contact touches from ``t_start`` to ``t_end``."""

    t_start: float  # s
    t_end: float  # s
    before: str  # the leg or virtual leg whose touchdown ends it
    stride: int  # index of the counted stride it falls in, -1 if none

    @property
    def duration(self) -> float:
        return self.t_end - self.t_start


@dataclass(frozen=True)
class Friction:
    """The friction coefficient one contact needed to stay put, over its complete stances."""

    contact: str
    peak: float  # max |F_t| / F_n over every usable stance sample
    peak_interior: float  # the same without the first and last ``edge`` seconds of each stance
    stance_peaks: list[float]  # per complete stance (NaN if no sample was usable)
    stance_peaks_interior: list[float]
    samples: int  # stance samples used
    skipped: int  # stance samples left out because the normal force was below the floor
    edge: float = FRICTION_EDGE  # s left out at each end of a stance for ``peak_interior``
    peak_first: float = math.nan  # max |F_t| / F_n over the first ``edge`` seconds of each stance


@dataclass(frozen=True)
class Summary:
    """One row of the table: a mean over strides, stances or steps, or a maximum."""

    key: str
    label: str  # Table 2 wording, unit in brackets
    value: float
    std: float  # sample standard deviation; NaN for a maximum or fewer than two values
    n: int  # how many values went in
    # "mean", "weighted mean" (the running speed's, by the strides' durations; std unweighted),
    # "max", "min" (n: how many samples fall below 0), or "total" over the window (n: its samples)
    how: str = "mean"
    why: str = ""  # why the row reads n/a where it means nothing for the creature (``WELDED``)


@dataclass
class GaitMetrics:
    """Per-stride series, every stance and flight, friction per contact, and the averaged rows."""

    t_from: float
    t_to: float
    reference: str
    per_stride: dict[str, list[float]]
    stances: list[Stance]
    flights: list[Flight]
    friction: list[Friction]
    summaries: list[Summary]
    note: str = ""  # why there are no strides, when there are none
    options: dict[str, Any] = field(default_factory=dict)
    scuff_note: str = ""  # touchdowns that look like scuffs, when no min_stance was given
    unwritten: str = ""  # why metrics.json could not be written (a read-only run folder)
    unmeasured: str = ""  # why the rows on the creature's geometry are left out, if they are
    # flag -> what its value did that it may not have been meant to (option_notes.py)
    option_notes: dict[str, str] = field(default_factory=dict)
    # how the run followed each path it was given, over the window (``path_report``): set by
    # ``legdsl metrics`` and ``Run.metrics()`` after measuring, not in metrics.json
    path_reports: list[dict[str, Any]] = field(default_factory=list)
    # the natural size of a value in kg, m, s and rad for the run's creature (resolution.py):
    # the table prints a value under its round-off as 0; empty: every value as measured
    sizes: dict[str, float] = field(default_factory=dict)
    # how the run ended, as its run.json says (None: a trajectory without one); where it did
    # not end ok, how (``plot_ending.Ending``) and where its window was cut (``ended``)
    status: str | None = None
    ending: Ending | None = None
    cut: str = ""

    @property
    def n_strides(self) -> int:
        return len(self.per_stride["duration"])

    def summary(self, key: str) -> Summary:
        """The summary row of metric ``key`` (a name, such as 'running_speed')."""
        if not isinstance(key, str):  # difflib's TypeError ('int' object is not iterable)
            keys = ", ".join(s.key for s in self.summaries)
            raise UnknownMetric(f"no metric {key!r}: a metric is named by a text, e.g. "
                                f"value('running_speed') (the run has {keys})")  # fmt: skip
        for s in self.summaries:
            if s.key == key:
                return s
        keys = [s.key for s in self.summaries]
        close = difflib.get_close_matches(key, keys, n=1)
        hint = f"; did you mean '{close[0]}'?" if close else ""
        raise UnknownMetric(f"no metric '{key}'{hint} (the run has {', '.join(keys)})")

    def value(self, key: str) -> float:
        return self.summary(key).value

    def ending_note(self, where: str = "the run") -> str:
        """What is said of the metrics of a run that did not end ok (``where``: ``the run in
        runs/b``), as ``plot`` and ``animate`` say it; "" for a run that did."""
        return "" if self.ending is None else ending_note(self.ending, where, self.cut)

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready data; NaN becomes null."""
        ended: dict[str, Any] = {} if self.status is None else {"status": self.status}
        if self.ending is not None:
            ended |= {"ended_at": self.ending.at, "cause": self.ending.cause,
                      "ending_note": self.ending_note()}  # fmt: skip
        data = {
            **ended,
            "window": {"from": self.t_from, "to": self.t_to},
            "reference": self.reference,
            "n_strides": self.n_strides,
            "note": self.note,
            "scuff_note": self.scuff_note,
            "option_notes": self.option_notes,
            "options": self.options,
            "summary": {
                s.key: {k: v for k, v in asdict(s).items() if k != "key" and (k != "why" or v)}
                for s in self.summaries
            },
            "strides": self.per_stride,
            "stances": [asdict(s) | {"duration": s.duration} for s in self.stances],
            "flights": [asdict(f) | {"duration": f.duration} for f in self.flights],
            "friction": [asdict(f) for f in self.friction],
        }
        if self.path_reports:  # as legdsl metrics --json prints them
            data["path_reports"] = self.path_reports
        return jsonable(data)

    def table(self) -> str:
        """The averaged rows as text, with units."""
        head = (
            f"gait metrics from {self.t_from:.3f} s to {self.t_to:.3f} s: "
            f"{self.n_strides} stride{'' if self.n_strides == 1 else 's'} (reference: {self.reference})"
        )
        lines = [head]
        if self.note:
            lines.append(f"no strides: {self.note}")
        width = max([len(s.label) for s in self.summaries] + [8])
        lines.append(f"{'quantity':<{width}}  {'value':>10}  {'std':>10}  {'n':>4}")
        zeroed = 0
        for s in self.summaries:
            unit = label_unit(s.label)
            scale = natural(unit, self.sizes) if unit is not None else None
            value, std = resolved(s.value, scale), resolved(s.std, scale)
            zeroed += value == 0.0 != s.value  # a NaN is no round-off
            spread = {"max": "(peak)", "min": "(least)", "total": "(window)"}.get(
                s.how,
                figure(std, std if value == 0.0 != s.value else value),  # to the value's decimals
            )
            why = f"  ({s.why})" if s.why else ""  # as legdsl run's "n/a (its root is ...)"
            lines.append(f"{s.label:<{width}}  {figure(value):>10}  {spread:>10}  {s.n:>4}{why}")
        if zeroed:
            lines.append(
                f"({zeroed} row{'s read' if zeroed > 1 else ' reads'} 0.000: under {ROUND_OFF:g} "
                f"of what the creature's size ({figure(self.sizes['m'])} m), mass and gravity make "
                "of the unit, a value is the round-off of a zero)"
            )
        return "\n".join(lines) + "\n"

    def path_table(self) -> str:
        """The path reports as text, as ``legdsl metrics`` prints them after its table ("path
        following:", then each path's rows); "" for a run that followed no path."""
        from legdsl.analysis.path_rows import path_text

        if not self.path_reports:
            return ""
        return "path following:\n" + "".join(path_text(r) + "\n" for r in self.path_reports)


def write_json(metrics: GaitMetrics, path: Path) -> None:
    """Write ``metrics.to_dict()`` to ``path`` whole or not at all."""
    write_atomic(path, json.dumps(metrics.to_dict(), indent=2, allow_nan=False) + "\n")


def jsonable(x: Any) -> Any:
    if isinstance(x, dict):
        return {str(k): jsonable(v) for k, v in x.items()}
    if isinstance(x, list | tuple):
        return [jsonable(v) for v in x]
    if isinstance(x, np.generic):
        x = x.item()
    if isinstance(x, float) and not math.isfinite(x):
        return None
    return x
