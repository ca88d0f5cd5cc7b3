"""A drop reported from outside (tests/good/outside/blob.leg): a 1 kg body on a 0.1 kg leg,
dropped onto a stiff, damped ground with the hip held at 2 deg. At the default 0.4 ms step the
ground's tangent damper on the leg's tip (an effective mass of 4 g: the leg turns about its
centre of mass at the hip) feeds energy in: the total leaps from 25.8 J to 1153 J in one step,
the hip turns at 1500 rad/s between two checks of the divergence rule, and the run used to end
as an ordinary fall (exit 4). The energy check (``legdsl.sim.energy_check``) tells it as a
divergence, with the rise and the step the ground allows, on both backends alike; at 0.02 ms
the same drop lands without a rise (and, standing on one leg, tips over by itself at 1.126 s)."""

from __future__ import annotations

import itertools
import json
import math
import shlex
from pathlib import Path

import numpy as np
import pytest
from conftest import OUTSIDE, ROOT
from runtime_helpers import needs_c_compiler

from legdsl.cli import main
from legdsl.sim.energy_check import RISE, unexplained_rise
from legdsl.sim.trajectory import empty

LEG = OUTSIDE / "blob.leg"
REL = "tests/good/outside/blob.leg"
DROP = ["--time", "0.5", "--set", "hip_servo.setpoint=2deg"]
RISE_LINE = (
    "legdsl: the simulation diverged at t = 0.3208 s: the total energy rose from 25.75 J at "
    "t = 0.3204 s to 1153 J at t = 0.3208 s (one sample later) with only 0 J of actuator "
    "work between (not counting 42.5 J of springs and servos whose stiffness and rest never "
    "change: they only give back what they stored), and nothing else in a creature adds "
    "energy. Likely cause: the step 0.4 ms "
    "is too large for the contact stiffness: the ground's tangent spring on contact 'toe' "
    "(k = 1e+04 N/m, b = 100 N*s/m) acts on an effective mass of 0.00402 kg there, and "
    "explicit stability needs dt < 0.0803 ms; try a step of 0.02 ms (--dt, or dt in the "
    "simulation block). After it the run fell at t = 0.3300 s: the root tilted 66.2 deg from "
    "upright (limit 60 deg)"
)


@pytest.fixture(scope="module")
def gen(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """One generated tree for the module: the blob is compiled once."""
    return tmp_path_factory.mktemp("blob_generated")


def run(out: Path, gen: Path, backend: str, *more: str) -> int:
    return main(["run", str(LEG), *DROP, *more, "--backend", backend, "--generated", str(gen),
                 "--out", str(out)])  # fmt: skip


@needs_c_compiler
def test_the_drop_at_the_default_step_is_told_as_a_divergence_of_its_energy(
    tmp_path: Path, gen: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    said = {}
    for backend in ("python", "c"):
        assert run(tmp_path / backend, gen, backend, "--record-rate", "0") == 3
        out, err = capsys.readouterr()
        assert RISE_LINE in err.splitlines()
        status = next(row for row in out.splitlines() if row.strip().startswith("status"))
        assert status.split(None, 1)[1] == "diverged: " + RISE_LINE.removeprefix("legdsl: ")
        said[backend] = json.loads((tmp_path / backend / "run.json").read_text())
    info = said["python"]
    assert said["c"] == info
    assert (tmp_path / "c" / "trajectory.npz").read_bytes() == (
        tmp_path / "python" / "trajectory.npz"
    ).read_bytes()  # the run itself is as it was: its fall at 0.33 s, every sample
    assert info["status"] == "diverged" and info["message"] == RISE_LINE.removeprefix("legdsl: ")
    assert info["cause"].startswith("the total energy rose from 25.75 J at t = 0.3204 s")
    assert info["ended_at"] == 0.33 and info["steps"] == 825  # where the fall stopped it
    assert info["diverged_at"] == 0.3208  # where the rise ended


@needs_c_compiler
def test_a_sweeps_row_says_where_the_energy_rose(tmp_path: Path, gen: Path) -> None:
    """The row of a run told diverged by its energy gives the rise's end, as the message does
    (it gave the fall that stopped the run, 0.330 s; sampled at the default rate, the rise
    ends at 0.3224 s)."""
    import legdsl
    from legdsl.api.sweep import Job, _row

    assert run(tmp_path / "r", gen, "c") == 3
    job = Job(index=0, source=str(LEG), creature=None, controller="", values={}, units={},
              fixed=(), duration=0.5, start=0.0, generated=str(gen), keep=None)  # fmt: skip
    assert (
        _row(job, legdsl.open_run(tmp_path / "r", generated=gen))["outcome"]
        == "diverged at 0.322 s"
    )


@needs_c_compiler
def test_the_rise_is_seen_at_the_default_record_rate_too(
    tmp_path: Path, gen: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A sample every 13 steps misses the peak (1153 J): the one after it holds 126 J."""
    assert run(tmp_path / "r", gen, "c") == 3
    err = capsys.readouterr().err
    assert "the total energy rose from 10.78 J at t = 0.3172 s to 125.8 J at t = 0.3224 s" in err
    assert "try a step of 0.02 ms" in err


@needs_c_compiler
@pytest.mark.parametrize("backend", ["python", "c"])
def test_at_a_step_the_ground_allows_the_drop_ends_ok(
    tmp_path: Path, gen: Path, capsys: pytest.CaptureFixture[str], backend: str
) -> None:
    assert run(tmp_path / "r", gen, backend, "--dt", "0.02ms") == 0
    out, err = capsys.readouterr()
    assert "energy rose" not in out + err and "diverged" not in out + err
    info = json.loads((tmp_path / "r" / "run.json").read_text())
    assert info["status"] == "ok" and "cause" not in info


def _doc_example() -> tuple[list[str], str]:
    """docs/runtime.md's example of an energy rise: its command (after '$ ') and the message
    under it, its lines joined."""
    lines = (ROOT / "docs" / "runtime.md").read_text(encoding="utf-8").splitlines()
    (k,) = [k for k, line in enumerate(lines) if line.strip().startswith(f"$ legdsl run {REL}")]
    said = itertools.takewhile(str.strip, lines[k + 1 :])
    return shlex.split(lines[k].strip().removeprefix("$ ")), " ".join(s.strip() for s in said)


@needs_c_compiler
def test_the_docs_example_is_what_its_command_prints(
    tmp_path: Path, gen: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """It quoted a run recorded at every step as the plain command's (which tells the rise
    between two samples 13 steps apart: other figures)."""
    command, said = _doc_example()
    assert command[:3] == ["legdsl", "run", REL]
    argv = [*command[1:2], str(LEG), *command[3:], "--generated", str(gen), "--out", str(tmp_path)]
    assert main(argv) == 3
    assert said.startswith("legdsl: the simulation diverged") and said == RISE_LINE
    assert said in capsys.readouterr().err.splitlines()


@needs_c_compiler
def test_at_the_advised_step_the_blob_lands_and_later_tips_over_by_itself(
    tmp_path: Path, gen: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """docs/runtime.md: at --dt 0.02ms (the message's advice) nothing diverges; --time 1 ends
    ok, and at the default --time 5 the blob, standing on one leg, falls at 1.126 s, the same
    at half the step: its own fall, not the step's."""
    drop = ["run", str(LEG), "--set", "hip_servo.setpoint=2deg", "--generated", str(gen)]
    assert main([*drop, "--dt", "0.02ms", "--time", "1", "--out", str(tmp_path / "1s")]) == 0
    for dt in ("0.02ms", "0.01ms"):
        assert main([*drop, "--dt", dt, "--out", str(tmp_path / dt)]) == 4
        info = json.loads((tmp_path / dt / "run.json").read_text())
        assert info["status"] == "fell" and round(info["ended_at"], 3) == 1.126, info["message"]
    assert "diverged" not in capsys.readouterr().err


@needs_c_compiler
def test_a_divergence_found_while_running_names_the_grounds_step(
    tmp_path: Path, gen: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """At 0.1 ms the hip passes 1000 rad/s at a check: the likely cause gives the step the
    ground allows on the leg's tip (it compared the stiffness alone with the leg's whole mass,
    which allowed 3 ms, and said nothing of it)."""
    assert run(tmp_path / "r", gen, "c", "--dt", "0.1ms") == 3
    err = capsys.readouterr().err
    assert "a velocity reached 2.09e+03 rad/s (hip; the limit is 1e+03 rad/s)" in err
    assert "the step 0.1 ms is too large for the contact stiffness" in err
    assert "effective mass of 0.00399 kg there" in err and "try a step of 0.02 ms" in err
    # Its ordinary landing, 38 weights on the light tip at a step too large for the ground, is
    # no foot "far under the surface" (that came first, before the right cause).
    assert "touched down" not in err


@needs_c_compiler
def test_a_batchs_copy_that_ran_to_its_end_is_told_as_its_single_run(gen: Path) -> None:
    """A copy C ran to its end is taken as ok without its result: one whose energy rose is
    looked at, and told as the single run tells it."""
    import legdsl

    blob = legdsl.load(LEG, generated=gen)
    hip = {"hip_servo.setpoint": ([2.0, 0.0], "deg")}
    copies = blob.run_copies(2, None, vary=hip, time=0.4, dt=0.0004, fall_tilt=math.pi)
    single = blob.run(set={"hip_servo.setpoint": "2 deg"}, time=0.4, fall_tilt=math.pi)
    assert copies.status.tolist() == ["diverged", "ok"] and single.status == "diverged"
    assert copies[0].info["message"] == single.info["message"]
    assert "After it the run ran on to its end at t = 0.4000 s" in single.info["message"]


def _recording(kinetic: list[float], elastic: list[float], work: list[float]):
    n = len(kinetic)
    traj = empty(n, 1, 1, 0, 0, 1, total_mass=1.0, gravity=9.81)
    traj.t[:] = np.arange(n) * 0.005
    traj.com[:, 2] = 1.0  # a floor of 0.1 * 9.81 J
    traj.potential[:] = 5.0
    traj.kinetic[:], traj.elastic[:] = kinetic, elastic
    traj.work_positive[:, 0], traj.work_negative[:, 0] = work, 0.0
    return traj


def test_only_a_rise_without_a_source_is_told() -> None:
    """Energy a controller stores in a spring (a setpoint moved: no work) and energy the
    actuators' work gives are the creature's own; a leap past both is not."""
    calm = [1.0, 1.0, 1.0, 1.0, 1.0]
    assert unexplained_rise(_recording(calm, [0.0] * 5, [0.0] * 5)) is None
    # a servo's setpoint moved at the third sample: it stores 30 J, then gives them back as
    # work (its force along its coordinate's motion)
    stored, released = [0.0, 0.0, 30.0, 20.0, 10.0], [0.0, 0.0, 0.0, 10.0, 20.0]
    assert unexplained_rise(_recording([1.0, 1.0, 1.0, 11.0, 21.0], stored, released)) is None
    worked = [1.0, 1.0, 31.0, 31.0, 31.0]
    assert unexplained_rise(_recording(worked, [0.0] * 5, [0.0, 0.0, 30.0, 30.0, 30.0])) is None
    rise = unexplained_rise(_recording(worked, [0.0] * 5, [0.0, 0.0, 1.0, 1.0, 1.0]))
    assert rise is not None and (rise.start, rise.end) == (1, 2) and rise.ratio > RISE
    assert rise.said().startswith("the total energy rose from 6 J at t = 0.0050 s to 36 J at")
