"""Single and double support: the phases of a run with one set of feet down, and their
rows when two or more feet touch at once (a gallop's stance)."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from legdsl.analysis.contact_times import ContactTimes
from legdsl.analysis.results import Summary
from legdsl.analysis.rows import stat
from legdsl.analysis.strides import EPS_T, foot_contacts, touching
from legdsl.sim.trajectory import Trajectory


@dataclass(frozen=True)
class SupportPhase:
    """A complete run of samples with one set of feet down: ``kind`` is "flight" (none),
    "single" (one) or "double" (two or more); ``feet`` names the feet (legs) down."""

    kind: str
    feet: tuple[str, ...]
    t_start: float  # s
    t_end: float  # s

    @property
    def duration(self) -> float:
        return self.t_end - self.t_start


def support_phases(
    t: np.ndarray,
    down: np.ndarray,
    names: Sequence[str],
    t_from: float,
    t_to: float,
    at_change: Callable[[int, bool], float] | None = None,
) -> list[SupportPhase]:
    """Split a run into phases of constant support: ``down`` is (samples, feet) true where a
    foot touches. A phase counts when both its ends were seen inside ``[t_from, t_to]``
    (as stances do: a phase still going on at the first or last sample is left out).
    ``at_change(k, starts)``, when given, is the exact time of the change the samples see at
    ``k`` (as the phase that starts or ends there has it), else the sample's time."""
    at = at_change or (lambda k, starts: float(t[k]))
    if down.ndim != 2 or down.shape[0] < 2 or down.shape[1] == 0:
        return []
    change = np.flatnonzero(np.any(down[1:] != down[:-1], axis=1)) + 1
    bounds = np.concatenate(([0], change, [down.shape[0]]))
    phases = []
    for a, b in zip(bounds[:-1], bounds[1:], strict=True):
        if a == 0 or b == down.shape[0]:  # one end not seen
            continue
        if t[a] < t_from - EPS_T or t[b] > t_to + EPS_T:
            continue
        feet = tuple(n for n, on in zip(names, down[a], strict=True) if on)
        kind = ("flight", "single")[len(feet)] if len(feet) < 2 else "double"
        phases.append(SupportPhase(kind, feet, at(int(a), True), at(int(b), False)))
    return phases


def with_support_rows(
    rows: list[Summary], tr: Trajectory, t_from: float, t_to: float, times: ContactTimes
) -> list[Summary]:
    """Add rows for single and double support when two or more feet touch at once in the
    window (a gallop's stance: single, double, single support); else ``rows`` unchanged. The
    phases are timed by the run's events in ``times`` (a gallop's 4.4 ms lead read as one
    5.2 ms sample on the samples alone)."""
    if tr.leg_names:
        cols = [foot_contacts(tr, i) for i in range(len(tr.leg_names))]
        names = [n for n, c in zip(tr.leg_names, cols, strict=True) if c]
        cols = [c for c in cols if c]
    else:
        names, cols = list(tr.contact_names), [(i,) for i in range(len(tr.contact_names))]
    if len(cols) < 2:
        return rows
    down = np.stack([touching(tr, c) for c in cols], axis=1)
    window = (tr.t >= t_from - EPS_T) & (tr.t <= t_to + EPS_T)
    if not (down[window].sum(axis=1) >= 2).any():
        return rows

    def at_change(k: int, starts: bool) -> float:
        """A phase starts at the last change of its feet between samples k-1 and k (it holds
        from there), and ends at the first."""
        found = [
            x
            for j in np.flatnonzero(down[k] != down[k - 1])
            for x in times.between(cols[j], "touchdown" if down[k, j] else "liftoff", k)
        ]
        return (max if starts else min)(found, default=float(tr.t[k]))

    phases = support_phases(tr.t, down, names, t_from, t_to, at_change)
    singles = [p for p in phases if p.kind == "single"]
    doubles = [p for p in phases if p.kind == "double"]
    extra = [
        stat(
            "single_support_duration",
            "single support duration (s)",
            [p.duration for p in singles],
        ),
    ]
    for name in names:
        extra.append(
            stat(
                f"single_support_duration_{name}",
                f"single support duration, {name} (s)",
                [p.duration for p in singles if p.feet == (name,)],
            )
        )
    extra.append(
        stat(
            "double_support_duration", "double support duration (s)", [p.duration for p in doubles]
        )
    )
    inside = down[window].sum(axis=1)
    extra.append(
        Summary(
            "double_support_fraction",
            "fraction of the time in double support (-)",
            float(np.mean(inside >= 2)),
            math.nan,
            int(inside.size),
        )
    )
    return rows + extra
