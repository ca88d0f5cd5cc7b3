"""Virtual legs of a quadruped found from where its hips are, and how well a pair is a pair.

Table 2's quadruped rows are about pairs of legs: the bound's front and rear legs, the trot's
diagonals (the pace's lateral pairs). Which legs those are is read from the creature, never
from leg names: each leg's hip point in the root body's frame (the origins of the joints
from the root out to the leg's first joint, at zero joint angles; x forward, y left) is
compared with the middle of all the hips. A leg whose hip is ahead of the middle is a front
leg, one to its left a left leg. This needs four legs: two ahead and two behind for the
front/rear pairs (a planar quadruped too), two left and two right for the lateral ones, both
for the diagonals; any quadruped of other proportions or names qualifies.

    front / rear:  the two front legs, the two rear legs          (bound, gallop)
    diagonal:      front-left with rear-right, front-right with rear-left  (trot)
    lateral:       the two left legs, the two right legs          (pace)

A pair's touchdown spread is, for each stance of the pair (the union of its members'
contact), the time from its first member's touchdown to its last member's (a member that
does not touch in that stance is left out of it): 0 when the pair strikes in unison. The
touchdowns are timed by the run's events, exact to the step (``contact_times``).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from legdsl.analysis.contact_times import ContactTimes, contact_times
from legdsl.analysis.results import MetricsError, Summary
from legdsl.analysis.rows import stat
from legdsl.analysis.strides import EPS_T, Unit, runs, touching
from legdsl.ir.model import Model
from legdsl.sim.trajectory import Trajectory

PAIRINGS = ("front/rear", "diagonal", "lateral")
PAIR_NAMES = {"front/rear": ("front", "rear"), "lateral": ("left", "right")}  # rows read these


def group_hint(pairing: str) -> str:
    """How to give a ``pairing``'s virtual legs by hand."""
    names = PAIR_NAMES.get(pairing)
    given = " ".join(f"--group {n}=LEG,LEG" for n in names) if names else ""
    return "--group NAME=LEG,LEG for each" + (
        f", named as its rows read them: {given}" if names else ""
    )


UNISON = 0.010  # s: members that touch down this close together strike in unison


def hip_positions(model: Model) -> dict[str, tuple[float, float]]:
    """Each leg's hip point (x, y) in the root body's frame, at zero joint angles."""
    joints = {j.name: j for j in model.joints}
    bodies = {b.name: b for b in model.bodies}
    out = {}
    for leg in model.legs:
        joint = joints[leg.joints[0]]
        x, y = joint.origin[0], joint.origin[1]
        parent = joint.parent
        while parent is not None and bodies[parent].parent is not None:
            up = joints[bodies[parent].joint]
            x, y = x + up.origin[0], y + up.origin[1]
            parent = up.parent
        out[leg.name] = (float(x), float(y))
    return out


def pair_groups(positions: Mapping[str, tuple[float, float]], pairing: str) -> dict[str, list[str]]:
    """The virtual legs of a ``pairing`` (one of ``PAIRINGS``) from the legs' hip points."""
    if pairing not in PAIRINGS:
        raise MetricsError(f"pairing {pairing!r}: one of {', '.join(PAIRINGS)}")
    legs = list(positions)
    if len(legs) != 4:
        raise MetricsError(
            f"the {pairing} pairs are those of a quadruped; this creature has {len(legs)} "
            f"leg{'' if len(legs) == 1 else 's'} "
            f"({', '.join(legs)}): give its virtual legs with {group_hint(pairing)}"
        )
    mx = float(np.mean([p[0] for p in positions.values()]))
    my = float(np.mean([p[1] for p in positions.values()]))
    front = [n for n in legs if positions[n][0] > mx]
    left = [n for n in legs if positions[n][1] > my]
    needs = {"front/rear": (front,), "lateral": (left,), "diagonal": (front, left)}[pairing]
    if any(len(half) != 2 for half in needs):  # a planar quadruped has no left and right
        where = ", ".join(f"{n} at ({x:g}, {y:g}) m" for n, (x, y) in positions.items())
        halves = {"front/rear": "two hips ahead of the middle and two behind",
                  "lateral": "two hips left of the middle and two right",
                  "diagonal": "two hips ahead of the middle and two behind, two left and two "
                              "right"}[pairing]  # fmt: skip
        raise MetricsError(
            f"the {pairing} pairs need {halves} (hips: {where}); give its virtual legs with "
            f"{group_hint(pairing)}"
        )
    rear = [n for n in legs if n not in front]
    right = [n for n in legs if n not in left]
    if pairing == "front/rear":
        return {"front": front, "rear": rear}
    if pairing == "lateral":
        return {"left": left, "right": right}

    def corner(a: list[str], b: list[str]) -> str:
        return next(n for n in a if n in b)

    one = [corner(front, left), corner(rear, right)]
    two = [corner(front, right), corner(rear, left)]
    return {"+".join(one): one, "+".join(two): two}


def touchdown_spreads(
    tr: Trajectory, unit: Unit, t_from: float, t_to: float, times: ContactTimes | None = None
) -> list[float]:
    """For each complete stance of a virtual leg in the window, its members' touchdown spread,
    timed by the run's events in ``times`` where it has them (else by the samples)."""
    times = times or contact_times(tr, None)
    a, b = runs(touching(tr, unit.contacts))
    out = []
    for s, e in zip(a.tolist(), b.tolist(), strict=True):
        if tr.t[s] < t_from - EPS_T or tr.t[e] > t_to + EPS_T:
            continue
        firsts = []
        for c in unit.contacts:
            on = np.flatnonzero(tr.contact[s:e, c] != 0)
            if on.size:
                firsts.append(times.touchdown(c, s + int(on[0])))
        if len(firsts) > 1:
            out.append(max(firsts) - min(firsts))
    return out


def pair_rows(
    tr: Trajectory, units: Sequence[Unit], t_from: float, t_to: float, times: ContactTimes
) -> list[Summary]:
    """Per virtual leg of two or more legs: the mean touchdown spread and the fraction of its
    steps whose members touched down within ``UNISON`` of each other (timed by ``times``: a
    spread of 10 ms cannot be judged on samples 5.2 ms apart)."""
    rows = []
    for u in units:
        if u.kind != "group" or len(u.contacts) < 2:
            continue
        spreads = touchdown_spreads(tr, u, t_from, t_to, times)
        rows.append(stat(f"touchdown_spread_{u.name}", f"touchdown spread, {u.name} (s)", spreads))
        within = [float(x <= UNISON + EPS_T) for x in spreads]
        rows.append(
            stat(
                f"unison_{u.name}",
                f"steps of {u.name} touching down within {UNISON * 1000:g} ms (-)",
                within,
            )
        )
    return rows
