"""Random rigs: the random creatures of tests/lower/test_random_creatures.py with what that
generator leaves out, as people outside the team write them: actuators of every kind (springs,
servos, force and torque sources, with and without ``max``) on hinges, slides and the hinges
of gimbals and balls; joint ``limits`` with and without ``stop``; ``initial`` and
``velocity``; templates of limbs hung from a generated body, instanced up to three times,
mirrored or not; contacts on several bodies; every ground (linear spring or paw pad, with or
without torsion and friction, steps, boxes or a slope); and welded roots placed so that their
lowest contact starts just above the ground (free roots are dropped onto it).

Each must compile (as ``legdsl run`` compiles it); a passive run of 0.3 s must be the same on
the Python and C backends (``assert_same``: one that ends by a fall or a divergence ends alike);
``legdsl export`` must write an MJCF that MuJoCo loads with the contacts where legdsl puts them,
and a URDF MuJoCo loads. Contact models differ, so no run is compared with MuJoCo's.

The rigs are drawn by tests/random_rigs.py. ``LEGDSL_RANDOM_RIGS=N`` checks N rigs (default ``CI_RIGS``) from seeds
``LEGDSL_RANDOM_RIG_SEED``, +1, ...; a failure names its seed and prints the rig's text.
"""

from __future__ import annotations

import contextlib
import io
import math
import os
from pathlib import Path

import numpy as np
import pytest
from runtime_helpers import assert_same, needs_c_compiler
from seeded import told_with_seed

from legdsl.cli import main
from legdsl.lang.errors import LegError
from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions

mujoco = pytest.importorskip("mujoco")
from random_rigs import follow_advice, placed_rig, rig_shown  # noqa: E402  (needs mujoco)

CI_RIGS = 3  # a planar free root; a 3D welded one with a mirrored limb; 3 planar limbs
COUNT = int(os.environ.get("LEGDSL_RANDOM_RIGS", CI_RIGS))
FIRST_SEED = int(os.environ.get("LEGDSL_RANDOM_RIG_SEED", "0"))
DURATION = 0.3

pytestmark = needs_c_compiler


def _check_exports(source: Path, session: RunSession, folder: Path) -> None:
    """MJCF and URDF exports MuJoCo loads; the MJCF's contact sites where legdsl puts them and
    its joint ranges where legdsl's stops are."""
    model = session.model
    files = {}
    for fmt, extra in (("mjcf", []), ("urdf", ["--link-mass", "1e-6"])):
        files[fmt] = folder / f"{source.stem}.{fmt}"
        argv = ["export", str(source), "--format", fmt, "-o", str(files[fmt]), *extra]
        said = io.StringIO()
        with contextlib.redirect_stderr(said):
            status = main(argv)
        if status != 0 and fmt == "mjcf" and "--no-anchor-pads" in said.getvalue():
            # a light body cannot give a contact's anchor pad its mass: refused, saying so
            status = main([*argv, "--no-anchor-pads"])
        assert status == 0, f"legdsl export --format {fmt} failed: {said.getvalue()}"
    for fmt, path in files.items():
        mj = mujoco.MjModel.from_xml_path(str(path))
        joints = {mj.joint(i).name for i in range(mj.njnt)}
        assert {d.name for d in model.dofs} <= joints, f"{fmt}: coordinates missing"
    mj = mujoco.MjModel.from_xml_path(str(files["mjcf"]))
    for stop in model.stops:  # the runtime's stop where MuJoCo's joint range is (mirrored too)
        at = mj.jnt_range[mj.joint(stop.dof).id]
        assert np.allclose(at, (stop.low, stop.high), rtol=0, atol=1e-12), (
            f"stop on {stop.dof} at {(stop.low, stop.high)}, the MJCF's range {at}"
        )
    data = mujoco.MjData(mj)
    mujoco.mj_resetDataKeyframe(mj, data, mj.key("initial").id)
    mujoco.mj_kinematics(mj, data)
    points = session.dynamics.contact_positions([float(x) for x in model.q0])
    for c, p in zip(model.contacts, points, strict=True):
        site = data.site(c.name).xpos
        assert np.allclose(site, p, atol=1e-9), f"MJCF site {c.name} at {site}, legdsl {p}"


def check_rig(seed: int, folder: Path) -> None:
    source, drop = placed_rig(seed, folder)
    session = RunSession.from_file(source, generated=folder / "generated")
    rng = np.random.default_rng([seed, 9])
    falls = rng.random() < 0.5  # the default fall rules, or none: the whole run
    opts = RunOptions(
        duration=DURATION,
        drop=drop,
        record_rate=float(rng.choice([0.0, 200.0])),
        **({} if falls else {"fall_height": 0.0, "fall_tilt": math.pi}),
    )
    for _ in range(3):
        try:
            python = session.run(options=opts, backend="python").result
            break
        except LegError as e:  # an actuator too stiff or damped for the step: refused, soundly
            follow_advice(source, str(e))
            session = RunSession.from_file(source, generated=folder / "generated")
    else:
        python = session.run(options=opts, backend="python").result
    c = session.run(options=opts, backend="c").result
    assert_same(python, c)
    _check_exports(source, session, folder)


SEEDS = range(FIRST_SEED, FIRST_SEED + COUNT)


@pytest.mark.parametrize("seed", SEEDS)
def test_random_rig_runs_alike_on_both_backends_and_exports(seed: int, tmp_path: Path) -> None:
    rerun = f"LEGDSL_RANDOM_RIG_SEED={seed} LEGDSL_RANDOM_RIGS=1"
    with told_with_seed(f"random rig of seed {seed}", rerun, lambda: rig_shown(seed, tmp_path)):
        check_rig(seed, tmp_path)


def test_the_torsion_spring_on_a_slope_turns_a_foot_alike_on_both_backends(tmp_path: Path) -> None:
    """Rig 107: 3D, torsion, a slope of -14.9 degrees. The spring turns the foot about the slope's
    normal (tests/sim/test_random_energy.py checks the physics): C follows Python bit for bit."""
    check_rig(107, tmp_path)
