"""The actuators' recorded work (``work_positive``, ``work_negative``) against what physics says
it must be, independently of how the simulator sums it:

* a constant force on a slide does ``F * (q_end - q_start)`` of work (the definition of work,
  to the integrator's error), and with no other force the work-energy theorem holds: the
  kinetic energy (the generated ``kinetic_energy``) gains the actuators' net work, to
  round-off on both integrators (Euler's work is summed at the mean of each step's rates,
  the rule under which that holds);
* a damper's power ``-b qd^2`` is never positive: all its work is negative;
* an undamped leg spring's net work is minus the change of its elastic energy (recorded from
  the coordinate alone), and its positive work is the energy it gives back;
* both backends record the same work, bit for bit;
* the metrics report it with units, and ``energy_per_metre`` and ``cost_of_transport`` are
  the window's work over its distance and over ``m g d``.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from conftest import CREATURES, GENERATED, compile_text

from legdsl.analysis.energy import energy_rows
from legdsl.analysis.metrics import compute_metrics
from legdsl.check.source import check_model
from legdsl.pipeline.generated import load_dynamics
from legdsl.pipeline.session import RunSession
from legdsl.sim.c_backend import available
from legdsl.sim.run_loop import RunOptions
from legdsl.sim.simulate import Simulation
from legdsl.sim.trajectory import Trajectory, empty

SLIDER = """
creature slider {
  planar
  gravity 0 m/s^2
  body base free {
    mass 10 kg  inertia 0.5 kg*m^2
    initial x = 0 m, z = 1 m, pitch = 0 deg
  }
  body block on base via prismatic slide at (0 m, 0 m) {
    length 0.5 m  com (0 m, -0.25 m)  mass 2 kg  inertia 0.01 kg*m^2
  }
  actuator push on slide force(max = 100 N)
  actuator brake on slide spring(k = 0 N/m, b = 4 N*s/m)
}
"""


def test_a_constant_force_does_force_times_displacement(tmp_path: Path) -> None:
    model, dyn = compile_text(tmp_path, SLIDER)
    for integrator in ("euler", "rk4"):
        options = RunOptions(duration=0.5, fall_height=-1e6, integrator=integrator)
        sim = Simulation(model, dyn, options)
        sim.actuators.by_name["push"].force = 30.0  # N
        tr = sim.run().trajectory
        push, brake = tr.actuator_names.index("push"), tr.actuator_names.index("brake")
        slide = tr.q_names.index("slide")
        moved = tr.q[:, slide] - tr.q[0, slide]
        assert moved[-1] > 0.1  # it slid: the test is not vacuous
        # work = F * displacement, at every sample, to the integrator's error: Euler's is of
        # first order (within F dt |rate|), RK4's of fourth
        error = np.abs(tr.work_positive[:, push] - 30.0 * moved).max()
        rate = np.abs(tr.v[:, tr.v_names.index("slide")]).max()
        assert error <= (30.0 * options.dt * rate if integrator == "euler" else 1e-6)
        assert np.all(tr.work_negative[:, push] == 0.0)
        # the damper only ever takes energy out
        assert np.all(tr.work_positive[:, brake] == 0.0)
        assert tr.work_negative[-1, brake] < -0.01
        # the work-energy theorem: nothing else acts (no gravity, no ground)
        gained = tr.kinetic - tr.kinetic[0]
        net = tr.work_positive.sum(axis=1) + tr.work_negative.sum(axis=1)
        assert net[-1] > 10.0  # J
        assert np.abs(gained - net).max() < 1e-9 * net[-1]


def test_an_undamped_leg_spring_gives_back_what_it_stored(generated: Path) -> None:
    source = CREATURES / "hopper.leg"
    model = check_model(source)
    dyn = load_dynamics(model, source, generated)
    sim = Simulation(model, dyn, RunOptions(duration=0.8, drop=0.2))
    sim.actuators.by_name["leg_spring"].damping = 0.0  # a lossless spring
    tr = sim.run().trajectory
    spring = tr.actuator_names.index("leg_spring")
    stored = tr.leg_spring_energy[:, 0]  # 1/2 k (q - rest)^2, from q alone
    assert stored.max() > 5.0  # J: it landed and compressed the spring
    net = tr.work_positive[:, spring] + tr.work_negative[:, spring]
    # the spring's work is minus the change of its energy (to the step's O(dt) error)
    assert np.abs(net + (stored - stored[0])).max() < 0.01 * stored.max()
    # its positive work: the energy it released, the falls of its stored energy
    released = np.clip(-np.diff(stored), 0.0, None).sum()
    assert tr.work_positive[-1, spring] == pytest.approx(released, rel=0.02)


@pytest.mark.skipif(available() is not None, reason=f"needs a C compiler: {available()}")
def test_both_backends_record_the_same_work() -> None:
    sess = RunSession.from_file(CREATURES / "kangaroo.leg", generated=GENERATED)
    for integrator in ("euler", "rk4"):
        opts = RunOptions(duration=0.6, integrator=integrator)
        python = sess.run("hop", ["speed=3m/s"], options=opts, backend="python").result
        c = sess.run("hop", ["speed=3m/s"], options=opts, backend="c").result
        for name in ("work_positive", "work_negative"):
            a, b = getattr(python.trajectory, name), getattr(c.trajectory, name)
            assert a.shape == b.shape and a.tobytes() == b.tobytes(), (integrator, name)
        assert python.trajectory.work_positive[-1].min() > 0.0  # every actuator worked


def test_the_window_work_per_metre_and_cost_of_transport() -> None:
    """On made-up samples: 2 W of positive work while the centre of mass moves at 0.5 m/s
    along x and 0 in y, over [1 s, 3 s]: 4 J, 1 m, 4 J/m, 4 / (m g)."""
    n = 401
    tr: Trajectory = empty(n, 3, 3, 0, 0, 2, actuator_names=("a", "b"), total_mass=8.0,
                           gravity=9.81)  # fmt: skip
    tr.t[:] = np.linspace(0.0, 4.0, n)
    tr.work_positive[:, 0] = 1.5 * tr.t
    tr.work_positive[:, 1] = 0.5 * tr.t
    tr.work_negative[:, 0] = -0.25 * tr.t
    tr.com[:, 0] = tr.root_pos[:, 0] = 0.5 * tr.t
    rows = {r.key: r for r in energy_rows(tr, 1.0, 3.0)}
    assert rows["positive_work"].value == pytest.approx(4.0)
    assert rows["positive_work_a"].value == pytest.approx(3.0)
    assert rows["negative_work"].value == pytest.approx(-0.5)
    assert rows["distance"].value == pytest.approx(1.0)
    assert rows["energy_per_metre"].value == pytest.approx(4.0)
    assert rows["cost_of_transport"].value == pytest.approx(4.0 / (8.0 * 9.81))
    labels = {r.key: r.label for r in rows.values()}
    assert labels["positive_work"].endswith("(J)")
    assert labels["energy_per_metre"].endswith("(J/m)")
    assert labels["cost_of_transport"].endswith("(-)")
    standing = empty(n, 3, 3, 0, 0, 2, actuator_names=("a", "b"), total_mass=8.0)
    standing.t[:] = tr.t
    still = {r.key: r.value for r in energy_rows(standing, 1.0, 3.0)}
    assert still["distance"] == 0.0 and math.isnan(still["energy_per_metre"])
    tr.root_pos[:] = 0.0  # welded to the world: the centre of mass moves, the creature does not
    rig = {r.key: r.value for r in energy_rows(tr, 1.0, 3.0)}
    assert rig["distance"] == pytest.approx(1.0) and rig["positive_work"] == pytest.approx(4.0)
    assert math.isnan(rig["energy_per_metre"]) and math.isnan(rig["cost_of_transport"])


def test_a_trot_in_place_has_no_work_per_metre() -> None:
    """A trot in place (its root swaying, its centre of mass still but for rounding) summed
    2.7e-15 m of horizontal path and read 1.3e17 J/m and a cost of transport of 6.8e14; a
    path shorter than a millionth of the centre of mass's height is no move."""
    n = 401
    tr: Trajectory = empty(n, 3, 3, 0, 0, 1, actuator_names=("a",), total_mass=8.0,
                           gravity=9.81)  # fmt: skip
    tr.t[:] = np.linspace(0.0, 4.0, n)
    tr.work_positive[:, 0] = 100.0 * tr.t
    tr.root_pos[:, 0] = 0.01 * np.sin(tr.t * 20.0)  # the trunk sways
    tr.com[:, 0] = 1e-17 * (-1.0) ** np.arange(n)  # rounding
    tr.com[:, 2] = 0.55
    still = {r.key: r.value for r in energy_rows(tr, 1.0, 3.0)}
    assert 0.0 < still["distance"] < 1e-14 and still["positive_work"] == pytest.approx(200.0)
    assert math.isnan(still["energy_per_metre"]) and math.isnan(still["cost_of_transport"])
    tr.com[:, 0] = 1e-5 * tr.t  # 20 micrometres in the window: a move, however slow
    crept = {r.key: r.value for r in energy_rows(tr, 1.0, 3.0)}
    assert crept["energy_per_metre"] == pytest.approx(200.0 / 2e-5)


def test_a_run_reports_its_energy_and_an_older_run_loads_without(tmp_path: Path) -> None:
    import legdsl

    run = legdsl.load(CREATURES / "hopper.leg", generated=GENERATED).run(
        controller="hop", set={"speed": "1 m/s"}, time=2
    )
    metrics = run.metrics(start=0.5)
    work = metrics.value("positive_work")
    assert work > 0
    distance = metrics.value("distance")
    assert distance == pytest.approx(float(run["com.x"][-1] - np.interp(0.5, run["t"], run["com.x"])),
                                     rel=0.02)  # fmt: skip
    assert metrics.value("energy_per_metre") == pytest.approx(work / distance)
    weight = run.trajectory.total_mass * run.trajectory.gravity
    assert metrics.value("cost_of_transport") == pytest.approx(work / distance / weight)
    assert "positive actuator work per metre (J/m)" in metrics.table()
    assert run["work_positive.leg_spring"][-1] > 0
    # a run written before the work was recorded still loads; its metrics have no energy rows
    where = run.save(tmp_path / "run")
    with np.load(where / "trajectory.npz") as data:
        old = {k: data[k] for k in data.files if not k.startswith("work_")}
    meta = json.loads(bytes(old["meta"]))
    del meta["actuator_names"]
    old["meta"] = np.frombuffer(json.dumps(meta, sort_keys=True).encode(), dtype=np.uint8)
    np.savez_compressed(where / "trajectory.npz", **old)  # type: ignore[arg-type]
    again = Trajectory.load(where)
    assert again.work_positive.shape == (len(again), 0)
    keys = {s.key for s in compute_metrics(again, t_from=0.5).summaries}
    assert "stride_duration" in keys and "positive_work" not in keys
