"""A leg with several soles (``foot toe, heel``) in a recorded run: its stance in the metrics
and its footfall row last while any sole touches (heel strike to toe-off), the flight ended
by the heel is named by the leg, and the soles survive a save and load; a run directory
written before legs had several soles (only ``leg_feet``) still reads, each leg on its foot."""

from __future__ import annotations

import json
import zipfile
from pathlib import Path

import numpy as np

from legdsl.analysis.metrics import compute_metrics
from legdsl.analysis.plot import footfall_bars, stance_phases
from legdsl.sim.trajectory import Trajectory, empty


def _r(pairs: list[tuple[float, float]]) -> list[tuple[float, float]]:
    return [(round(a, 9), round(b, 9)) for a, b in pairs]


def _heel_first(soles: tuple[tuple[int, ...], ...]) -> Trajectory:
    n = 201
    tr = empty(
        n, 3, 3, 3, 1, q_names=("x", "z", "pitch"), v_names=("x", "z", "pitch"),
        contact_names=("toe", "heel", "knee"), leg_names=("main",), leg_feet=(0,),
        leg_soles=soles, total_mass=1.0,
    )  # fmt: skip
    tr.t[:] = np.linspace(0.0, 2.0, n)
    for start in (20, 80, 140):  # heel strike, the toe 10 samples later; the heel leaves first
        tr.contact[start : start + 20, 1] = 1
        tr.contact[start + 10 : start + 40, 0] = 1
    return tr


def test_the_stance_runs_from_heel_strike_to_toe_off() -> None:
    tr = _heel_first(((0, 1),))
    m = compute_metrics(tr)
    stances = _r([(s.t_touchdown, s.t_liftoff) for s in m.stances if s.unit == "main"])
    assert stances == [(0.2, 0.6), (0.8, 1.2), (1.4, 1.8)]
    assert {f.before for f in m.flights} == {"main"}
    rows = footfall_bars(tr)
    # the leg's row is its stance; its soles' rows tell the heel strike from the toe's landing
    assert [name for name, _ in rows] == ["main", "toe", "heel"]
    assert _r(rows[0][1]) == [(0.2, 0.6), (0.8, 1.2), (1.4, 1.8)]
    assert _r(rows[1][1])[0] == (0.3, 0.6) and _r(rows[2][1])[0] == (0.2, 0.4)
    assert _r(stance_phases(tr, 0))[0] == (0.2, 0.6)


def test_a_leg_on_its_foot_alone_is_as_before() -> None:
    tr = _heel_first(())
    m = compute_metrics(tr)
    stances = _r([(s.t_touchdown, s.t_liftoff) for s in m.stances if s.unit == "main"])
    assert stances == [(0.3, 0.6), (0.9, 1.2), (1.5, 1.8)]
    assert {f.before for f in m.flights} == {"heel"}
    assert [name for name, _ in footfall_bars(tr)] == ["main", "heel"]


def test_the_soles_are_saved_and_an_old_run_still_reads(tmp_path: Path) -> None:
    tr = _heel_first(((0, 1),))
    tr.save(tmp_path / "new")
    assert Trajectory.load(tmp_path / "new").leg_soles == ((0, 1),)
    one = _heel_first(())
    one.save(tmp_path / "old")
    with zipfile.ZipFile(tmp_path / "old" / "trajectory.npz") as z:  # as written before soles
        meta = json.loads(np.load(z.open("meta.npy")).tobytes())
    assert "leg_soles" not in meta and meta["leg_feet"] == [0]
    old = Trajectory.load(tmp_path / "old")
    assert old.leg_soles == () and old.soles_of(0) == (0,)
    assert _r(footfall_bars(old)[0][1]) == [(0.3, 0.6), (0.9, 1.2), (1.5, 1.8)]


def test_the_keyframe_note_reads_a_leg_s_stance_from_heel_strike_to_toe_off() -> None:
    """The exports' note on keyframes per stance took the foot contact's (the toe's) stance."""
    from legdsl.export.stances import typical_stance

    model = type("M", (), {"contacts": ()})()  # the trajectory names the legs and soles
    both = typical_stance(model, _heel_first(((0, 1),)))  # type: ignore[arg-type]
    toe = typical_stance(model, _heel_first(((0,),)))  # type: ignore[arg-type]
    assert both is not None and both[0] == "leg main" and abs(both[1] - 0.4) < 1e-9
    assert toe is not None and toe[0] == "leg main" and abs(toe[1] - 0.3) < 1e-9
