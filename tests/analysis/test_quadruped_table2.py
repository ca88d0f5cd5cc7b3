"""Table 2's quadruped rows (trot and bound) on synthetic contact events whose answers are
known, with the pairs of legs found from the creature's hips, never from their names."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from legdsl.analysis.metrics import compute_metrics
from legdsl.analysis.pairs import hip_positions, pair_groups, touchdown_spreads
from legdsl.analysis.results import MetricsError
from legdsl.analysis.strides import stance_units
from legdsl.analysis.table2 import MEASURE, TABLE2, virtual_legs
from legdsl.check.source import check_model
from legdsl.cli import main
from legdsl.sim.trajectory import Trajectory, empty

ROOT = Path(__file__).resolve().parents[2]
QUADRUPED = ROOT / "creatures" / "quadruped.leg"
DT = 0.001
LEGS = ("fl", "fr", "rl", "rr")


def _pattern(n: int, period: int, shift: int, span: tuple[int, int]) -> np.ndarray:
    phase = (np.arange(n) + shift) % period
    return ((phase >= span[0]) & (phase < span[1])).astype(np.int8)


def quadruped_run(spans: dict[str, tuple[int, int]], period: int, n: int = 3001) -> Trajectory:
    """Four legs named as in creatures/quadruped.leg, each foot down over its span of every
    ``period`` samples; running at 2.5 m/s (command 2.8), pitching 20 deg peak to peak once a
    stride, each leg 3 cm shorter at mid-stance."""
    names = ("x", "z", "pitch")
    tr = empty(
        n, 3, 3, 4, 4, q_names=names, v_names=names, contact_names=tuple(f"toe_{s}" for s in LEGS),
        leg_names=LEGS, leg_feet=(0, 1, 2, 3), total_mass=20.0, gravity=9.81, planar=False,
    )  # fmt: skip
    tr.t[:] = np.arange(n) * DT
    for c, leg in enumerate(LEGS):
        tr.contact[:, c] = _pattern(n, period, 200, spans[leg])
        a, b = spans[leg]
        tau = (np.arange(n) + 200 - a) % period
        tr.leg_length[:, c] = 0.8 - 0.03 * np.where(tau < b - a, np.sin(np.pi * tau / (b - a)), 0)
    tr.com[:, 0] = 2.5 * tr.t
    tr.com[:, 2] = 0.7
    tr.com_vel[:, 0] = 2.5
    tr.root_rpy[:, 1] = np.radians(10.0) * np.sin(2 * np.pi * (np.arange(n) + 200) / period)
    tr.speed_command[:] = 2.8
    return tr


# The bound: front legs [0, 100) and [2, 102) -> front stance 102 ms; gathered flight 220 ms;
# rear legs [322, 402) and [324, 404) -> rear stance 82 ms; extended flight 30 ms.
BOUND = {"fl": (0, 100), "fr": (2, 102), "rl": (322, 402), "rr": (324, 404)}
# The trot: fl and rr [0, 120) and [4, 124); fr and rl [270, 390) and [285, 405) (15 ms apart).
TROT = {"fl": (0, 120), "rr": (4, 124), "fr": (270, 390), "rl": (285, 405)}


def test_pairs_come_from_the_hips_of_the_shipped_quadruped() -> None:
    positions = hip_positions(check_model(QUADRUPED))
    assert positions["fl"] == pytest.approx((0.39, 0.12))
    assert positions["rr"] == pytest.approx((-0.39, -0.12))  # mirrored
    assert pair_groups(positions, "front/rear") == {"front": ["fl", "fr"], "rear": ["rl", "rr"]}
    assert pair_groups(positions, "diagonal") == {"fl+rr": ["fl", "rr"], "fr+rl": ["fr", "rl"]}
    assert pair_groups(positions, "lateral") == {"left": ["fl", "rl"], "right": ["fr", "rr"]}


def test_pairs_of_any_quadruped_whatever_its_legs_are_called() -> None:
    # legs named in no particular order, a long trunk set off-centre, front legs wider
    positions = {"a": (-1.1, -0.2), "b": (0.6, 0.3), "c": (-1.1, 0.2), "d": (0.6, -0.3)}
    assert pair_groups(positions, "front/rear") == {"front": ["b", "d"], "rear": ["a", "c"]}
    assert pair_groups(positions, "diagonal") == {"b+a": ["b", "a"], "d+c": ["d", "c"]}


@pytest.mark.parametrize(
    ("positions", "message"),
    [
        ({"l": (0.0, 0.1), "r": (0.0, -0.1)}, "this creature has 2 legs"),
        ({"a": (1, 1), "b": (1, -1), "c": (1, 0.5), "d": (-1, -1)}, "two hips ahead"),
    ],
)
def test_pairs_need_a_quadruped(positions: dict, message: str) -> None:
    with pytest.raises(MetricsError, match=message):
        pair_groups(positions, "front/rear")


def test_a_planar_quadruped_has_front_and_rear_pairs_only() -> None:
    """Its hips have no left and right (all at y = 0): the bound's front/rear pairs were
    refused for want of them; the pace's and the trot's need them, and say how to name the
    pairs by hand."""
    planar = {"fl": (0.39, 0.0), "fr": (0.39, 0.0), "rl": (-0.39, 0.0), "rr": (-0.39, 0.0)}
    assert pair_groups(planar, "front/rear") == {"front": ["fl", "fr"], "rear": ["rl", "rr"]}
    for pairing in ("lateral", "diagonal"):
        with pytest.raises(MetricsError, match="left.*right.*--group NAME=LEG,LEG"):
            pair_groups(planar, pairing)


def _rows(tr: Trajectory, gait: str) -> dict[str, float]:
    groups, reference = virtual_legs(gait, check_model(QUADRUPED))
    m = compute_metrics(tr, groups=groups, leg=reference)
    by_key = {s.key: s.value for s in m.summaries} | {s.label: s.value for s in m.summaries}
    alias = MEASURE[gait]
    return {label: by_key.get(alias.get(label, label), math.nan) for label in TABLE2[gait]}


def test_bound_rows_of_table_2() -> None:
    rows = _rows(quadruped_run(BOUND, 434), "quadruped bound")
    assert set(rows) == set(TABLE2["quadruped bound"])  # every row of the paper
    expected = {
        "pitch magnitude (deg)": 20.0,
        "stride length (m)": 2.5 * 0.434,
        "stride duration (s)": 0.434,
        "gathered flight phase duration (s)": 0.220,
        "extended flight phase duration (s)": 0.030,
        "stance duration, front legs (s)": 0.102,
        "stance duration, rear legs (s)": 0.082,
        "change of leg length during support (m)": 0.03,
        "running speed (m/s)": 2.5,
        "error in running speed (m/s)": -0.3,
    }
    assert rows == pytest.approx(expected, abs=2e-3)


def test_trot_rows_of_table_2_and_the_pairs_in_unison() -> None:
    tr = quadruped_run(TROT, 540)
    rows = _rows(tr, "quadruped trot")
    expected = {
        "pitch magnitude (deg)": 20.0,
        "stride length (m)": 2.5 * 0.540,
        "stride duration (s)": 0.540,
        "flight duration (s)": (0.540 - 0.124 - 0.135) / 2,  # 146 and 135 ms
        "stance duration (s)": 0.120,
        "change of leg length during support (m)": 0.03,
        "desired running speed (m/s)": 2.8,
        "error in running speed (m/s)": -0.3,
    }
    assert rows == pytest.approx(expected, abs=2e-3)
    groups, _ = virtual_legs("quadruped trot", check_model(QUADRUPED))
    m = compute_metrics(tr, groups=groups)
    assert m.value("touchdown_spread_fl+rr") == pytest.approx(0.004, abs=1e-9)
    assert m.value("unison_fl+rr") == 1.0  # 4 ms apart: in unison
    assert m.value("touchdown_spread_fr+rl") == pytest.approx(0.015, abs=1e-9)
    assert m.value("unison_fr+rl") == 0.0  # 15 ms apart: not


def test_a_member_that_stays_up_is_left_out_of_the_spread() -> None:
    tr = quadruped_run(TROT, 540)
    tr.contact[:, 3] = 0  # rr never lands: the fl+rr stances have one member
    units = stance_units(tr, {"fl+rr": ["fl", "rr"]})
    assert touchdown_spreads(tr, units[-1], 0.0, 3.0) == []


def _save_run(tr: Trajectory, out: Path) -> None:
    tr.save(out)
    info = {"source": str(QUADRUPED), "creature": "quadruped", "status": "ok", "events": []}
    (out / "run.json").write_text(json.dumps(info))


@pytest.mark.parametrize(("gait", "spans", "period"), [("bound", BOUND, 434), ("trot", TROT, 540)])
def test_cli_prints_every_row_of_table_2_beside_the_run(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], gait: str, spans: dict, period: int
) -> None:
    _save_run(quadruped_run(spans, period), tmp_path)
    assert main(["metrics", str(tmp_path), "--table2", f"quadruped {gait}"]) == 0
    out = capsys.readouterr().out
    beside = out[out.index(f"beside Table 2 of the paper, quadruped {gait}:") :].splitlines()
    for label, (robot, paper) in TABLE2[f"quadruped {gait}"].items():
        line = next(x for x in beside if x.startswith(label))
        assert "n/a" not in line, line
        assert line.split()[-2:] == [f"{robot:g}", f"{paper:g}"]
    if gait == "bound":
        gathered = next(x for x in beside if x.startswith("gathered flight phase"))
        assert "0.220" in gathered
        assert "stride duration (s)" in out and "reference: front" in out.replace("  ", " ")


def test_cli_pairs_of_a_run_without_its_leg_file_is_a_user_error(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    tr = quadruped_run(BOUND, 434)
    tr.save(tmp_path)
    (tmp_path / "run.json").write_text(json.dumps({"source": "gone.leg", "creature": "q"}))
    assert main(["metrics", str(tmp_path), "--table2", "quadruped bound"]) == 2
    assert "--group NAME=LEG,LEG" in capsys.readouterr().err
    # given by hand, the pairs need no .leg file
    groups = ["--group", "front=fl,fr", "--group", "rear=rl,rr", "--leg", "front"]
    assert main(["metrics", str(tmp_path), "--table2", "quadruped bound", *groups]) == 0
