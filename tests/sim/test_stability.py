"""Actuators too stiff for the step: the bounds of ``legdsl.sim.stability`` against the
integrators themselves, and the run refused before it starts."""

from __future__ import annotations

import dataclasses
import math
import random
from pathlib import Path

import pytest

from legdsl.check.source import check_model
from legdsl.cli import main
from legdsl.sim.actuators import ActuatorState
from legdsl.sim.stability import ground_too_stiff, inverse_inertia_diagonal, too_stiff

ROOT = Path(__file__).resolve().parents[2]


def _spring(k: float, b: float, limit: float | None = None) -> ActuatorState:
    return ActuatorState("s", "spring", 0, 0, k, b, 0.0, 0.0, limit)


def _grows(k: float, b: float, m: float, h: float, integrator: str) -> bool:
    """Whether x'' = -(k x + b x') / m, stepped as the runtime steps it, blows up."""
    x, v = 1.0, 0.0

    def acc(x: float, v: float) -> float:
        return -(k * x + b * v) / m

    for _ in range(4000):
        if integrator == "euler":  # semi-implicit: the velocity first, the position with it
            v += h * acc(x, v)
            x += h * v
        else:
            k1x, k1v = v, acc(x, v)
            k2x, k2v = v + h / 2 * k1v, acc(x + h / 2 * k1x, v + h / 2 * k1v)
            k3x, k3v = v + h / 2 * k2v, acc(x + h / 2 * k2x, v + h / 2 * k2v)
            k4x, k4v = v + h * k3v, acc(x + h * k3x, v + h * k3v)
            x += h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x)
            v += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v)
        if abs(x) > 1e6 or abs(v) > 1e9:
            return True
    return False


@pytest.mark.parametrize("integrator", ["euler", "rk4"])
def test_the_bound_is_where_the_integrator_turns_unstable(integrator: str) -> None:
    """On either side of each bound (5% off it), the prediction is what stepping does."""
    rng = random.Random(4)
    h, m = 4e-4, 0.3
    for _ in range(40):
        k = 10 ** rng.uniform(5, 7.5)
        b = 10 ** rng.uniform(0, 3.5)
        for factor in (0.95, 1.05):
            # scale the step to 5% inside or outside the bound found for this k and b
            found = too_stiff([_spring(k, b)], [1 / m], h, integrator, set())
            edge = found[0].dt_limit if found else _largest_step(k, b, m, integrator)
            step = factor * edge
            flagged = bool(too_stiff([_spring(k, b)], [1 / m], step, integrator, set()))
            if integrator == "rk4" and b / m * step > 0.3 and k / m * step**2 > 0.3:
                continue  # RK4's region is not a box: only its two axes are claimed
            assert flagged == _grows(k, b, m, step, integrator), (k, b, step, flagged)


def _largest_step(k: float, b: float, m: float, integrator: str) -> float:
    """The step where the bound of ``too_stiff`` lies, by bisection on its own verdict."""
    lo, hi = 1e-9, 1.0
    for _ in range(200):
        mid = math.sqrt(lo * hi)
        if too_stiff([_spring(k, b)], [1 / m], mid, integrator, set()):
            hi = mid
        else:
            lo = mid
    return hi


def test_saturating_and_controlled_actuators_are_not_checked() -> None:
    assert too_stiff([_spring(1e12, 0.0)], [1.0], 4e-4, "euler", set())
    assert not too_stiff([_spring(1e12, 0.0, limit=100.0)], [1.0], 4e-4, "euler", set())
    assert not too_stiff([_spring(1e12, 0.0)], [1.0], 4e-4, "euler", {("s", "k")})
    # too damped, its stiffness fine: the damping is named
    (found,) = too_stiff([_spring(10.0, 1e5)], [1.0], 4e-4, "euler", set())
    assert (found.setting, found.limit) == ("b", pytest.approx(2 / 4e-4))


def test_inverse_inertia_is_the_diagonal_of_the_inverse() -> None:
    assert inverse_inertia_diagonal([[2.0, 1.0], [1.0, 2.0]]) == pytest.approx([2 / 3, 2 / 3])
    assert inverse_inertia_diagonal([[1.0, 1.0], [1.0, 1.0]]) == [0.0, 0.0]


def test_a_run_too_stiff_for_its_step_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], generated: Path, creatures_dir: Path
) -> None:
    out = tmp_path / "run"
    argv = ["run", str(creatures_dir / "hopper.leg"), "--controller", "hop", "--time", "1s",
            "--set", "leg_spring.k=1e9N/m", "--out", str(out), "--generated", str(generated)]  # fmt: skip
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "actuator 'leg_spring' is too stiff for the integration step" in err
    assert (
        "use k below 7.27e+06 N/m, or a step below 0.0341 ms (--dt, or dt in the simulation block)"
        in err
    )
    assert not out.exists()


@pytest.mark.parametrize("k", ["1e100N/m", "1e308N/m"])
def test_a_stiffness_no_step_can_hold_is_told_to_be_lowered(
    k: str, tmp_path: Path, capsys: pytest.CaptureFixture[str], generated: Path, creatures_dir: Path
) -> None:
    """k = 1e100 N/m was advised 'a step below 1.08e-47 ms', which legdsl refuses to count, and
    1e308 N/m 'a step below nan ms': no step is advised where none from 1 ns up would do."""
    argv = ["run", str(creatures_dir / "hopper.leg"), "--controller", "hop", "--time", "1s",
            "--set", f"leg_spring.k={k}", "--out", str(tmp_path / "run"),
            "--generated", str(generated)]  # fmt: skip
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert (
        "use k below 7.27e+06 N/m, or a 'max' for it in the .leg file (--set cannot give one)"
        in err
    )
    assert "step below" not in err and "nan" not in err


def test_a_ground_no_step_can_hold_is_told_to_be_lowered() -> None:
    """The ground's advice had the same flaw: 'try a step of 1e-47 ms'."""
    model = check_model(ROOT / "creatures" / "hopper.leg")
    assert model.ground is not None
    normal = dataclasses.replace(model.ground.normal, k=1e100)  # a file's 'k = 1e100 N/m'
    model = dataclasses.replace(model, ground=dataclasses.replace(model.ground, normal=normal))
    said = ground_too_stiff(model, 4e-4, "semi_implicit_euler")
    assert said is not None and "try a step" not in said
    assert said.endswith("no step legdsl takes is that small: lower the ground's k and b")


def test_a_saturating_actuator_past_the_bound_is_a_warning(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], generated: Path, creatures_dir: Path
) -> None:
    out = tmp_path / "run"
    argv = ["run", str(creatures_dir / "hopper.leg"), "--time", "0.1s", "--set",
            "hip_servo.kp=1e9N*m/rad", "--out", str(out), "--generated", str(generated)]  # fmt: skip
    assert main(argv) == 0
    err = capsys.readouterr().err
    assert "warning: actuator 'hip_servo' is too stiff for the integration step" in err
    assert "only its 'max' holds it: it will chatter between -max and max every step" in err
    argv = ["run", str(creatures_dir / "hopper.leg"), "--time", "0.1s", "--out", str(out),
            "--generated", str(generated)]  # fmt: skip
    assert main(argv) == 0
    assert "warning" not in capsys.readouterr().err


def test_a_stiffness_written_in_the_file_is_refused_at_its_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], generated: Path, creatures_dir: Path
) -> None:
    leg = tmp_path / "hopper.leg"
    text = (creatures_dir / "hopper.leg").read_text()
    leg.write_text(text.replace("spring(k = 3000 N/m", "spring(k = 1e9 N/m", 1))
    line = next(i for i, row in enumerate(leg.read_text().split("\n"), 1) if "k = 1e9 N/m" in row)
    argv = ["run", str(leg), "--controller", "hop", "--time", "1s", "--out", str(tmp_path / "r"),
            "--generated", str(generated)]  # fmt: skip
    assert main(argv) == 2
    err = capsys.readouterr().err.splitlines()
    head = next(i for i, row in enumerate(err) if "is too stiff" in row)
    assert err[head].startswith(f"{leg}:{line}:3: error: actuator 'leg_spring' is too stiff")
    assert "k = 1e9 N/m" in err[head + 1] and err[head + 2].strip().startswith("^")


def test_a_divergence_at_a_singular_mass_matrix_is_told_so() -> None:
    """A joint at a singular configuration (gimbal lock) makes the mass matrix singular: the
    likely cause says so, instead of suggesting a smaller step."""
    from conftest import shipped_model

    from legdsl.sim.stability import likely_cause

    model = shipped_model("hopper")
    q = [0.0, 1.0, 0.0, 0.0, 0.0]
    locked = [[1.0, 0.0], [0.0, 1e-17]]
    said = likely_cause(model, 0.0004, "euler", q, locked)
    assert said.startswith("the mass matrix is singular here (condition number 1e+17)")
    assert "gimbal lock" in said and "smaller --dt" not in said
    for sound in ([[2.0, 0.1], [0.1, 1.0]], None):
        assert "mass matrix" not in likely_cause(model, 0.0004, "euler", q, sound)


def test_a_bound_is_told_rounded_down() -> None:
    """A bound to stay under is rounded down: kv = 0.5 against a bound of 0.4999 was told
    'use kv below 0.5'."""
    from legdsl.sim.stability import below

    assert below(0.49995) == "0.499"
    assert below(7.2749e6) == "7.27e+06"
    assert below(2.5) == "2.5" and below(0.0342) == "0.0342"


def test_a_divergence_names_what_is_too_stiff_now() -> None:
    """A gain the controller set (not checked before the run) and a joint stop too stiff or
    too damped for the step are named as the likely cause, with the value to use."""
    from conftest import shipped_model

    from legdsl.ir.model import Stop
    from legdsl.lang.errors import Span
    from legdsl.sim.stability import likely_cause, stiff_now

    set_by_controller = ActuatorState("leg_spring", "spring", 0, 0, 1e9, 0.0, 0.0, 0.0, None)
    saturating = ActuatorState("hip_servo", "servo", 1, 1, 1e9, 0.0, 0.0, 0.0, 10.0)
    stop = Stop("knee", 1, 1, -0.05, 0.05, 1e5, 0.0, Span("x.leg", 1, 1, 1, 2),
                ("N*m/rad", "N*m*s/rad"))  # fmt: skip
    hopper = dataclasses.replace(shipped_model("hopper"), stops=(stop,))
    found = stiff_now(hopper, [set_by_controller, saturating], [1.0, 1e3], 4e-4, "euler")
    assert found == [
        "actuator 'leg_spring' has k = 1e+09 N/m now, too stiff for the step: use k below "
        "2.5e+07 N/m, or a step below 0.0632 ms (--dt, or dt in the simulation block)",
        "the stop of joint coordinate knee is too stiff for the step (k = 1e+05 N*m/rad): use "
        "k below 2.5e+04 N*m/rad, or a step below 0.2 ms (--dt, or dt in the simulation block)",
    ]
    said = likely_cause(hopper, 4e-4, "euler", [0.0, 1.0, 0.0, 0.0, 0.0], None, found)
    assert said.startswith("actuator 'leg_spring' has k = 1e+09 N/m now")
    assert "grew without bound" not in said


SWING = """
# A pendulum on a ball joint about x, y, x: its first and last axes line up where its middle
# angle is 0, which its swing passes close to.
creature swing {
  spatial
  body frame fixed at (0 m, 0 m, 1 m) { mass 5 kg  inertia (0.1, 0.1, 0.1) kg*m^2 }
  body bob on frame via ball pivot {
    axes (1, 0, 0), (0, 1, 0), (1, 0, 0)
    initial pivot_2 = 20 deg
    velocity pivot_1 = 0.094 rad/s, pivot_2 = -4 rad/s, pivot_3 = -0.1 rad/s
    length 0.5 m  com 0.5 m  mass 1 kg  inertia (0.001, 0.001, 0.0001) kg*m^2
  }
}
"""


def test_a_ball_joint_driven_into_gimbal_lock_is_named_as_the_cause(tmp_path: Path) -> None:
    """Its rates grow without bound near the lock: the likely cause names the joint and its
    middle angle, on both backends, instead of suggesting a smaller step."""
    from runtime_helpers import assert_same, compile_text

    from legdsl.sim.c_backend import available
    from legdsl.sim.run_loop import RunOptions

    sess = compile_text(SWING, tmp_path, "swing")
    python = sess.run(options=RunOptions(duration=1.0), backend="python").result
    assert python.status == "diverged" and python.sim_time < 0.2
    assert "Likely cause: ball joint 'pivot' is near gimbal lock: at pivot_2 = " in python.message
    assert "limits on pivot_2" in python.message and "smaller --dt" not in python.message
    if available() is None:
        assert_same(python, sess.run(options=RunOptions(duration=1.0), backend="c").result)


def test_the_spread_of_a_ball_joints_axes() -> None:
    from legdsl.ir.model import axes_spread

    x, y, z = (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)
    assert axes_spread([x, y, z], [0.3, -1.2, 2.0]) == pytest.approx(math.cos(-1.2))
    assert axes_spread([x, y, x], [0.7, 0.0, 1.1]) == pytest.approx(0.0, abs=1e-15)
    assert axes_spread([x, y, x], [0.7, math.pi / 2, 1.1]) == pytest.approx(1.0)


def test_a_templates_actuator_too_stiff_is_told_for_each_instance(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], creatures_dir: Path
) -> None:
    """One template line, four instances: each error names its instance (it repeated the
    same line four times, told apart only by the generated actuator names)."""
    leg = tmp_path / "quadruped.leg"
    text = (creatures_dir / "quadruped.leg").read_text()
    leg.write_text(text.replace("spring(k = 3000 N/m", "spring(k = 1e9 N/m", 1))
    argv = ["run", str(leg), "--time", "0.1s", "--out", str(tmp_path / "r"), "--backend", "c"]
    assert main(argv) == 2
    heads = [row for row in capsys.readouterr().err.splitlines() if "is too stiff" in row]
    assert [h.rsplit("(in ", 1)[1] for h in heads] == [
        f"instance '{name}' of template 'leg')" for name in ("fl", "fr", "rl", "rr")
    ]


def test_a_foot_that_touched_down_far_under_the_surface_is_named() -> None:
    """A foot run into a box's side face is under the box's top at once and pushed with
    thousands of weights: that is the cause (it was blamed on joint limits the blow-up
    passed); a foot down already and pushed hard as the run blows up is not named."""
    import numpy as np

    from legdsl.check.source import check_model
    from legdsl.sim.stability import likely_cause
    from legdsl.sim.trajectory import empty

    model = check_model(ROOT / "creatures" / "hopper.leg")
    weight = model.total_mass * 9.81
    run = empty(5, 1, 1, 1, 0, q_names=("x",), v_names=("x",), contact_names=("toe",))
    run.t[:] = np.arange(5) * 0.005
    run.contact[3:, 0], run.force[3, 0, 2] = 1, 500 * weight
    run.force[4] = np.nan  # the sample the run diverged in
    cause = likely_cause(model, 0.0004, "euler", model.q0, recorded=run)
    assert cause.startswith("contact 'toe' touched down far under the surface: the ground pushed")
    assert "at t = 0.0150 s, 500 times the creature's weight" in cause
    run.contact[:, 0] = 1  # down all along: a blow-up
    cause = likely_cause(model, 0.0004, "euler", model.q0, recorded=run)
    assert "touched down" not in cause


def test_a_foot_run_into_a_boxs_side_is_the_divergences_cause(
    tmp_path: Path, generated: Path
) -> None:
    """The kangaroo's jump at 4 m/s into a 20 cm box: its toe enters through the side face and
    the run diverges; the likely cause says so, on both backends alike."""
    from runtime_helpers import assert_same

    from legdsl.pipeline.session import RunSession
    from legdsl.sim.c_backend import available
    from legdsl.sim.run_loop import RunOptions

    text = (ROOT / "creatures" / "kangaroo.leg").read_text()
    anchor = "  ground {"
    assert text.count(anchor) == 1
    leg = tmp_path / "kangaroo.leg"
    box = "    terrain box(x0 = 10 m, x1 = 12 m, height = 0.2 m)\n"
    leg.write_text(text.replace(anchor, anchor + "\n" + box, 1))
    sess = RunSession.from_file(leg, generated=generated)
    options = RunOptions(duration=6.0)
    python = sess.run("jump", ["speed=4m/s"], options=options, backend="python").result
    assert python.status == "diverged"
    assert "Likely cause: contact 'toe' touched down far under the surface" in python.message
    assert "the side of a step or box" in python.message
    if available() is None:
        assert_same(python, sess.run("jump", ["speed=4m/s"], options=options, backend="c").result)
