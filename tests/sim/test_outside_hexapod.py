"""A hexapod written outside the team from the docs alone (tests/good/outside/tripod_hexapod.leg):
six legs whose two virtual legs are tripods of three feet, trotting with the shipped quadruped's
trot extended. It compiles, runs the same on both backends, keeps its trunk up at about its
commanded 1 m/s, and is measured on its tripods (``--group``, ``--table2``)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT
from runtime_helpers import assert_same, needs_c_compiler

from legdsl.cli import main
from legdsl.pipeline.measure import measure_run
from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions

LEG = ROOT / "tests" / "good" / "outside" / "tripod_hexapod.leg"
TRIPODS = ["a=fl,mr,rl", "b=fr,ml,rr"]

pytestmark = needs_c_compiler


@pytest.fixture(scope="module")
def generated(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """One generated tree for the module: the creature is compiled once."""
    return tmp_path_factory.mktemp("hexapod_generated")


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory: pytest.TempPathFactory, generated: Path) -> Path:
    """The tripod at 1 m/s for 3 s, in C, written as ``legdsl run`` writes it."""
    out = tmp_path_factory.mktemp("hexapod") / "run"
    argv = ["run", str(LEG), "--controller", "tripod", "--set", "speed=1m/s", "--time", "3",
            "--backend", "c", "--generated", str(generated), "--out", str(out)]  # fmt: skip
    assert main(argv) == 0
    return out


def test_the_hexapod_runs_the_same_on_both_backends_and_keeps_its_trunk_up(
    run_dir: Path, generated: Path
) -> None:
    sess = RunSession.from_file(LEG, generated=generated)
    opts = RunOptions(duration=2.5)
    python = sess.run("tripod", ["speed=1m/s"], options=opts, backend="python").result
    c = sess.run("tripod", ["speed=1m/s"], options=opts, backend="c").result
    assert python.status == "ok", python.message
    assert_same(python, c)
    tr = python.trajectory
    assert tr.root_pos[:, 2].min() > 0.38  # it stands with its trunk at 0.48 m
    assert np.abs(tr.root_rpy[:, :2]).max() < np.radians(20)
    x = tr.com[:, 0]
    half = len(x) // 2
    assert 0.6 < (x[-1] - x[half]) / (tr.t[-1] - tr.t[half]) < 1.2  # speeding up to 1 m/s
    assert tr.leg_length.shape[1] == 6
    for leg in range(6):  # every leg bears stances
        assert (tr.contact[:, leg] != 0).any()


def test_its_tripods_are_measured_as_virtual_legs(run_dir: Path) -> None:
    metrics, _ = measure_run(run_dir, 1.5, groups=TRIPODS, leg="a")
    rows = {s.key: s for s in metrics.summaries}
    assert metrics.reference == "a" and metrics.n_strides >= 1
    assert 0.7 < rows["running_speed"].value < 1.2
    assert {"touchdown_spread_a", "touchdown_spread_b"} <= set(rows)


def test_table2_with_pairs_by_hand_starts_strides_at_the_first_pair(run_dir: Path) -> None:
    """With --group the gait's pairs are the ones given: its strides started at the first
    leg's touchdowns (fl's, whose own short bounces count), not the first pair's."""
    metrics, _ = measure_run(run_dir, 1.5, groups=TRIPODS, table2="quadruped trot")
    assert metrics.reference == "a"


def test_table2_on_six_legs_says_to_give_the_pairs(
    run_dir: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["metrics", str(run_dir), "--table2", "quadruped trot"]) == 2
    err = capsys.readouterr().err
    assert "this creature has 6 legs" in err and "--group NAME=LEG,LEG" in err
    assert "Traceback" not in err


def test_table2_bound_says_to_name_the_pairs_front_and_rear(
    run_dir: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The bound's rows read groups named front and rear: others gave n/a rows without a word."""
    argv = ["metrics", str(run_dir), "--table2", "quadruped bound"]
    assert main([*argv, "--group", "a=fl,mr,rl", "--group", "b=fr,ml,rr"]) == 2
    err = capsys.readouterr().err
    assert "no --group is named front or rear" in err
    assert "--group front=LEG,LEG --group rear=LEG,LEG" in err
    assert main(argv) == 2  # six legs: found pairs none, and it says how to name them
    assert "--group front=LEG,LEG --group rear=LEG,LEG" in capsys.readouterr().err
    assert main([*argv, "--group", "front=fl,fr", "--group", "rear=rl,rr"]) == 0
