"""The friction coefficient each contact needed to stay put: ``|F_t| / F_n`` over its
complete stances (normal and tangential to the ground: on a slope, to its tilted surface),
with and without the first and last instants of each stance, and over the first instants
alone (a touchdown's: where ground speed matching matters)."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from legdsl.analysis.results import Friction, Summary
from legdsl.analysis.strides import EPS_T, in_window, runs
from legdsl.sim.trajectory import Trajectory

MIN_NORMAL_FRACTION = 0.01  # of body weight: below this the friction ratio is not computed
LEVEL = (0.0, 0.0, 1.0)  # the ground's unit normal but on a slope


def contact_friction(
    tr: Trajectory,
    c: int,
    lo: float,
    hi: float,
    edge: float,
    min_normal_fraction: float,
    normal: tuple[float, float, float] = LEVEL,
) -> Friction:
    """|F_t| / F_n over the complete stances of contact ``c``, along and across the ground
    whose unit ``normal`` is given. Samples whose normal force is below
    ``min_normal_fraction`` of body weight (or not pushing at all) are skipped: at the first
    and last instants of contact the ratio of two near-zero forces is noise. The ``edge`` at
    each end is measured from the support's ends, the first sample that pushes and the first
    after the last that does: a foot's contact outlasts its push (the ground's damper lets go
    while the spring is still compressed; the quadruped's by 11 ms), and the paper's "period
    of up to 10 ms" is at the start and end of support."""
    floor = min_normal_fraction * tr.total_mass * tr.gravity
    floor = floor if floor > 0 else 1e-9
    fn, tangent = _split(tr.force[:, c, :], normal)
    ratio = tangent / np.where(fn > floor, fn, np.inf)
    usable = fn > floor
    a, b = runs(tr.contact[:, c] != 0)
    keep = in_window(tr.t, a, b, lo, hi)
    peaks, interior_peaks, first_peaks, used, skipped = [], [], [], 0, 0
    for s, e in zip(a[keep].tolist(), b[keep].tolist(), strict=True):
        t = tr.t[s:e]
        ok = usable[s:e]
        pushing = np.flatnonzero(ok)
        if len(pushing):  # else every sample is skipped and each peak is n/a
            on, off = tr.t[s + pushing[0]], tr.t[min(s + pushing[-1] + 1, len(tr.t) - 1)]
            away = (t - on >= edge - EPS_T) & (off - t > edge + EPS_T)
            first = t - on < edge - EPS_T
        else:
            away = first = ok
        peaks.append(_masked_max(ratio[s:e], ok))
        interior_peaks.append(_masked_max(ratio[s:e], ok & away))
        first_peaks.append(_masked_max(ratio[s:e], ok & first))
        used += int(ok.sum())
        skipped += int((~ok).sum())
    return Friction(
        contact=tr.contact_names[c],
        peak=_nanmax(peaks),
        peak_interior=_nanmax(interior_peaks),
        stance_peaks=peaks,
        stance_peaks_interior=interior_peaks,
        samples=used,
        skipped=skipped,
        edge=edge,
        peak_first=_nanmax(first_peaks),
    )


def _split(force: np.ndarray, normal: tuple[float, float, float]) -> tuple[np.ndarray, np.ndarray]:
    """The forces' components along the ground's normal and their size across it: on level
    ground, exactly the world z and the horizontal magnitude."""
    if normal == LEVEL:
        return force[:, 2], np.hypot(force[:, 0], force[:, 1])
    n = np.asarray(normal, dtype=float)
    along = force @ n
    return along, np.linalg.norm(force - along[:, None] * n, axis=1)


def _masked_max(x: np.ndarray, mask: np.ndarray) -> float:
    return float(np.max(x[mask])) if mask.any() else math.nan


def _nanmax(values: Sequence[float]) -> float:
    finite = [v for v in values if math.isfinite(v)]
    return max(finite) if finite else math.nan


def friction_rows(f: Friction) -> list[Summary]:
    n = sum(math.isfinite(p) for p in f.stance_peaks)  # stances with a usable sample
    n_in = sum(math.isfinite(p) for p in f.stance_peaks_interior)
    label = f"friction coefficient needed, {f.contact}"
    away = f"past first/last {f.edge * 1000:g} ms"
    return [
        Summary(f"friction_{f.contact}", f"{label} (-)", f.peak, math.nan, n, "max"),
        Summary(
            f"friction_interior_{f.contact}",
            f"{label}, {away} (-)",
            f.peak_interior,
            math.nan,
            n_in,
            "max",
        ),
        Summary(
            f"friction_first_{f.contact}",
            f"{label}, first {f.edge * 1000:g} ms (-)",
            f.peak_first,
            math.nan,
            n,
            "max",
        ),
    ]
