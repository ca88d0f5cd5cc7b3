"""Touchdown and liftoff times exact to the integration step, from run.json's events.

The contact flags are sampled at the record rate (a sample every 5.2 ms at the default
200 Hz), so a touchdown read from them is late by up to one record interval: a 7.2 ms lag
between two feet read as two intervals, 10.4 ms. run.json's events time each touchdown and
liftoff to the step. A contact whose flag changed between samples k-1 and k has its event in
``(t[k-1], t[k]]``; where none is found there (a trajectory without its run.json, a contact
that changed back and forth unseen) the sample time ``t[k]`` stands, as before.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from typing import Any

import numpy as np

from legdsl.analysis.strides import EPS_T
from legdsl.sim.trajectory import Trajectory


class ContactTimes:
    """The events of one run, looked up by contact, kind and sample."""

    def __init__(
        self, t: np.ndarray, contact_names: Sequence[str], events: Iterable[Mapping[str, Any]]
    ):
        self.t = t
        index = {name: i for i, name in enumerate(contact_names)}
        found: dict[tuple[int, str], list[float]] = {}
        for e in events:
            c = index.get(str(e.get("contact")))
            if c is not None and e.get("kind") in ("touchdown", "liftoff"):
                found.setdefault((c, str(e["kind"])), []).append(float(e["t"]))
        self._times = {key: np.sort(np.asarray(v)) for key, v in found.items()}

    def between(self, contacts: Iterable[int], kind: str, k: int) -> list[float]:
        """The ``kind`` events of ``contacts`` in ``(t[k-1], t[k]]`` (up to ``t[0]`` for k 0)."""
        lo = float(self.t[k - 1]) + EPS_T if k > 0 else -np.inf
        hi = float(self.t[k]) + EPS_T
        out: list[float] = []
        for c in contacts:
            times = self._times.get((c, kind))
            if times is not None:
                out += times[(times > lo) & (times <= hi)].tolist()
        return out

    def touchdown(self, contact: int, k: int) -> float:
        """When ``contact``, first in contact at sample ``k``, touched down."""
        return min(self.between((contact,), "touchdown", k), default=float(self.t[k]))


def contact_times(tr: Trajectory, events: Iterable[Mapping[str, Any]] | None) -> ContactTimes:
    """The contact times of trajectory ``tr`` with its run's ``events`` (none: the samples')."""
    return ContactTimes(tr.t, tr.contact_names, events or ())
