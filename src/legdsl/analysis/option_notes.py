"""Notes on a ``min_stance`` or friction ``edge`` that changed a measurement more than it can
have been meant to. A time given without its unit is seconds (``--min-stance 20`` is 20 s), so
such a value erases every stance, or leaves no stance an interior for the friction rows, and
the table alone showed only ``n/a`` rows, or blamed the run for touching down once."""

from __future__ import annotations

import math

import numpy as np

from legdsl.analysis.results import Friction
from legdsl.analysis.strides import (
    EPS_T,
    SCUFF_FRACTION,
    Unit,
    feet_contacts,
    in_window,
    runs,
)
from legdsl.sim.trajectory import Trajectory


def time_text(seconds: float) -> str:
    """A time as a person reads it: ``20 ms``, ``20 s``."""
    return f"{seconds * 1000:g} ms" if seconds < 1 else f"{seconds:g} s"


def min_stance_note(
    raw: Trajectory, units: list[Unit], lo: float, hi: float, min_stance: float | None
) -> str:
    """Said when ``min_stance`` left out feet's stances in the window that are no scuffs (at
    least ``SCUFF_FRACTION`` of the feet's median stance, as ``scuff_note`` counts them); ""
    otherwise, and when it left out scuffs alone, as it is meant to."""
    if min_stance is None:
        return ""
    seen = [d for _, _, d in feet_contacts(raw, units, lo, hi)]
    if not seen:
        return ""
    usual = float(np.median(seen))
    stances = [d for d in seen if d >= SCUFF_FRACTION * usual]
    cut = [d for d in stances if d < min_stance - EPS_T]
    if not cut:
        return ""
    how_many = (
        f"all {len(cut)}" if len(cut) == len(stances) else f"{len(cut)} of the {len(stances)}"
    )
    at_most = math.floor(SCUFF_FRACTION * usual * 1000 + 1e-6)
    return (
        f"--min-stance {time_text(min_stance)} left out {how_many} stances of the feet in the "
        f"window that are no scuffs (at least a third of their median stance, {usual:.3f} s): "
        "a contact shorter than --min-stance is no touchdown; to leave out scuffs alone, give "
        f"at most --min-stance {at_most}ms"
    )


def friction_edge_note(tr: Trajectory, friction: list[Friction], lo: float, hi: float) -> str:
    """Said when the friction ``edge`` leaves no sample of any stance's interior, so that every
    'past first/last' row is n/a and every 'first' row holds whole stances; "" otherwise."""
    pushed = [f for f in friction if f.samples > 0]
    if not pushed or any(math.isfinite(f.peak_interior) for f in pushed):
        return ""
    edge = pushed[0].edge
    if edge <= 0:
        return ""
    longest = 0.0
    for c in range(len(tr.contact_names)):
        a, b = runs(tr.contact[:, c] != 0)
        keep = in_window(tr.t, a, b, lo, hi)
        longest = max([longest, *(tr.t[b[keep]] - tr.t[a[keep]]).tolist()])
    return (
        f"--friction-edge {time_text(edge)} leaves no sample inside any stance (it is left out "
        f"at both ends, and the longest contact in the window lasts {longest:.3f} s), so the "
        f"friction rows past the first and last {time_text(edge)} are n/a and those of the "
        "first hold whole stances; the paper's edge is 10ms"
    )
