"""The footfall diagram of a leg whose foot body has two contacts (a toe, the leg's foot,
and a heel): the heel's touches get a row of their own beside the legs' (a heel strike
before the toe lands was not drawn at all); a contact that never touches gets none."""

from __future__ import annotations

import numpy as np

from legdsl.analysis.plot import footfall_bars
from legdsl.sim.trajectory import empty


def test_a_heel_beside_the_toe_gets_its_own_row() -> None:
    n = 101
    tr = empty(
        n, 3, 3, 3, 1, q_names=("x", "z", "pitch"), v_names=("x", "z", "pitch"),
        contact_names=("toe", "heel", "knee"), leg_names=("main",), leg_feet=(0,),
        total_mass=1.0,
    )  # fmt: skip
    tr.t[:] = np.linspace(0.0, 1.0, n)
    tr.contact[20:50, 1] = 1  # heel strike at 0.2 s
    tr.contact[30:60, 0] = 1  # the toe lands at 0.3 s
    rows = footfall_bars(tr)
    assert [name for name, _ in rows] == ["main", "heel"]
    assert rows[0][1] == [(0.3, 0.6)]
    assert rows[1][1] == [(0.2, 0.5)]


def test_a_leg_with_several_soles_gets_a_row_for_each_sole() -> None:
    """A flat foot whose leg stands on sole, heel and toe (``foot sole_l, heel_l, toe_l``):
    the leg's row is its stance as the metrics count it, from the heel strike to the toe's
    liftoff, and only the soles' own rows told the heel strike from the toe's landing (they
    had none, though docs/metrics.md promised the heel its row)."""
    n = 101
    tr = empty(
        n, 3, 3, 4, 1, q_names=("x", "z", "pitch"), v_names=("x", "z", "pitch"),
        contact_names=("toe_l", "heel_l", "sole_l", "tail"), leg_names=("left",),
        leg_feet=(2,), leg_soles=((2, 1, 0),), total_mass=1.0,
    )  # fmt: skip
    tr.t[:] = np.linspace(0.0, 1.0, n)
    tr.contact[20:50, 1] = 1  # heel strike at 0.2 s
    tr.contact[30:50, 2] = 1  # the sole flat at 0.3 s
    tr.contact[30:60, 0] = 1  # the toe leaves last, at 0.6 s
    rows = footfall_bars(tr)
    assert [name for name, _ in rows] == ["left", "sole_l", "heel_l", "toe_l"]
    assert dict(rows) == {
        "left": [(0.2, 0.6)],
        "sole_l": [(0.3, 0.5)],
        "heel_l": [(0.2, 0.5)],
        "toe_l": [(0.3, 0.6)],
    }
