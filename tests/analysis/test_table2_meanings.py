"""Rows compared with the paper's Table 2 measure what the paper's rows mean, whatever
virtual legs a display option asks for: the leg's shortening in support (not max - min, which
counted the thrust's lengthening), the elastic energy taken up from the landing (not the
thrust stroke's work), a phase of the bound's stride counted 0 in a stride without it, and
the biped's stride a single step as the paper's."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from legdsl.analysis.metrics import compute_metrics
from legdsl.analysis.table2 import MEASURE, TABLE2, compare_table, step_legs, virtual_legs
from legdsl.check.source import check_model
from legdsl.cli import main
from legdsl.sim.trajectory import Trajectory, empty

ROOT = Path(__file__).resolve().parents[2]
DT = 0.001
M, G = 20.0, 9.81


def _run(legs: tuple[str, ...], n: int) -> Trajectory:
    names = ("x", "z", "pitch")
    tr = empty(
        n, 3, 3, len(legs), len(legs), q_names=names, v_names=names,
        contact_names=tuple(f"toe_{s}" for s in legs), leg_names=legs,
        leg_feet=tuple(range(len(legs))), total_mass=M, gravity=G, planar=True,
    )  # fmt: skip
    tr.t[:] = np.arange(n) * DT
    tr.com[:, 0] = 2.0 * tr.t
    tr.com[:, 2] = 0.7
    tr.com_vel[:, 0] = 2.0
    return tr


def _stance(n: int, period: int, start: int, length: int) -> tuple[np.ndarray, np.ndarray]:
    """Where a foot is down (every ``period`` samples from ``start``, for ``length``) and a
    bump rising from 0 to 1 at mid-stance and back to 0 at liftoff."""
    tau = (np.arange(n) - start) % period
    on = tau < length
    return on, np.where(on, np.sin(np.pi * tau / length), 0.0)


def _trot(n: int = 3001) -> Trajectory:
    """Diagonal pairs fl+rr and fr+rl landing in turn, 300 samples apart; each leg shortens
    and stores PEAK in its spring, then its controller lengthens the spring's rest at the
    bottom (THRUST): 4 x PEAK more until liftoff. The body falls DROP in each step."""
    tr = _run(("fl", "fr", "rl", "rr"), n)
    z = np.full(n, 0.7)
    for leg, start in (("fl", 0), ("rr", 2), ("fr", 300), ("rl", 303)):
        c = tr.leg_names.index(leg)
        on, bump = _stance(n, 600, start + 150, 120)
        rising = on & (((np.arange(n) - start - 150) % 600) < 60)
        tr.contact[:, c] = on
        tr.leg_length[:, c] = 0.8 - 0.04 * bump
        tr.leg_spring_energy[:, c] = np.where(rising, PEAK * bump, 5 * PEAK * bump)
        if leg in ("fl", "fr"):
            z -= DROP * bump
    tr.com[:, 2] = z
    return tr


PEAK, DROP = 3.0, 0.05


def test_the_energy_recirculated_is_the_same_with_or_without_the_pairs() -> None:
    """The trot's fraction read 0.837 alone and 1.673 with --table2 'quadruped trot' (its
    pairs' springs added), and its stored energy was the thrust stroke's."""
    tr = _trot()
    alone = compute_metrics(tr)
    pairs = compute_metrics(tr, groups={"fl+rr": ["fl", "rr"], "fr+rl": ["fr", "rl"]})
    for key in ("stored_energy", "energy_taken_up", "energy_recirculated"):
        assert alone.value(key) == pytest.approx(pairs.value(key)), key
    # four legs store PEAK each (read a sample before the bottom) in a stride of two steps
    assert alone.value("stored_energy") == pytest.approx(4 * PEAK, rel=1e-3)
    assert alone.value("energy_taken_up") == pytest.approx(2 * M * G * DROP, rel=1e-3)
    fraction = 4 * PEAK / (2 * M * G * DROP)
    assert alone.value("energy_recirculated") == pytest.approx(fraction, rel=1e-3)
    assert alone.value("energy_recirculated") < 1


def test_the_change_of_leg_length_is_the_shortening() -> None:
    """A leg that shortens 3 cm and leaves the ground 5 cm longer than it landed (the trot's
    thrust) changed by 3 cm in support, not by max - min's 8 cm."""
    n = 2001
    tr = _run(("main",), n)
    on, bump = _stance(n, 400, 100, 150)
    tau = (np.arange(n) - 100) % 400
    tr.contact[:, 0] = on
    tr.leg_length[:, 0] = 0.8 - 0.03 * bump + np.where(on & (tau > 75), 0.08 * (tau - 75) / 75, 0)
    m = compute_metrics(tr)
    assert m.value("leg_length_change") == pytest.approx(0.03, abs=1e-9)
    assert [s.leg_length_change for s in m.stances] == [pytest.approx(0.03, abs=1e-9)] * len(
        m.stances
    )


def _bound(n: int = 8001) -> Trajectory:
    """A bound of two kinds of stride, 400 samples each: front [0, 100), gathered flight,
    rear [300, 380), an extended flight of 20 ms; then front [400, 500), gathered flight, rear
    [700, 820), down still when the front lands at 800: no extended flight."""
    tr = _run(("f", "r"), n)
    tau = (np.arange(n) + 150) % 800
    tr.contact[:, 0] = (tau < 100) | ((tau >= 400) & (tau < 500))
    tr.contact[:, 1] = ((tau >= 300) & (tau < 380)) | (tau >= 700) | (tau < 20)
    return tr


def test_a_stride_without_an_extended_flight_counts_zero() -> None:
    """The bound's extended flight read 0.027 s over the 20 of 38 strides that had one; a
    phase of the stride, it is 0.015 s a stride."""
    m = compute_metrics(_bound(), groups={"front": ["f"], "rear": ["r"]}, leg="front")
    assert m.value("flight_duration_before_front") == pytest.approx(0.020, abs=1e-9)
    per_stride = m.summary("flight_time_before_front")
    assert per_stride.n == m.n_strides >= 18
    assert per_stride.value == pytest.approx(0.010, abs=0.020 / m.n_strides)
    assert m.value("flight_time_before_rear") == pytest.approx(0.200, abs=1e-9)
    rows = TABLE2["quadruped bound"]
    text = compare_table(m, rows, measured_as=MEASURE["quadruped bound"])
    label = "extended flight phase duration (s)"
    extended = next(x for x in text.splitlines() if x.startswith(label))
    assert float(extended[len(label) :].split()[0]) == pytest.approx(per_stride.value, rel=0.01)


def test_the_biped_run_is_measured_a_step_a_stride() -> None:
    """--table2 'biped run' set this tool's two-step stride beside the paper's single step."""
    groups, first = virtual_legs("biped run", check_model(ROOT / "creatures" / "biped.leg"))
    assert groups == {"either": ["left", "right"]} and first == "either"
    assert step_legs("biped run", ["main"]) == ({}, None)  # a hopper's stride is a step


def test_cli_biped_run_strides_are_steps(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    n = 4001
    tr = _run(("left", "right"), n)
    tr.contact[:, 0] = _stance(n, 400, 50, 120)[0]
    tr.contact[:, 1] = _stance(n, 400, 250, 120)[0]
    tr.save(tmp_path)
    # the legs are the trajectory's: the run's .leg file is not needed
    (tmp_path / "run.json").write_text(json.dumps({"source": "gone.leg", "creature": "biped"}))
    assert main(["metrics", str(tmp_path), "--table2", "biped run"]) == 0
    out = capsys.readouterr().out
    assert "reference: either" in out
    beside = out[out.index("beside Table 2 of the paper, biped run:") :].splitlines()
    duration = next(x for x in beside if x.startswith("stride duration (s)"))
    assert duration.split()[3] == "0.200"  # a step: 200 samples, not the two-step 0.400
