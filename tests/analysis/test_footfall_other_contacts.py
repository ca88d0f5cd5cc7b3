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
