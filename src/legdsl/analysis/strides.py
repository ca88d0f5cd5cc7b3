"""Strides, stances and flights of a recorded run, found from its ``contact`` flags.

A touchdown is the first sample in contact and a liftoff the first sample out of contact,
so a stance is the half-open sample range ``[touchdown, liftoff)``. Stances and flights
count when both their ends were seen inside the window; strides when they lie wholly in
it. A contact shorter than ``min_stance`` (when one is given) is no touchdown at all
(``debounced``); without it, contacts much shorter than the feet's usual stance are only
pointed out (``scuff_note``). Each counted stride also gets its series of values (duration, length, pitch and roll
magnitude, speed, peak vertical acceleration, external-energy fluctuation and the external
energy taken up, and the magnitude and correlation of chosen coordinates).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from legdsl.analysis.averages import finite_mean
from legdsl.analysis.results import Flight, MetricsError, Stance
from legdsl.sim.trajectory import Trajectory

EPS_T = 1e-9  # s: slack for comparing sample times that went through floating point
# A foot's contact under a third of the median stance of the feet looks like a scuff: a real
# stance of a steady gait varies by tens of percent, a scuff lasts a step to a few samples.
SCUFF_FRACTION = 1 / 3


@dataclass(frozen=True)
class Unit:
    """Something that has stances: a leg, a virtual leg, or a contact of a run without legs."""

    name: str
    kind: str
    contacts: tuple[int, ...]
    legs: tuple[int, ...]


def stance_units(tr: Trajectory, groups: dict[str, Sequence[str]]) -> list[Unit]:
    legs = list(tr.leg_names)
    if legs:
        units = [Unit(n, "leg", foot_contacts(tr, i), (i,)) for i, n in enumerate(legs)]
    else:  # a run without legs: each contact stands for itself
        units = [Unit(n, "contact", (i,), ()) for i, n in enumerate(tr.contact_names)]
    taken = {u.name for u in units}
    names, kind = (legs, "leg") if legs else (list(tr.contact_names), "contact")
    for name, members in groups.items():
        unknown = [m for m in members if m not in names]
        if unknown:
            raise MetricsError(
                f"group {name!r}: no {kind} named {', '.join(unknown)} "
                f"({kind}s: {', '.join(names) or 'none'})"
            )
        if name in taken:
            raise MetricsError(
                f"group {name!r} has the name of a {kind}: give it a name of its own (--group "
                f"{name}_group={','.join(members)})"
            )
        twice = sorted({m for m in members if list(members).count(m) > 1})
        if twice:  # its stances would count that foot twice, as two feet landing together
            raise MetricsError(
                f"group {name!r} names {', '.join(twice)} twice: give each {kind} once "
                f"(--group {name}={','.join(dict.fromkeys(members))})"
            )
        idx = tuple(names.index(m) for m in members)
        if legs:
            units.append(Unit(name, "group", sum((foot_contacts(tr, i) for i in idx), ()), idx))
        else:  # a run without legs: a group of its contacts
            units.append(Unit(name, "group", idx, ()))
    return units


def foot_contacts(tr: Trajectory, leg: int) -> tuple[int, ...]:
    """The contact indices of a leg's soles (its foot first): its stance is while any of
    them touches; none if the recording names no valid foot for it."""
    feet = tr.leg_feet
    ok = leg < len(feet) and 0 <= feet[leg] < len(tr.contact_names)
    return tr.soles_of(leg) if ok else ()


def reference(tr: Trajectory, units: list[Unit], leg: str | None) -> tuple[str, tuple[int, ...]]:
    if leg is None:
        if not units:
            return "none", ()
        return units[0].name, units[0].contacts
    for u in units:
        if u.name == leg:
            return u.name, u.contacts
    if leg in tr.contact_names:
        return leg, (tr.contact_names.index(leg),)
    known = ", ".join([u.name for u in units] + list(tr.contact_names))
    raise MetricsError(f"no leg, group or contact named {leg!r} (known: {known or 'none'})")


def coordinates(tr: Trajectory, joint: str | None, against: str | None) -> dict[str, int]:
    if against is not None and joint is None:
        raise MetricsError("--against needs --joint: the correlation is of the joint with it")
    cols = {}
    for role, name in (("joint", joint), ("against", against)):
        if name is None:
            continue
        if name not in tr.q_names:
            raise MetricsError(
                f"no coordinate named {name!r} (coordinates: {', '.join(tr.q_names) or 'none'})"
            )
        cols[role] = tr.q_names.index(name)
    return cols


def touching(tr: Trajectory, contacts: Sequence[int]) -> np.ndarray:
    """True where any of ``contacts`` touches: the stance of a leg or of a virtual leg."""
    if not contacts:
        return np.zeros(len(tr), dtype=bool)
    return np.any(tr.contact[:, list(contacts)] != 0, axis=1)


def _edges(on: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Sample indices of rises (first sample on) and falls (first sample off)."""
    d = np.diff(on.astype(np.int8))
    return np.flatnonzero(d == 1) + 1, np.flatnonzero(d == -1) + 1


def runs(on: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Complete runs of ``on`` as half-open ``[start, stop)``: a run already on at the first
    sample, or still on at the last, is left out because one of its ends was not seen."""
    rises, falls = _edges(on)
    falls = falls[falls > rises[0]] if rises.size else falls[:0]
    return rises[: falls.size], falls


def in_window(t: np.ndarray, a: np.ndarray, b: np.ndarray, lo: float, hi: float) -> np.ndarray:
    return (t[a] >= lo - EPS_T) & (t[b] <= hi + EPS_T)


def counted_strides(
    t: np.ndarray, ref_on: np.ndarray, lo: float, hi: float, ref_name: str
) -> tuple[np.ndarray, np.ndarray, str]:
    """Counted strides as sample indices (start, end) of consecutive reference touchdowns."""
    touchdowns, _ = _edges(ref_on)
    a, b = touchdowns[:-1], touchdowns[1:]
    keep = in_window(t, a, b, lo, hi)
    a, b = a[keep], b[keep]
    note = ""
    if a.size == 0:
        inside = touchdowns_in_window(t, ref_on, lo, hi)
        note = (
            f"the reference foot ({ref_name}) touches down {inside} time(s) in the window; "
            "a stride needs two"
        )
    return a, b, note


def touchdowns_in_window(t: np.ndarray, on: np.ndarray, lo: float, hi: float) -> int:
    touchdowns, _ = _edges(on)
    return int(np.count_nonzero((t[touchdowns] >= lo - EPS_T) & (t[touchdowns] <= hi + EPS_T)))


def _stride_of(index: int, starts: np.ndarray, ends: np.ndarray) -> int:
    k = int(np.searchsorted(starts, index, side="right")) - 1
    return k if k >= 0 and index < ends[k] else -1


def stride_series(
    tr: Trajectory,
    starts: np.ndarray,
    ends: np.ndarray,
    cols: dict[str, int],
    joint_slides: bool = False,
) -> dict[str, list[float]]:
    """One value per counted stride. Means use the samples ``[start, end)`` so a periodic
    signal is averaged over whole periods; extrema use ``[start, end]``. The joint's magnitude
    is in degrees, or in metres for a sliding joint."""
    t, g, mass = tr.t, tr.gravity, tr.total_mass
    yaw = tr.root_rpy[:, 2]
    forward = tr.com_vel[:, 0] * np.cos(yaw) + tr.com_vel[:, 1] * np.sin(yaw)
    horizontal = tr.com[:, :2] if not tr.planar else tr.com[:, :1]
    if mass > 0:
        fz = tr.force[:, :, 2].sum(axis=1)
        acc_g = (fz / mass - g) / g
    else:  # no mass recorded: the acceleration cannot be told from the forces
        acc_g = np.full(len(tr), np.nan)
    e_ext = 0.5 * mass * np.sum(tr.com_vel**2, axis=1) + mass * g * tr.com[:, 2]
    pitch, roll = np.degrees(tr.root_rpy[:, 1]), np.degrees(tr.root_rpy[:, 0])

    names = ["t_start", "t_end", "duration", "length", "pitch_magnitude", "roll_magnitude"]
    names += ["speed", "speed_command", "speed_error", "peak_vertical_acceleration"]
    names += ["energy_fluctuation", "energy_taken_up"]
    series: dict[str, list[float]] = {k: [] for k in names}
    if "joint" in cols:
        series["joint_magnitude"] = []
    if "against" in cols:
        series["joint_correlation"] = []
    for a, b in zip(starts.tolist(), ends.tolist(), strict=True):
        closed = slice(a, b + 1)
        cmd = tr.speed_command[a:b]
        series["t_start"].append(float(t[a]))
        series["t_end"].append(float(t[b]))
        series["duration"].append(float(t[b] - t[a]))
        series["length"].append(_displacement(horizontal[b] - horizontal[a]))
        series["pitch_magnitude"].append(_ptp(pitch[closed]))
        series["roll_magnitude"].append(math.nan if tr.planar else _ptp(roll[closed]))
        series["speed"].append(float(np.mean(forward[a:b])))
        series["speed_command"].append(finite_mean(cmd))
        series["speed_error"].append(finite_mean(forward[a:b] - cmd))
        series["peak_vertical_acceleration"].append(float(np.max(acc_g[closed])))
        series["energy_fluctuation"].append(_ptp(e_ext[closed]))
        # every fall, not max - min: a trot's or a biped's stride takes up energy twice
        falls = np.diff(e_ext[closed])
        series["energy_taken_up"].append(float(-np.sum(falls[falls < 0])))
        if "joint" in cols:
            q = tr.q[closed, cols["joint"]]
            series["joint_magnitude"].append(_ptp(q) if joint_slides else math.degrees(_ptp(q)))
            if "against" in cols:
                series["joint_correlation"].append(_correlation(q, tr.q[closed, cols["against"]]))
    return series


def _displacement(d: np.ndarray) -> float:
    """Planar: the signed forward displacement; 3D: the horizontal straight-line distance."""
    return float(d[0]) if d.size == 1 else float(np.hypot(d[0], d[1]))


def _ptp(x: np.ndarray) -> float:
    return float(np.max(x) - np.min(x))


def _correlation(x: np.ndarray, y: np.ndarray) -> float:
    """Pearson correlation; NaN when either signal is constant (no phase to speak of)."""
    if _ptp(x) == 0 or _ptp(y) == 0:
        return math.nan
    return float(np.corrcoef(x, y)[0, 1])


def all_stances(
    tr: Trajectory, units: list[Unit], starts: np.ndarray, ends: np.ndarray, lo: float, hi: float
) -> list[Stance]:
    out: list[Stance] = []
    for u in units:
        a, b = runs(touching(tr, u.contacts))
        keep = in_window(tr.t, a, b, lo, hi)
        for s, e in zip(a[keep].tolist(), b[keep].tolist(), strict=True):
            leg = _compression(tr, u.legs[0], s, e) if u.kind == "leg" else _NONE
            out.append(
                Stance(
                    unit=u.name,
                    kind=u.kind,
                    t_touchdown=float(tr.t[s]),
                    t_liftoff=float(tr.t[e]),
                    stride=_stride_of(s, starts, ends),
                    leg_length_change=leg[0],
                    stored_energy=leg[1],
                )
            )
    return out


_NONE = (math.nan, math.nan, -1)


def _compression(tr: Trajectory, leg: int, s: int, e: int) -> tuple[float, float, int]:
    """A leg's shortening in the stance ``[s, e)`` (its length at touchdown less its least),
    the elastic energy its springs took up while it shortened (their peak from touchdown to
    the sample before the least length, above their touchdown value), and the sample of the
    least length. Neither counts the thrust: a leg lengthened past its touchdown length, or a
    spring whose rest the controller lengthens, is the actuator's work, not the landing's. The
    least length's own sample is left out: a controller that lengthens the rest as soon as the
    leg stops shortening (the quadruped's THRUST) has done so by then (its trot's rear legs:
    27 J there, 4.5 J a sample before)."""
    length = tr.leg_length[s:e, leg]
    bottom = int(np.argmin(length))
    spring = tr.leg_spring_energy[s:e, leg]
    held = float(np.max(spring[: max(bottom, 1)]))
    return float(length[0] - length[bottom]), held - float(spring[0]), s + bottom


def with_recirculation(
    tr: Trajectory,
    units: list[Unit],
    starts: np.ndarray,
    ends: np.ndarray,
    per_stride: dict[str, list[float]],
) -> None:
    """Add to ``per_stride`` the elastic energy the legs' springs store in it and its fraction
    of the external energy the stride takes up. Each leg counts on its own, whatever virtual
    legs were asked for (a display option must not change an energy), in the stride its
    largest compression falls in: a leg landing a sample before the reference foot stores its
    energy in the reference's stride, as it takes up the body's."""
    stored = [0.0] * len(starts)
    for u in units:
        if u.kind != "leg":
            continue
        a, b = runs(touching(tr, u.contacts))
        for s, e in zip(a.tolist(), b.tolist(), strict=True):
            _, energy, bottom = _compression(tr, u.legs[0], s, e)
            k = _stride_of(bottom, starts, ends)
            if k >= 0:
                stored[k] += energy
    per_stride["stored_energy"] = stored
    per_stride["energy_recirculated"] = [
        e / taken if taken > 0 else math.nan
        for e, taken in zip(stored, per_stride["energy_taken_up"], strict=True)
    ]


def all_flights(
    tr: Trajectory, units: list[Unit], starts: np.ndarray, ends: np.ndarray, lo: float, hi: float
) -> list[Flight]:
    if not tr.contact_names:
        return []
    touching = tr.contact != 0
    a, b = runs(~touching.any(axis=1))
    keep = in_window(tr.t, a, b, lo, hi)
    # Name a flight by the virtual leg (or else the leg) whose touchdown ends it.
    owner: dict[int, str] = {}
    for u in sorted(units, key=lambda u: u.kind != "group"):
        for c in u.contacts:
            owner.setdefault(c, u.name)
    out = []
    for s, e in zip(a[keep].tolist(), b[keep].tolist(), strict=True):
        landing = np.flatnonzero(touching[e])
        before = "+".join(sorted({owner.get(int(c), tr.contact_names[c]) for c in landing}))
        out.append(Flight(float(tr.t[s]), float(tr.t[e]), before, _stride_of(s, starts, ends)))
    return out


def debounced(tr: Trajectory, min_stance: float | None) -> Trajectory:
    """``tr`` with every contact shorter than ``min_stance`` (touchdown to liftoff) taken out
    of its flags, so that it neither starts a stride nor counts as a stance or a touch; a
    contact whose start or end was not recorded is kept (its length is not known)."""
    if min_stance is None:
        return tr
    contact = tr.contact.copy()
    for c in range(contact.shape[1]):
        a, b = runs(contact[:, c] != 0)
        short = tr.t[b] - tr.t[a] < min_stance - EPS_T
        for s, e in zip(a[short].tolist(), b[short].tolist(), strict=True):
            contact[s:e, c] = 0
    return replace(tr, contact=contact)


def feet_contacts(
    tr: Trajectory, units: list[Unit], lo: float, hi: float
) -> list[tuple[float, str, float]]:
    """(touchdown, foot, duration) of each complete contact in the window of each leg's foot
    (of each contact, for a run without legs)."""
    feet = [(u.name, u.contacts[0]) for u in units if u.kind != "group" and u.contacts]
    seen: list[tuple[float, str, float]] = []
    for name, c in feet:
        a, b = runs(tr.contact[:, c] != 0)
        keep = in_window(tr.t, a, b, lo, hi)
        ta, tb = tr.t[a[keep]], tr.t[b[keep]]
        seen += [(float(x), name, float(y - x)) for x, y in zip(ta, tb, strict=True)]
    return seen


def scuff_note(tr: Trajectory, units: list[Unit], lo: float, hi: float) -> str:
    """Which feet's contacts in the window last under ``SCUFF_FRACTION`` of the median stance
    of every foot there, and the ``--min-stance`` that would leave them out ("" if none)."""
    seen = feet_contacts(tr, units, lo, hi)
    if not seen:
        return ""
    usual = float(np.median([d for _, _, d in seen]))
    scuffs = sorted(s for s in seen if s[2] < SCUFF_FRACTION * usual)
    if not scuffs:
        return ""
    above_ms = math.floor(max(d for _, _, d in scuffs) * 1000 + 1e-6) + 1
    listed = ", ".join(f"{name} at {t:.3f} s ({d:.3f} s)" for t, name, d in scuffs[:8])
    more = f" and {len(scuffs) - 8} more" if len(scuffs) > 8 else ""
    return (
        f"{len(scuffs)} touchdown(s) look like scuffs, contacts under a third of the feet's "
        f"median stance ({usual:.3f} s): {listed}{more}; each counts as a stance and, on the "
        f"reference, starts a stride; --min-stance {above_ms}ms leaves them out"
    )
