"""Springs and servos on coupled coordinates checked together before a run
(``legdsl.sim.coupled``), and a ball joint near gimbal lock named where the pose is why.

Reported from outside: a 2 kg tail on a ball joint (axes x, y, z) 20 deg from gimbal lock,
a servo with kv = 1 N*m*s/rad on each coordinate. Each servo passed the check alone (the
diagonal of M^-1), the run diverged within 15 steps, and was told 'the state grew without
bound; try a smaller step or --integrator rk4' (rk4 diverged too): the x and z coordinates
turn the tail about its light axis together. At 89.5 deg each servo was refused alone, with
no word of the pose."""

from __future__ import annotations

import random
from pathlib import Path

import numpy as np
import pytest

from legdsl.cli import main
from legdsl.sim.actuators import ActuatorState
from legdsl.sim.coupled import InverseInertia
from legdsl.sim.stability import too_stiff

BALLTAIL = """\
creature balltail {
  spatial
  body base fixed at (0 m, 0 m, 1 m) { mass 5 kg  inertia (0.1, 0.1, 0.1) kg*m^2 }
  body tail on base via ball swivel at (0 m, 0 m, 0 m) {
    direction (-1, 0, 0)
    length 0.5 m  com 0.4 m  mass 2 kg  inertia (0.002, 0.05, 0.05) kg*m^2
    initial swivel_x = 0 deg, swivel_y = MIDDLE deg, swivel_z = 0 deg
    velocity swivel_x = 30 deg/s, swivel_z = 40 deg/s
  }
  actuator sx on swivel_x servo(kp = 50 N*m/rad, kv = 1 N*m*s/rad)
  actuator sy on swivel_y servo(kp = 50 N*m/rad, kv = 1 N*m*s/rad)
  actuator sz on swivel_z servo(kp = 50 N*m/rad, kv = 1 N*m*s/rad)
}
"""
LOCK = (
    "ball joint 'swivel' is 20 deg from gimbal lock here (swivel_y = 70 deg: its axes lie "
    "within 20 deg of one plane), and its coordinates' inertia shrinks the nearer it comes"
)


def _run(tmp_path: Path, middle: str, *more: str) -> int:
    leg = tmp_path / "balltail.leg"
    leg.write_text(BALLTAIL.replace("MIDDLE", middle), encoding="utf-8")
    return main(["run", str(leg), "--time", "0.1", "--generated", str(tmp_path / "gen"),
                 "--out", str(tmp_path / "run"), *more])  # fmt: skip


def test_two_servos_of_a_ball_near_gimbal_lock_are_refused_together(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert _run(tmp_path, "70") == 2
    err = capsys.readouterr().err
    for one, other in (("sx", "sz"), ("sz", "sx")):
        assert (
            f"actuator '{one}' is too damped for the integration step together with '{other}' "
            "(their coordinates share a mode lighter than any of them alone): kv = 1 N*m*s/rad "
            f"with dt = 0.4 ms diverges at once; use kv below 0.611 N*m*s/rad (and the kv of "
            f"'{other}' by as much), or a step below 0.246 ms (--dt, or dt in the simulation "
            f"block), or a 'max' for it in the .leg file (--set cannot give one); {LOCK}"
        ) in err
    assert "'sy'" not in err  # the middle coordinate's servo is no part of it
    # what it advises runs
    assert _run(tmp_path, "70", "--dt", "0.24ms", "--backend", "python") == 0
    kv = ["--set", "sx.kv=0.6N*m*s/rad", "--set", "sz.kv=0.6N*m*s/rad", "--backend", "python"]
    assert _run(tmp_path, "70", *kv) == 0


def test_a_servo_refused_alone_near_gimbal_lock_is_told_why(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert _run(tmp_path, "89.5") == 2
    err = capsys.readouterr().err
    assert "actuator 'sx' is too damped for the integration step: kv = 1 N*m*s/rad" in err
    assert "; ball joint 'swivel' is 0.5 deg from gimbal lock here (swivel_y = 89.5 deg" in err


def test_away_from_gimbal_lock_the_servos_pass(tmp_path: Path) -> None:
    assert _run(tmp_path, "0", "--backend", "python") == 0


def _damper(name: str, v_index: int, k: float, b: float) -> ActuatorState:
    return ActuatorState(name, "spring", v_index, v_index, k, b, 0.0, 0.0, None)


def test_two_dampers_on_one_coordinate_are_summed() -> None:
    """Each passes alone (c h = 1.5 < 2), together they do not (3): no pose is to blame."""
    inverse = InverseInertia(np.array([[1.0]]))
    pair = [_damper("a", 0, 0.0, 1.5 / 0.01), _damper("b", 0, 0.0, 1.5 / 0.01)]
    found = too_stiff(pair, inverse, 0.01, "euler", set())
    assert [(f.actuator, f.together, f.why) for f in found] == [
        ("a", ("b",), ""),
        ("b", ("a",), ""),
    ]
    assert found[0].dt_limit == pytest.approx(0.01 * 2 / 3)  # c h < 2 for c = 300
    assert too_stiff(pair[:1], inverse, 0.01, "euler", set()) == []
    assert too_stiff(pair, inverse, 0.01, "euler", {("b", "b")}) == []  # b's is the controller's


def _grows(w: np.ndarray, k: np.ndarray, b: np.ndarray, h: float, integrator: str) -> bool:
    """Whether x'' = -W (K x + B x'), stepped as the runtime steps it, blows up."""
    x, v = np.ones(len(k)), np.zeros(len(k))

    def acc(x: np.ndarray, v: np.ndarray) -> np.ndarray:
        return -w @ (k * x + b * v)

    for _ in range(3000):
        if integrator == "euler":
            v = v + h * acc(x, v)
            x = x + h * v
        else:
            k1x, k1v = v, acc(x, v)
            k2x, k2v = v + h / 2 * k1v, acc(x + h / 2 * k1x, v + h / 2 * k1v)
            k3x, k3v = v + h / 2 * k2v, acc(x + h / 2 * k2x, v + h / 2 * k2v)
            k4x, k4v = v + h * k3v, acc(x + h * k3x, v + h * k3v)
            x = x + h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x)
            v = v + h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v)
    return not np.abs(np.concatenate([x, v])).max() < 10.0


@pytest.mark.parametrize("integrator", ["euler", "rk4"])
def test_the_check_together_agrees_with_stepping_the_coupled_system(integrator: str) -> None:
    rng = random.Random(7)
    reach = 1.0 if integrator == "euler" else 2.5  # RK4's bounds are wider
    said = []
    for _ in range(150):
        n = rng.choice([2, 3])
        a = np.array([[rng.uniform(-1, 1) for _ in range(n)] for _ in range(n)])
        w = a @ a.T + 0.05 * np.eye(n)  # an inverse inertia: symmetric, positive definite
        h = 0.01
        springs = [_damper(f"s{i}", i, reach * rng.uniform(0, 3) / h**2 / w[i, i] / n,
                           reach * rng.uniform(0, 1.5) / h / w[i, i]) for i in range(n)]  # fmt: skip
        k = np.array([s.gain for s in springs])
        b = np.array([s.damping for s in springs])
        if too_stiff(springs, list(np.diag(w)), h, integrator, set()):
            continue  # refused alone, by the single check's bounds (tests/sim/test_stability.py)
        found = too_stiff(springs, InverseInertia(w), h, integrator, set())
        grows = _grows(w, k, b, h, integrator)
        said.append(grows)
        assert bool(found) == grows, (w, k, b)
        if found and found[0].limit > 0:  # its bound, a little under it, is stable
            f = found[0]
            lower = f.limit / f.value * 0.98
            named = {x.actuator for x in found}
            k2 = np.array([s.gain * (lower if s.name in named and f.setting == "k" else 1)
                           for s in springs])  # fmt: skip
            b2 = np.array([s.damping * (lower if s.name in named and f.setting == "b" else 1)
                           for s in springs])  # fmt: skip
            assert not _grows(w, k2, b2, h, integrator)
            assert not _grows(w, k, b, found[0].dt_limit * 0.98, integrator)
    assert 5 < sum(said) < len(said) - 5  # both outcomes were drawn
