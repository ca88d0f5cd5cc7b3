"""Gait metrics of a recorded run, measured as Table 2 of Raibert & Hodgins (1991) measures them.

Everything is computed from a ``Trajectory`` alone (the events in ``run.json``
are not needed): touchdowns and liftoffs are the 0->1 and 1->0 edges of the
``contact`` flags. A touchdown happens at the first sample in contact and a
liftoff at the first sample out of contact, so a stance is the half-open
sample range ``[touchdown, liftoff)`` and its duration is exact to one sample.

Definitions (docs/metrics.md has the long form):

- **Stride**: from one touchdown of the reference foot to its next. Only
  strides that lie entirely inside the window ``[t_from, t_to]`` count.
- **Stance** of a leg: touchdown to liftoff of its foot; of a virtual leg (a
  group of legs): the union of their contact. **Flight**: no contact at all
  touches. Stances and flights count when both their ends were seen inside the
  window (a run that starts in stance or ends mid-stance leaves those out).
- **Peak vertical acceleration** of the centre of mass, in g, from the ground
  reaction: ``(sum(force[:, :, 2]) / total_mass - gravity) / gravity``.
- **Friction coefficient needed**: ``|tangential force| / normal force`` during
  stance, normal = z; samples whose normal force is below a floor (a fraction
  of body weight) are skipped because the ratio means nothing there.
- **Elastic energy recirculated per step** (after Alexander 1988): the
  elastic energy the leg springs take up during a stance (peak minus the value
  at touchdown) divided by the fluctuation (max - min) of the external
  mechanical energy ``1/2 M |com_vel|^2 + M g com_z`` over the stride.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from legdsl.sim.trajectory import Trajectory

if TYPE_CHECKING:
    from legdsl.ir.paths import PathSpec

FRICTION_EDGE = 0.010  # s: the paper's "period of up to 10 ms" at each end of a stance
MIN_NORMAL_FRACTION = 0.01  # of body weight: below this the friction ratio is not computed
_EPS_T = 1e-9  # s: slack for comparing sample times that went through floating point


class MetricsError(ValueError):
    """A request the run cannot answer: an unknown leg, group or coordinate, an empty window."""


# ---------------------------------------------------------------- results


@dataclass(frozen=True)
class Stance:
    """One complete stance of a leg, a virtual leg (``kind == "group"``) or a bare contact."""

    unit: str
    kind: str  # "leg", "group" or "contact"
    t_touchdown: float  # s
    t_liftoff: float  # s
    stride: int  # index of the counted stride its touchdown falls in, -1 if none
    leg_length_change: float  # m: max - min of leg_length during the stance (legs only)
    stored_energy: float  # J: peak leg-spring energy in the stance minus its value at touchdown
    recirculated: float  # stored_energy / external-energy fluctuation of its stride

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


@dataclass(frozen=True)
class Summary:
    """One row of the table: a mean over strides, stances or steps, or a maximum."""

    key: str
    label: str  # Table 2 wording, unit in brackets
    value: float
    std: float  # sample standard deviation; NaN for a maximum or fewer than two values
    n: int  # how many values went in
    how: str = "mean"  # or "max"


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

    @property
    def n_strides(self) -> int:
        return len(self.per_stride["duration"])

    def summary(self, key: str) -> Summary:
        for s in self.summaries:
            if s.key == key:
                return s
        raise KeyError(key)

    def value(self, key: str) -> float:
        return self.summary(key).value

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready data; NaN becomes null."""
        data = {
            "window": {"from": self.t_from, "to": self.t_to},
            "reference": self.reference,
            "n_strides": self.n_strides,
            "note": self.note,
            "options": self.options,
            "summary": {
                s.key: {k: v for k, v in asdict(s).items() if k != "key"} for s in self.summaries
            },
            "strides": self.per_stride,
            "stances": [asdict(s) | {"duration": s.duration} for s in self.stances],
            "flights": [asdict(f) | {"duration": f.duration} for f in self.flights],
            "friction": [asdict(f) for f in self.friction],
        }
        return _jsonable(data)

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
        for s in self.summaries:
            spread = "(peak)" if s.how == "max" else _num(s.std)  # a maximum has no spread
            lines.append(f"{s.label:<{width}}  {_num(s.value):>10}  {spread:>10}  {s.n:>4}")
        return "\n".join(lines) + "\n"


def compare_table(
    metrics: GaitMetrics,
    reference_rows: Mapping[str, Sequence[float | None]],
    headers: Sequence[str] = ("robot/animal", "paper animation"),
) -> str:
    """The run's values beside reference columns (e.g. ``TABLE2["kangaroo hop"]``), as text.

    Rows are matched by label (``"stride duration (s)"``) or key
    (``"stride_duration"``); a row the run did not measure shows ``n/a``.
    """
    by_name = {s.label: s for s in metrics.summaries} | {s.key: s for s in metrics.summaries}
    width = max([len(name) for name in reference_rows] + [8])
    cols = [f"{h:>15}" for h in headers]
    lines = [f"{'quantity':<{width}}  {'this run':>17}  " + "  ".join(cols)]
    for name, refs in reference_rows.items():
        s = by_name.get(name)
        run = "n/a" if s is None else _num(s.value)
        if s is not None and math.isfinite(s.std):
            run += f" +/- {_num(s.std)}"
        ref = "  ".join(f"{'n/a' if r is None else f'{r:g}':>15}" for r in refs)
        lines.append(f"{name:<{width}}  {run:>17}  {ref}")
    return "\n".join(lines) + "\n"


# Table 2 of the paper: (robot or animal, paper animation), keyed by this module's labels.
# The bound assumes virtual legs named "front" and "rear": its extended flight ends at the
# front touchdown, its gathered flight at the rear touchdown. The kangaroo's "tail wag
# relative to trunk" is the magnitude of its tail_base coordinate (--joint tail_base).
TABLE2: dict[str, dict[str, tuple[float, float]]] = {
    "quadruped bound": {
        "pitch magnitude (deg)": (26.4, 25.8),
        "stride length (m)": (1.15, 1.22),
        "stride duration (s)": (0.37, 0.43),
        "flight duration before rear (s)": (0.11, 0.22),
        "flight duration before front (s)": (0.04, 0.03),
        "stance duration, front (s)": (0.10, 0.10),
        "stance duration, rear (s)": (0.12, 0.08),
        "change of leg length during support (m)": (0.085, 0.092),
        "running speed (m/s)": (2.9, 2.8),
        "error in running speed (m/s)": (1.25, 1.2),
    },
    "quadruped trot": {
        "pitch magnitude (deg)": (2.2, 6.2),
        "stride length (m)": (1.84, 1.49),
        "stride duration (s)": (0.80, 0.54),
        "flight duration (s)": (0.27, 0.18),
        "stance duration (s)": (0.12, 0.09),
        "change of leg length during support (m)": (0.04, 0.03),
        "desired running speed (m/s)": (2.3, 2.3),
        "error in running speed (m/s)": (0.7, 0.2),
    },
    "biped run": {
        "pitch magnitude (deg)": (2.0, 3.4),
        "roll magnitude (deg)": (6.7, 11.5),
        "stride length (m)": (0.57, 0.74),
        "stride duration (s)": (0.36, 0.47),
        "flight duration (s)": (0.18, 0.29),
        "stance duration (s)": (0.18, 0.18),
        "change of leg length during support (m)": (0.01, 0.04),
        "error in running speed (m/s)": (-0.3, 0.2),
    },
    "kangaroo hop": {
        "peak vertical acceleration (g)": (5.0, 4.6),
        "pitch magnitude (deg)": (10.0, 12.0),
        "magnitude of tail_base (deg)": (30.0, 31.0),
        "stride length (m)": (2.2, 1.5),
        "stride duration (s)": (0.35, 0.35),
        "flight duration (s)": (0.25, 0.24),
        "stance duration (s)": (0.10, 0.11),
        "desired running speed (m/s)": (6.2, 5.0),
    },
}


def write_json(metrics: GaitMetrics, path: Path) -> None:
    """Write ``metrics.to_dict()`` to ``path`` whole or not at all."""
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(json.dumps(metrics.to_dict(), indent=2, allow_nan=False) + "\n")
    tmp.replace(path)


def parse_groups(specs: Sequence[str]) -> dict[str, list[str]]:
    """``["front=fl,fr", "rear=rl,rr"]`` -> ``{"front": ["fl", "fr"], "rear": ["rl", "rr"]}``."""
    groups: dict[str, list[str]] = {}
    for spec in specs:
        name, eq, members = spec.partition("=")
        legs = [m.strip() for m in members.split(",") if m.strip()]
        if not eq or not name.strip() or not legs:
            raise MetricsError(f"a group is written NAME=LEG,LEG (got {spec!r})")
        if name.strip() in groups:
            raise MetricsError(f"group {name.strip()!r} is given twice")
        groups[name.strip()] = legs
    return groups


# ---------------------------------------------------------------- computing


@dataclass(frozen=True)
class _Unit:
    """Something that has stances: a leg, a virtual leg, or a contact of a run without legs."""

    name: str
    kind: str
    contacts: tuple[int, ...]
    legs: tuple[int, ...]


def compute_metrics(
    tr: Trajectory,
    *,
    t_from: float = 0.0,
    t_to: float | None = None,
    leg: str | None = None,
    groups: Mapping[str, Sequence[str]] | None = None,
    joint: str | None = None,
    against: str | None = None,
    edge: float = FRICTION_EDGE,
    min_normal_fraction: float = MIN_NORMAL_FRACTION,
) -> GaitMetrics:
    """Measure a run: strides by the reference ``leg`` (a leg, a group name, or a contact;
    default the first leg's foot), virtual legs from ``groups``, the per-stride magnitude of
    coordinate ``joint`` and its correlation with coordinate ``against``.

    The peak vertical acceleration is that of the centre of mass computed from the ground
    reaction, ``sum(force[:, :, 2]) / total_mass - gravity``, divided by gravity.
    """
    t = tr.t
    end = float(t[-1]) if len(tr) else 0.0
    t_to = end if t_to is None else float(t_to)
    if t_to < t_from:
        raise MetricsError(f"the window ends ({t_to:g} s) before it starts ({t_from:g} s)")
    units = _units(tr, dict(groups or {}))
    ref_name, ref_contacts = _reference(tr, units, leg)
    cols = _coordinates(tr, joint, against)

    starts, ends, note = _strides(t, _touching(tr, ref_contacts), t_from, t_to, ref_name)
    per_stride = _stride_series(tr, starts, ends, cols)
    stances = _all_stances(tr, units, starts, ends, per_stride["energy_fluctuation"], t_from, t_to)
    flights = _flights(tr, units, starts, ends, t_from, t_to)
    per_stride["flight_time"] = [
        float(sum(f.duration for f in flights if f.stride == k)) for k in range(len(starts))
    ]
    per_stride["flight_count"] = [
        float(sum(1 for f in flights if f.stride == k)) for k in range(len(starts))
    ]
    friction = [
        _friction(tr, c, t_from, t_to, edge, min_normal_fraction)
        for c in range(len(tr.contact_names))
    ]
    options = {
        "leg": leg,
        "groups": {k: list(v) for k, v in (groups or {}).items()},
        "joint": joint,
        "against": against,
        "friction_edge_s": edge,
        "min_normal_fraction": min_normal_fraction,
    }
    return GaitMetrics(
        t_from=float(t_from),
        t_to=t_to,
        reference=ref_name,
        per_stride=per_stride,
        stances=stances,
        flights=flights,
        friction=friction,
        summaries=_with_support_rows(
            _summaries(tr, units, per_stride, stances, flights, friction, joint, against),
            tr,
            t_from,
            t_to,
        ),
        note=note,
        options=options,
    )


def _units(tr: Trajectory, groups: dict[str, Sequence[str]]) -> list[_Unit]:
    legs = list(tr.leg_names)
    if legs:
        units = [_Unit(n, "leg", _foot(tr, i), (i,)) for i, n in enumerate(legs)]
    else:  # a run without legs: each contact stands for itself
        units = [_Unit(n, "contact", (i,), ()) for i, n in enumerate(tr.contact_names)]
    taken = {u.name for u in units}
    for name, members in groups.items():
        unknown = [m for m in members if m not in legs]
        if unknown:
            raise MetricsError(
                f"group {name!r}: no leg named {', '.join(unknown)} (legs: {', '.join(legs) or 'none'})"
            )
        if name in taken:
            raise MetricsError(f"group {name!r} has the name of a leg")
        idx = tuple(legs.index(m) for m in members)
        units.append(_Unit(name, "group", sum((_foot(tr, i) for i in idx), ()), idx))
    return units


def _foot(tr: Trajectory, leg: int) -> tuple[int, ...]:
    """The contact index of a leg's foot; none if the recording names no valid foot for it."""
    feet = tr.leg_feet
    ok = leg < len(feet) and 0 <= feet[leg] < len(tr.contact_names)
    return (feet[leg],) if ok else ()


def _reference(tr: Trajectory, units: list[_Unit], leg: str | None) -> tuple[str, tuple[int, ...]]:
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


def _coordinates(tr: Trajectory, joint: str | None, against: str | None) -> dict[str, int]:
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


def _touching(tr: Trajectory, contacts: Sequence[int]) -> np.ndarray:
    """True where any of ``contacts`` touches: the stance of a leg or of a virtual leg."""
    if not contacts:
        return np.zeros(len(tr), dtype=bool)
    return np.any(tr.contact[:, list(contacts)] != 0, axis=1)


def _edges(on: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Sample indices of rises (first sample on) and falls (first sample off)."""
    d = np.diff(on.astype(np.int8))
    return np.flatnonzero(d == 1) + 1, np.flatnonzero(d == -1) + 1


def _runs(on: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Complete runs of ``on`` as half-open ``[start, stop)``: a run already on at the first
    sample, or still on at the last, is left out because one of its ends was not seen."""
    rises, falls = _edges(on)
    falls = falls[falls > rises[0]] if rises.size else falls[:0]
    return rises[: falls.size], falls


def _in_window(t: np.ndarray, a: np.ndarray, b: np.ndarray, lo: float, hi: float) -> np.ndarray:
    return (t[a] >= lo - _EPS_T) & (t[b] <= hi + _EPS_T)


def _strides(
    t: np.ndarray, ref_on: np.ndarray, lo: float, hi: float, ref_name: str
) -> tuple[np.ndarray, np.ndarray, str]:
    """Counted strides as sample indices (start, end) of consecutive reference touchdowns."""
    touchdowns, _ = _edges(ref_on)
    a, b = touchdowns[:-1], touchdowns[1:]
    keep = _in_window(t, a, b, lo, hi)
    a, b = a[keep], b[keep]
    note = ""
    if a.size == 0:
        inside = int(
            np.count_nonzero((t[touchdowns] >= lo - _EPS_T) & (t[touchdowns] <= hi + _EPS_T))
        )
        note = (
            f"the reference foot ({ref_name}) touches down {inside} time(s) in the window; "
            "a stride needs two"
        )
    return a, b, note


def _stride_of(index: int, starts: np.ndarray, ends: np.ndarray) -> int:
    k = int(np.searchsorted(starts, index, side="right")) - 1
    return k if k >= 0 and index < ends[k] else -1


def _stride_series(
    tr: Trajectory, starts: np.ndarray, ends: np.ndarray, cols: dict[str, int]
) -> dict[str, list[float]]:
    """One value per counted stride. Means use the samples ``[start, end)`` so a periodic
    signal is averaged over whole periods; extrema use ``[start, end]``."""
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
    series: dict[str, list[float]] = {k: [] for k in names + ["energy_fluctuation"]}
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
        series["speed_command"].append(_finite_mean(cmd))
        series["speed_error"].append(_finite_mean(forward[a:b] - cmd))
        series["peak_vertical_acceleration"].append(float(np.max(acc_g[closed])))
        series["energy_fluctuation"].append(_ptp(e_ext[closed]))
        if "joint" in cols:
            q = tr.q[closed, cols["joint"]]
            series["joint_magnitude"].append(math.degrees(_ptp(q)))
            if "against" in cols:
                series["joint_correlation"].append(_correlation(q, tr.q[closed, cols["against"]]))
    return series


def _displacement(d: np.ndarray) -> float:
    """Planar: the signed forward displacement; 3D: the horizontal straight-line distance."""
    return float(d[0]) if d.size == 1 else float(np.hypot(d[0], d[1]))


def _ptp(x: np.ndarray) -> float:
    return float(np.max(x) - np.min(x))


def _finite_mean(x: np.ndarray) -> float:
    ok = np.isfinite(x)
    return float(np.mean(x[ok])) if ok.any() else math.nan


def _correlation(x: np.ndarray, y: np.ndarray) -> float:
    """Pearson correlation; NaN when either signal is constant (no phase to speak of)."""
    if _ptp(x) == 0 or _ptp(y) == 0:
        return math.nan
    return float(np.corrcoef(x, y)[0, 1])


def _all_stances(
    tr: Trajectory,
    units: list[_Unit],
    starts: np.ndarray,
    ends: np.ndarray,
    fluctuation: list[float],
    lo: float,
    hi: float,
) -> list[Stance]:
    out: list[Stance] = []
    for u in units:
        a, b = _runs(_touching(tr, u.contacts))
        keep = _in_window(tr.t, a, b, lo, hi)
        spring = tr.leg_spring_energy[:, list(u.legs)].sum(axis=1) if u.legs else None
        for s, e in zip(a[keep].tolist(), b[keep].tolist(), strict=True):
            k = _stride_of(s, starts, ends)
            length_change = _ptp(tr.leg_length[s:e, u.legs[0]]) if u.kind == "leg" else math.nan
            stored = float(np.max(spring[s:e]) - spring[s]) if spring is not None else math.nan
            swing = fluctuation[k] if k >= 0 else math.nan
            out.append(
                Stance(
                    unit=u.name,
                    kind=u.kind,
                    t_touchdown=float(tr.t[s]),
                    t_liftoff=float(tr.t[e]),
                    stride=k,
                    leg_length_change=length_change,
                    stored_energy=stored,
                    recirculated=stored / swing if swing > 0 else math.nan,
                )
            )
    return out


def _flights(
    tr: Trajectory, units: list[_Unit], starts: np.ndarray, ends: np.ndarray, lo: float, hi: float
) -> list[Flight]:
    if not tr.contact_names:
        return []
    touching = tr.contact != 0
    a, b = _runs(~touching.any(axis=1))
    keep = _in_window(tr.t, a, b, lo, hi)
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


def _friction(
    tr: Trajectory, c: int, lo: float, hi: float, edge: float, min_normal_fraction: float
) -> Friction:
    """|F_t| / F_n over the complete stances of contact ``c``. Samples whose normal force is
    below ``min_normal_fraction`` of body weight (or not pushing at all) are skipped: at the
    first and last instants of contact the ratio of two near-zero forces is noise."""
    floor = min_normal_fraction * tr.total_mass * tr.gravity
    floor = floor if floor > 0 else 1e-9
    fn = tr.force[:, c, 2]
    ratio = np.hypot(tr.force[:, c, 0], tr.force[:, c, 1]) / np.where(fn > floor, fn, np.inf)
    usable = fn > floor
    a, b = _runs(tr.contact[:, c] != 0)
    keep = _in_window(tr.t, a, b, lo, hi)
    peaks, interior_peaks, used, skipped = [], [], 0, 0
    for s, e in zip(a[keep].tolist(), b[keep].tolist(), strict=True):
        t = tr.t[s:e]
        ok = usable[s:e]
        away = (t - tr.t[s] >= edge - _EPS_T) & (tr.t[e] - t > edge + _EPS_T)
        peaks.append(_masked_max(ratio[s:e], ok))
        interior_peaks.append(_masked_max(ratio[s:e], ok & away))
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
    )


def _masked_max(x: np.ndarray, mask: np.ndarray) -> float:
    return float(np.max(x[mask])) if mask.any() else math.nan


def _nanmax(values: Sequence[float]) -> float:
    finite = [v for v in values if math.isfinite(v)]
    return max(finite) if finite else math.nan


# ---------------------------------------------------------------- rows


def _stat(key: str, label: str, values: Sequence[float]) -> Summary:
    x = np.asarray([v for v in values if math.isfinite(v)], dtype=float)
    mean = float(np.mean(x)) if x.size else math.nan
    std = float(np.std(x, ddof=1)) if x.size > 1 else math.nan
    return Summary(key, label, mean, std, int(x.size))


def _summaries(
    tr: Trajectory,
    units: list[_Unit],
    per_stride: dict[str, list[float]],
    stances: list[Stance],
    flights: list[Flight],
    friction: list[Friction],
    joint: str | None,
    against: str | None,
) -> list[Summary]:
    ps = per_stride
    legs = [u for u in units if u.kind in ("leg", "contact")]
    groups = [u for u in units if u.kind == "group"]
    grouped = {leg for g in groups for leg in g.legs}
    rows = [
        _stat("stride_duration", "stride duration (s)", ps["duration"]),
        _stat("stride_length", "stride length (m)", ps["length"]),
        _stat("flight_duration", "flight duration (s)", [f.duration for f in flights]),
    ]
    landings = sorted({f.before for f in flights})
    for name in landings if len(landings) > 1 else []:  # one kind of flight: the row above
        rows.append(
            _stat(
                f"flight_duration_before_{name}",
                f"flight duration before {name} (s)",
                [f.duration for f in flights if f.before == name],
            )
        )
    rows.append(_stat("flight_time", "flight time per stride (s)", ps["flight_time"]))
    leg_stances = [s for s in stances if s.kind != "group"]
    rows.append(_stat("stance_duration", "stance duration (s)", [s.duration for s in leg_stances]))
    for u in (legs if len(legs) > 1 else []) + groups:
        rows.append(
            _stat(
                f"stance_duration_{u.name}",
                f"stance duration, {u.name} (s)",
                [s.duration for s in stances if s.unit == u.name],
            )
        )
    if tr.leg_names:
        changes = [s.leg_length_change for s in stances if s.kind == "leg"]
        rows.append(_stat("leg_length_change", "change of leg length during support (m)", changes))
        for u in legs if len(legs) > 1 else []:
            rows.append(
                _stat(
                    f"leg_length_change_{u.name}",
                    f"change of leg length during support, {u.name} (m)",
                    [s.leg_length_change for s in stances if s.unit == u.name],
                )
            )
    rows += [
        _stat("pitch_magnitude", "pitch magnitude (deg)", ps["pitch_magnitude"]),
        _stat("roll_magnitude", "roll magnitude (deg)", ps["roll_magnitude"]),
        _stat("running_speed", "running speed (m/s)", ps["speed"]),
        _stat("desired_speed", "desired running speed (m/s)", ps["speed_command"]),
        _stat("speed_error", "error in running speed (m/s)", ps["speed_error"]),
        _stat(
            "peak_vertical_acceleration",
            "peak vertical acceleration (g)",
            ps["peak_vertical_acceleration"],
        ),
    ]
    if tr.planar:  # a planar run has no roll
        rows = [r for r in rows if r.key != "roll_magnitude"]
    if joint is not None:
        rows.append(_stat("joint_magnitude", f"magnitude of {joint} (deg)", ps["joint_magnitude"]))
    if against is not None:
        rows.append(
            _stat(
                "joint_correlation",
                f"correlation of {joint} with {against} (-)",
                ps["joint_correlation"],
            )
        )
    # A step is a stance of a virtual leg, or of a leg that belongs to none.
    steps = [
        s
        for s in stances
        if s.kind == "group" or (s.kind == "leg" and tr.leg_names.index(s.unit) not in grouped)
    ]
    if tr.leg_names:
        stored = [s.stored_energy for s in steps]
        fraction = [s.recirculated for s in steps]
        swing = ps["energy_fluctuation"]
        rows += [
            _stat("stored_energy", "elastic energy stored per step (J)", stored),
            _stat("energy_fluctuation", "external energy fluctuation per stride (J)", swing),
            _stat("energy_recirculated", "elastic energy recirculated per step (-)", fraction),
        ]
    for f in friction:
        rows += _friction_rows(f)
    return rows


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


def _support_phases(
    t: np.ndarray, down: np.ndarray, names: Sequence[str], t_from: float, t_to: float
) -> list[SupportPhase]:
    """Split a run into phases of constant support: ``down`` is (samples, feet) true where a
    foot touches. A phase counts when both its ends were seen inside ``[t_from, t_to]``
    (as stances do: a phase still going on at the first or last sample is left out)."""
    if down.ndim != 2 or down.shape[0] < 2 or down.shape[1] == 0:
        return []
    change = np.flatnonzero(np.any(down[1:] != down[:-1], axis=1)) + 1
    bounds = np.concatenate(([0], change, [down.shape[0]]))
    phases = []
    for a, b in zip(bounds[:-1], bounds[1:], strict=True):
        if a == 0 or b == down.shape[0]:  # one end not seen
            continue
        if t[a] < t_from - _EPS_T or t[b] > t_to + _EPS_T:
            continue
        feet = tuple(n for n, on in zip(names, down[a], strict=True) if on)
        kind = ("flight", "single")[len(feet)] if len(feet) < 2 else "double"
        phases.append(SupportPhase(kind, feet, float(t[a]), float(t[b])))
    return phases


def _with_support_rows(
    rows: list[Summary], tr: Trajectory, t_from: float, t_to: float
) -> list[Summary]:
    """Add rows for single and double support when two or more feet touch at once in the
    window (a gallop's stance: single, double, single support); else ``rows`` unchanged."""
    if tr.leg_names:
        cols = [_foot(tr, i) for i in range(len(tr.leg_names))]
        names = [n for n, c in zip(tr.leg_names, cols, strict=True) if c]
        cols = [c for c in cols if c]
    else:
        names, cols = list(tr.contact_names), [(i,) for i in range(len(tr.contact_names))]
    if len(cols) < 2:
        return rows
    down = np.stack([_touching(tr, c) for c in cols], axis=1)
    window = (tr.t >= t_from - _EPS_T) & (tr.t <= t_to + _EPS_T)
    if not (down[window].sum(axis=1) >= 2).any():
        return rows
    phases = _support_phases(tr.t, down, names, t_from, t_to)
    singles = [p for p in phases if p.kind == "single"]
    doubles = [p for p in phases if p.kind == "double"]
    extra = [
        _stat(
            "single_support_duration",
            "single support duration (s)",
            [p.duration for p in singles],
        ),
    ]
    for name in names:
        extra.append(
            _stat(
                f"single_support_duration_{name}",
                f"single support duration, {name} (s)",
                [p.duration for p in singles if p.feet == (name,)],
            )
        )
    extra.append(
        _stat(
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


def _friction_rows(f: Friction) -> list[Summary]:
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
    ]


# ---------------------------------------------------------------- text and JSON


def _num(x: float) -> str:
    return "n/a" if not math.isfinite(x) else f"{x:.3f}"


def _jsonable(x: Any) -> Any:
    if isinstance(x, dict):
        return {str(k): _jsonable(v) for k, v in x.items()}
    if isinstance(x, list | tuple):
        return [_jsonable(v) for v in x]
    if isinstance(x, np.generic):
        x = x.item()
    if isinstance(x, float) and not math.isfinite(x):
        return None
    return x


# ------------------------------------------------------------------ path following
PATH_FROM = 3.0  # s: the report's window starts here by default (after the start-up)


def path_report(
    tr: Trajectory, spec: PathSpec, t_from: float = PATH_FROM, t_to: float | None = None
) -> dict[str, Any]:
    """How well the centre of mass followed a path, from ``t_from``.

    The lateral deviation is the signed distance of the centre of mass from the
    path (positive to the left); its RMS, largest magnitude and mean are taken
    over the samples in the window. The progress is tracked from the run's
    first sample (so laps count from the start); the speed along the path is
    the progress made in the window over its duration.
    """
    from legdsl.sim.path_tracking import PathGeometry, track

    lateral, progress = track(
        spec, [float(x) for x in tr.com[:, 0]], [float(y) for y in tr.com[:, 1]]
    )
    lat = np.asarray(lateral)
    prog = np.asarray(progress)
    end = tr.t[-1] if t_to is None else t_to
    window = (tr.t >= t_from - _EPS_T) & (tr.t <= end + _EPS_T)
    length = PathGeometry(spec).length
    out: dict[str, Any] = {
        "path": spec.describe(),
        "from": float(t_from),
        "to": float(end),
        "samples": int(window.sum()),
        "length": float(length),
        "progress": float(prog[-1] - prog[0]) if len(prog) else math.nan,
        "laps": float((prog[-1] - prog[0]) / length) if len(prog) and length > 0 else math.nan,
    }
    if window.sum() >= 2:
        w = lat[window]
        t = tr.t[window]
        out |= {
            "lateral_rms": float(np.sqrt(np.mean(w**2))),
            "lateral_max": float(np.max(np.abs(w))),
            "lateral_mean": float(np.mean(w)),
            "path_speed": float((prog[window][-1] - prog[window][0]) / (t[-1] - t[0])),
        }
    else:
        out |= dict.fromkeys(("lateral_rms", "lateral_max", "lateral_mean", "path_speed"), math.nan)
    return _jsonable(out)


def path_rows(report: Mapping[str, Any]) -> list[tuple[str, str]]:
    """The report as (label, value) rows for ``legdsl run``'s summary and ``legdsl metrics``."""

    def num(key: str, unit: str) -> str:
        v = report.get(key)
        return "n/a" if v is None else f"{v:.3f}{unit}"

    window = f"from {report['from']:g} s"
    return [
        ("path", str(report["path"])),
        (f"lateral deviation RMS ({window})", num("lateral_rms", " m")),
        (
            f"lateral deviation max / mean ({window})",
            f"{num('lateral_max', ' m')} / {num('lateral_mean', ' m')}",
        ),
        (
            "progress along the path",
            f"{num('progress', ' m')} ({num('laps', '')} laps of {num('length', ' m')})",
        ),
        (f"speed along the path ({window})", num("path_speed", " m/s")),
    ]
