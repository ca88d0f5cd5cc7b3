"""Gait metrics of a recorded run, measured as Table 2 of Raibert & Hodgins (1991) measures them.

Everything is computed from a ``Trajectory``: touchdowns and liftoffs are the 0->1 and 1->0
edges of the ``contact`` flags. A touchdown happens at the first sample in contact and a
liftoff at the first sample out of contact, so a stance is the half-open
sample range ``[touchdown, liftoff)`` and its duration is exact to one sample. The touchdown
spreads and the support phases, whose thresholds and leads are a few ms, are timed by the
events in ``run.json`` (exact to the step) where they are given (``contact_times``).

Definitions (docs/metrics.md has the long form):

- **Stride**: from one touchdown of the reference foot to its next. Only
  strides that lie entirely inside the window ``[t_from, t_to]`` count.
- **Stance** of a leg: touchdown to liftoff of its foot; of a virtual leg (a
  group of legs): the union of their contact. **Flight**: no contact at all
  touches. Stances and flights count when both their ends were seen inside the
  window (a run that starts in stance or ends mid-stance leaves those out).
- **Touchdowns** with ``min_stance``: a contact shorter than it is none (it starts no
  stride and is no stance); without it every contact counts, and ``scuff_note`` says which
  look like scuffs.
- **Peak vertical acceleration** of the centre of mass, in g, from the ground
  reaction: ``(sum(force[:, :, 2]) / total_mass - gravity) / gravity``.
- **Friction coefficient needed**: ``|tangential force| / normal force`` during
  stance, normal = z; samples whose normal force is below a floor (a fraction
  of body weight) are skipped because the ratio means nothing there.
- **Elastic energy recirculated per step** (after Alexander 1988): over each stride, the
  elastic energy the leg springs take up while each leg shortens (their peak from touchdown to
  the sample before its least length, above their touchdown value), divided by the external
  mechanical energy ``1/2 M |com_vel|^2 + M g com_z`` the stride takes up (its falls).
- **Positive actuator work**, **energy per metre** and **cost of transport** over the
  window (``energy``): the rise of the recorded running sums of max(0, tau qd) dt, per
  metre of the centre of mass's horizontal path, and divided by the weight ``M g``.
- A creature whose root body is **welded** to the world (``fixed at``; the caller says so,
  from the creature, as ``legdsl run``'s summary decides it) goes nowhere and cannot pitch or
  roll: the rows and per-stride series of travel and of the root's attitude (``TRAVEL``)
  read n/a, each saying why (``results.WELDED``), however its centre of mass sways.

This module is the entry, ``compute_metrics``, and the names the command line uses; the work
is done in ``strides`` (strides, stances, flights), ``friction``, ``rows`` and ``support``
(the averaged rows), on the types of ``results``; ``table2`` holds the paper's numbers and
``path_report`` the path-following report.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

from legdsl.analysis.contact_times import contact_times
from legdsl.analysis.ended import measured_until
from legdsl.analysis.energy import energy_rows
from legdsl.analysis.friction import LEVEL, MIN_NORMAL_FRACTION, contact_friction
from legdsl.analysis.option_notes import friction_edge_note, min_stance_note, time_text
from legdsl.analysis.pairs import pair_rows
from legdsl.analysis.plot_ending import run_ending
from legdsl.analysis.resolution import natural_sizes
from legdsl.analysis.results import (
    FRICTION_EDGE,
    WELDED,
    GaitMetrics,
    MetricsError,
    Summary,
)
from legdsl.analysis.rows import summary_rows
from legdsl.analysis.strides import (
    all_flights,
    all_stances,
    coordinates,
    counted_strides,
    debounced,
    reference,
    scuff_note,
    stance_units,
    stride_series,
    touchdowns_in_window,
    touching,
    with_recirculation,
)
from legdsl.analysis.support import with_support_rows
from legdsl.sim.trajectory import Trajectory

# the rows that mean the creature's travel over the ground or its root body's attitude, and
# the per-stride series they average: n/a for a root welded to the world (the centre of mass
# of a test rig sways with its limbs: a stride "length" of 0.061 m, a "speed" of 0.036 m/s)
TRAVEL = {
    "stride_length": "length",
    "pitch_magnitude": "pitch_magnitude",
    "roll_magnitude": "roll_magnitude",
    "running_speed": "speed",
    "speed_error": "speed_error",
    "distance": None,
    "energy_per_metre": None,
    "cost_of_transport": None,
}
# what a path report measures of the centre of mass's way along the path (path_report.py)
PATH_TRAVEL = ("progress", "laps", "past_end", "lateral_rms", "lateral_max", "lateral_mean",
               "path_speed")  # fmt: skip


def parse_groups(specs: Sequence[str]) -> dict[str, list[str]]:
    """``["front=fl,fr", "rear=rl,rr"]`` -> ``{"front": ["fl", "fr"], "rear": ["rl", "rr"]}``."""
    groups: dict[str, list[str]] = {}
    for spec in specs:
        name, eq, members = spec.partition("=")
        legs = [m.strip() for m in members.split(",") if m.strip()]
        if not eq or not name.strip() or not legs:
            raise MetricsError(f"a group is written NAME=LEG,LEG (got {spec!r})")
        if name.strip() in groups:
            raise MetricsError(
                f"group {name.strip()!r} is given twice: give each --group a name of its own"
            )
        groups[name.strip()] = legs
    return groups


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
    joint_slides: bool = False,
    min_stance: float | None = None,
    ground_normal: tuple[float, float, float] = LEVEL,
    events: Sequence[Mapping[str, Any]] | None = None,
    welded: bool = False,
    run_info: Mapping[str, Any] | None = None,
) -> GaitMetrics:
    """Measure a run: strides by the reference ``leg`` (a leg, a group name, or a contact;
    default the first leg's foot), virtual legs from ``groups``, the per-stride magnitude of
    coordinate ``joint`` (in degrees, or in metres when ``joint_slides``: the trajectory does
    not say which) and its correlation with coordinate ``against``.

    ``min_stance`` (s): a contact shorter than this is no touchdown (default None: every
    contact is one, and ``GaitMetrics.scuff_note`` names those that look like scuffs).
    ``edge`` (s): left out at each end of a stance for the interior friction row (the paper's
    10 ms; a creature of size L scaled dynamically has its stances, and so this, √L as long).
    ``ground_normal``: the ground's unit normal, which the friction needed is measured
    against (a slope's; the trajectory does not say it). ``events``: run.json's, which time
    the touchdown spreads and the support phases to the step (``contact_times``).
    ``welded``: the creature's root body is welded to the world (``Model.welded_root``;
    the trajectory does not say it): its rows of travel and attitude read n/a. ``run_info``:
    run.json's content, which says how the run ended: the window of a run that fell or
    diverged ends at the reference's last touchdown before it did (``ended``), and the
    result says how it ended (``status``, ``ending``; None: a trajectory without run.json).

    The peak vertical acceleration is that of the centre of mass computed from the ground
    reaction, ``sum(force[:, :, 2]) / total_mass - gravity``, divided by gravity.
    """
    t = tr.t
    end = float(t[-1]) if len(tr) else 0.0
    t_to = end if t_to is None else float(t_to)
    for side, at in (("starts", t_from), ("ends", t_to)):
        if not at >= 0.0:  # a NaN too
            raise MetricsError(f"the window {side} at {at:g} s; give a time of 0 s or more")
    if t_to < t_from:
        raise MetricsError(f"the window ends ({t_to:g} s) before it starts ({t_from:g} s)")
    past = f"--to {t_to:g}s is after the run's end: measured to its end, {end:.3f} s"
    past, t_to = (past, end) if t_to > end and len(tr) else ("", t_to)  # the header said 10 s
    if min_stance is not None and not (math.isfinite(min_stance) and min_stance > 0):
        raise MetricsError(f"--min-stance {min_stance!r}: give a time more than zero, e.g. 20ms")
    if not (math.isfinite(edge) and edge >= 0):
        raise MetricsError(f"--friction-edge {edge!r}: give a time of 0 s or more, e.g. 10ms")
    units = stance_units(tr, dict(groups or {}))
    raw, tr = tr, debounced(tr, min_stance)
    ref_name, ref_contacts = reference(tr, units, leg)
    ending = None if run_info is None else run_ending(dict(run_info))
    t_to, cut = measured_until(t, touching(tr, ref_contacts), ref_name if tr.contact_names
                               else None, t_from, t_to, ending)  # fmt: skip
    scuffs = scuff_note(raw, units, t_from, t_to) if min_stance is None else ""
    times = contact_times(tr, events)
    cols = coordinates(tr, joint, against)

    starts, ends, note = counted_strides(t, touching(tr, ref_contacts), t_from, t_to, ref_name)
    if note and min_stance is not None:  # the run touched down more than the filter left
        left_out = touchdowns_in_window(
            t, touching(raw, ref_contacts), t_from, t_to
        ) - touchdowns_in_window(t, touching(tr, ref_contacts), t_from, t_to)
        if left_out:
            note += f" (--min-stance {time_text(min_stance)} left out {left_out} more)"
    if not tr.contact_names:
        note = "the creature has no contacts, so it takes none (only the work rows apply)"
    per_stride = stride_series(tr, starts, ends, cols, joint_slides)
    stances = all_stances(tr, units, starts, ends, t_from, t_to)
    flights = all_flights(tr, units, starts, ends, t_from, t_to)
    per_stride["flight_time"] = [
        float(sum(f.duration for f in flights if f.stride == k)) for k in range(len(starts))
    ]
    per_stride["flight_count"] = [
        float(sum(1 for f in flights if f.stride == k)) for k in range(len(starts))
    ]
    with_recirculation(tr, units, starts, ends, per_stride)
    friction = [
        contact_friction(tr, c, t_from, t_to, edge, min_normal_fraction, ground_normal)
        for c in range(len(tr.contact_names))
    ]
    notes = {
        "--min-stance": min_stance_note(raw, units, t_from, t_to, min_stance),
        "--friction-edge": friction_edge_note(tr, friction, t_from, t_to),
        "--to": past,
    }
    options = {
        "leg": leg,
        "groups": {k: list(v) for k, v in (groups or {}).items()},
        "joint": joint,
        "against": against,
        "friction_edge_s": edge,
        "min_normal_fraction": min_normal_fraction,
        "min_stance_s": min_stance,
    }
    measured = GaitMetrics(
        t_from=float(t_from),
        t_to=t_to,
        reference=ref_name,
        per_stride=per_stride,
        stances=stances,
        flights=flights,
        friction=friction,
        summaries=with_support_rows(
            summary_rows(
                tr, units, per_stride, stances, flights, friction, joint, against, joint_slides
            ),
            tr,
            t_from,
            t_to,
            times,
        )
        + pair_rows(tr, units, t_from, t_to, times)
        + energy_rows(tr, t_from, t_to),
        note=note,
        options=options,
        scuff_note=scuffs,
        option_notes={flag: said for flag, said in notes.items() if said},
        sizes=natural_sizes(tr),
        status=None if run_info is None else str(run_info.get("status", "ok") or "ok"),
        ending=ending,
        cut=cut,
    )
    return without_travel(measured) if welded else measured


def without_travel(metrics: GaitMetrics, why: str = WELDED) -> GaitMetrics:
    """``metrics`` of a creature that goes nowhere and cannot pitch or roll (its root welded to
    the world): the ``TRAVEL`` rows n/a (NaN, no values), each saying ``why``, and their
    per-stride series NaN (null in JSON); the other rows (stances, flights, energies, forces)
    stand."""
    metrics.summaries = [
        Summary(s.key, s.label, math.nan, math.nan, 0, s.how, why) if s.key in TRAVEL else s
        for s in metrics.summaries
    ]
    for series in TRAVEL.values():
        if series in metrics.per_stride:
            metrics.per_stride[series] = [math.nan] * len(metrics.per_stride[series])
    return metrics


def without_path_travel(report: Mapping[str, Any], why: str = WELDED) -> dict[str, Any]:
    """A path report (``path_report``) of a creature that goes nowhere: its progress, laps,
    lateral deviations and speed along the path n/a (None), saying ``why``, and no off-path
    note (its centre of mass swayed; it did not run off the path)."""
    gone = {k: None for k in PATH_TRAVEL if k in report}
    return {k: v for k, v in report.items() if k != "note"} | gone | {"why": why}
