"""A joint stop in MuJoCo pushes back with the stop's own stiffness and damping.

MuJoCo's limit row takes a direct (negative) ``solref`` as a reference acceleration, not a
force: the stop was written as ``solreflimit="-k -b"``, so a knee stop of 3000 N*m/rad pushed
back with 0.45 N*m at 0.01 rad past its limit where legdsl pushes with 30 N*m. It is now
scaled by the row's weight (``dof_invweight0``), with a small impedance, as the contacts are.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import CREATURES, ROOT

from legdsl.check.source import check_file, check_model
from legdsl.export.mjcf import model_to_mjcf

mujoco = pytest.importorskip("mujoco")

LEG_LIMITS = "    limits -0.25 m to 0.1 m\n"


def _hopper_with_leg_stop(tmp_path: Path) -> Path:
    text = (CREATURES / "hopper.leg").read_text()
    assert LEG_LIMITS in text
    path = tmp_path / "hopper.leg"
    path.write_text(text.replace(LEG_LIMITS, LEG_LIMITS + "    stop k = 2e4 N/m, b = 100 N*s/m\n"))
    return path


def _push_back(xml: str, coordinate: str, past: float, rate: float) -> float:
    """The limit row's generalized force on ``coordinate`` held ``past`` its nearer limit
    (positive: beyond the upper one) moving on at ``rate``, without gravity or actuators."""
    mj = mujoco.MjModel.from_xml_string(xml)
    mj.opt.gravity[:] = 0
    mj.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_ACTUATION
    data = mujoco.MjData(mj)
    mujoco.mj_resetDataKeyframe(mj, data, 0)
    joint = mj.joint(coordinate)
    low, high = mj.jnt_range[joint.id]
    data.qpos[joint.qposadr[0]] = high + past if past > 0 else low + past
    data.qvel[:] = 0
    data.qvel[joint.dofadr[0]] = rate
    mujoco.mj_forward(mj, data)
    return abs(float(data.qfrc_constraint[joint.dofadr[0]]))


@pytest.mark.parametrize("pads", [True, False])
@pytest.mark.parametrize(
    ("past", "rate"), [(0.01, 0.0), (0.05, 0.0), (0.03, 0.4), (-0.02, 0.0), (-0.02, -0.3)]
)
def test_a_knee_stop_pushes_with_its_stiffness_and_damping(
    pads: bool, past: float, rate: float
) -> None:
    model = check_model(ROOT / "tests" / "good" / "outside" / "knee_quadruped.leg")
    (stop,) = [s for s in model.stops if s.dof == "knee_fl"]
    xml = model_to_mjcf(model, pads=pads)
    expected = stop.k * abs(past) + stop.b * abs(rate)  # legdsl's one-sided spring-damper
    assert _push_back(xml, "knee_fl", past, rate) == pytest.approx(expected, rel=0.005)


def test_a_slide_stop_pushes_with_its_stiffness(tmp_path: Path) -> None:
    (model,) = check_file(_hopper_with_leg_stop(tmp_path))
    xml = model_to_mjcf(model)
    assert 'solimplimit="0.001 0.001 0.001 0.5 2"' in xml
    assert _push_back(xml, "leg", 0.004, 0.0) == pytest.approx(2e4 * 0.004, rel=0.005)
