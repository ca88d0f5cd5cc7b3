"""The simulation runtime on small creatures whose motion is known analytically."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from runtime_helpers import compile_text, run

# A 10 kg mass on a massless-looking spring leg: the paper's one-legged hopper reduced to
# its spring-mass core. The ground is 100 times stiffer than the leg (in series with it).
HOPPER = """
creature hopper {
  planar
  gravity 9.81 m/s^2
  body mass free { mass 10 kg  inertia 0.5 kg*m^2  initial x = 0 m, z = 1.0 m }
  body leg on mass via prismatic slide {
    length 0.5 m  com 0.5 m  mass 0.01 kg  inertia 1e-6 kg*m^2
  }
  contact foot on leg at tip
  actuator spring on slide spring(k = 2000 N/m, b = 0 N*s/m, rest = 0 m)
  # Damping near critical for the 10 g foot on the ground spring, so the foot lands without chatter.
  ground {
    normal spring(k = 2e5 N/m, b = 100 N*s/m)
    tangent spring(k = 1e5 N/m, b = 100 N*s/m)
  }
}
"""

SLED = """
creature sled {
  planar
  body block free { mass 1 kg  inertia 0.01 kg*m^2  initial x = 0 m, z = 0.001 m }
  contact corner on block at (0 m, 0 m)
  ground {
    normal spring(k = 1e4 N/m, b = 40 N*s/m)
    tangent spring(k = 1e4 N/m, b = 40 N*s/m)
    friction 0.5
    terrain slope(angle = ANGLE)
  }
}
"""


@pytest.fixture(scope="module")
def hopper(tmp_path_factory: pytest.TempPathFactory):
    return compile_text(HOPPER, tmp_path_factory.mktemp("hopper"), "hopper")


def _events(result, kind: str) -> list[float]:
    return [e["t"] for e in result.events if e["kind"] == kind]


def test_spring_mass_bounce_period_and_eq2_apex(hopper) -> None:
    result = run(hopper, duration=2.2, dt=1e-4, integrator="rk4", record_rate=0)
    assert result.status == "ok"
    touch, lift = _events(result, "touchdown"), _events(result, "liftoff")
    assert len(touch) >= 3 and len(lift) >= 2

    # Analytic: compression y'' = g - w^2 y from y = 0, y' = v0 at touchdown.
    mass, g = 10.0, 9.81
    k = 1.0 / (1.0 / 2000.0 + 1.0 / 2e5)  # leg and ground springs in series
    w = math.sqrt(k / mass)
    v0 = math.sqrt(2 * g * 0.5)  # the foot starts 0.5 m above the ground
    stance = (math.pi + 2 * math.atan2(g / w**2, v0 / w)) / w
    period = stance + 2 * v0 / g
    assert lift[0] - touch[0] == pytest.approx(stance, rel=0.01)
    assert touch[1] - touch[0] == pytest.approx(period, rel=0.01)

    # Eq. (2): in mid-stance, (strain + elevation + kinetic energy) / Mg predicts the next apex.
    # (The first stance: after it the undamped 10 g leg rings on its spring and later landings chatter.)
    tr = result.trajectory
    mid = np.searchsorted(tr.t, 0.5 * (touch[0] + lift[0]))
    total_mass = tr.total_mass
    strain = tr.elastic[mid]  # the leg spring and the ground springs
    kinetic = tr.kinetic[mid]
    predicted = (strain + total_mass * g * tr.com[mid, 2] + kinetic) / (total_mass * g)
    flight = (tr.t > lift[0]) & (tr.t < touch[1])
    assert tr.com[flight, 2].max() == pytest.approx(predicted, rel=0.01)
    assert predicted == pytest.approx(
        tr.com[0, 2], rel=0.01
    )  # and energy came back: the drop height


def test_same_inputs_give_byte_identical_trajectories(hopper, tmp_path: Path) -> None:
    for name in ("a", "b"):
        result = run(hopper, duration=0.6)
        result.trajectory.save(tmp_path / name)
    assert (tmp_path / "a" / "trajectory.npz").read_bytes() == (
        tmp_path / "b" / "trajectory.npz"
    ).read_bytes()
    assert (tmp_path / "a" / "trajectory.csv").read_text() == (
        tmp_path / "b" / "trajectory.csv"
    ).read_text()


def test_divergence_stops_with_time_state_and_cause_and_keeps_the_record(hopper) -> None:
    result = run(hopper, duration=2.0, dt=0.004, control_dt=0.004)
    assert result.status == "diverged"
    assert "t = " in result.message and "Likely cause" in result.message
    assert "too large for the contact stiffness" in result.message
    assert "z=" in result.message  # the state is printed by coordinate name
    assert len(result.trajectory) > 0 and result.trajectory.t[-1] < 2.0
    assert np.isfinite(result.trajectory.q).all()


def test_a_tipped_hopper_is_reported_as_a_fall(hopper) -> None:
    from legdsl.sim.run_loop import RunOptions
    from legdsl.sim.simulate import Simulation

    sim = Simulation(
        hopper.model, hopper.dynamics, RunOptions(duration=5.0, dt=1e-4, integrator="rk4")
    )
    sim.q[2] = 0.3  # pitched 17 degrees: it lands on a slant leg and topples
    result = sim.run()
    assert result.status == "fell"
    assert "tilted" in result.message or "fell below" in result.message
    assert result.sim_time < 5.0


# An arm welded to the world whose reach (500 m) dwarfs its base's height (1 m): the fall rule
# took 0.3 of the base's height over the arm's tip as the height to stay above.
LONG_ARM = """
creature crane {
  spatial
  body frame fixed at (0 m, 0 m, 1 m) { mass 5 kg  inertia (0.1, 0.1, 0.1) kg*m^2 }
  body arm on frame via revolute shoulder {
    axis (0, 1, 0)
    initial 80 deg
    length 500 m  com 250 m  mass 1 kg  inertia (0.001, 0.001, 0.0001) kg*m^2
  }
  contact tip on arm at tip
}
"""


def test_a_root_welded_to_the_world_never_falls(tmp_path: Path) -> None:
    from runtime_helpers import assert_same

    from legdsl.sim.c_backend import available
    from legdsl.sim.run_loop import RunOptions

    crane = compile_text(LONG_ARM, tmp_path, "crane")
    result = crane.run(options=RunOptions(duration=0.5), backend="python").result
    assert result.status == "ok", result.message  # it was 'fell' at t = 0 (limit 26 m)
    q = result.trajectory.q[:, 0]
    assert q[-1] < q[0] - 1e-3  # and the arm swings down all the same (slowly: it is 500 m)
    if available() is None:
        assert_same(result, crane.run(options=RunOptions(duration=0.5), backend="c").result)


@pytest.mark.parametrize(("angle", "slips"), [(15.0, False), (35.0, True)])
def test_friction_cone_on_a_slope(tmp_path: Path, angle: float, slips: bool) -> None:
    sled = compile_text(SLED.replace("ANGLE", f"{angle} deg"), tmp_path, "sled")
    result = run(sled, duration=1.0, dt=2e-4, integrator="rk4")
    assert result.status == "ok"
    tr = result.trajectory
    a = math.radians(angle)
    along = tr.root_pos[:, 0] * math.cos(a) + tr.root_pos[:, 2] * math.sin(a)
    slid = along[0] - along[-1]
    if slips:
        # Sliding down with acceleration g (sin a - mu cos a), give or take the settling.
        expected = 0.5 * 9.81 * (math.sin(a) - 0.5 * math.cos(a)) * tr.t[-1] ** 2
        assert slid == pytest.approx(expected, rel=0.1)
    else:
        assert abs(slid) < 2e-3  # held by the tangential spring, a millimetre at most
