"""The shipped creatures check, with the degrees of freedom and masses of Table 3."""

from __future__ import annotations

import math

import pytest
from conftest import CREATURES

from legdsl.check.source import check_model
from legdsl.cli import main


@pytest.mark.parametrize(
    ("name", "planar", "nq", "nv", "mass"),
    [
        ("kangaroo", True, 10, 10, 3.67 + 1.62 + 0.60 + 0.14 + 0.24 + 0.14 + 0.069 + 0.33),
        ("biped", False, 15, 14, 23.1 + 2 * (1.4 + 0.64)),
        ("quadruped", False, 19, 18, 10.0 + 4 * (1.5 + 1.0)),
    ],
)
def test_creature_dof_and_mass(name: str, planar: bool, nq: int, nv: int, mass: float) -> None:
    model = check_model(CREATURES / f"{name}.leg")
    assert model.planar is planar
    assert (model.nq, model.nv) == (nq, nv)
    assert math.isclose(model.total_mass, mass, rel_tol=1e-12)
    assert len(model.q0) == nq and len(model.v0) == nv


def test_kangaroo_tree_and_units() -> None:
    m = check_model(CREATURES / "kangaroo.leg")
    assert m.q_names == (
        "x",
        "z",
        "pitch",
        "hip",
        "knee",
        "ankle",
        "tail_base",
        "tail_mid",
        "tail_tip",
        "neck",
    )
    hip = m.joint("hip")
    assert hip.origin == (-0.11, 0.0, 0.0)
    knee = m.joint("knee")
    assert knee.origin == pytest.approx((0.0, 0.0, -0.13))  # 'at tip' of the thigh
    assert m.dofs[3].initial == pytest.approx(math.radians(-45))
    pad = m.ground.normal if m.ground else None
    assert pad is not None and type(pad).__name__ == "Pad"
    assert pad.thickness == pytest.approx(0.01)  # 1 cm in SI


def test_quaternion_root_starts_upright() -> None:
    m = check_model(CREATURES / "biped.leg")
    assert m.q0[:7] == pytest.approx((0, 0, 0.86, 1, 0, 0, 0))
    assert m.q_names[:7] == ("x", "y", "z", "qw", "qx", "qy", "qz")
    assert m.v_names[:6] == ("vx", "vy", "vz", "wx", "wy", "wz")


def test_cli_check_all_creatures(capsys: pytest.CaptureFixture[str]) -> None:
    files = [str(p) for p in sorted(CREATURES.glob("*.leg"))]
    assert main(["check", *files]) == 0
    out = capsys.readouterr().out
    assert "kangaroo" in out and "biped" in out and "quadruped" in out


def test_cli_show_kangaroo(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["show", str(CREATURES / "kangaroo.leg")]) == 0
    out = capsys.readouterr().out
    assert "10 DOF" in out
    assert "via revolute ankle [ankle] (1 DOF)" in out
    assert "main: joints hip, knee, ankle; foot toe" in out
    # every setting in the unit a .leg file writes it in
    assert (
        "ankle_spring: spring on ankle (k = 150 N*m/rad, b = 0.4 N*m*s/rad, rest = -115 deg)" in out
    )
    assert "knee_motor: force on knee (value = 0 N*m, max 60 N*m)" in out


def test_cli_show_gives_a_sliding_actuators_units(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["show", str(CREATURES / "hopper.leg")]) == 0
    out = capsys.readouterr().out
    assert "leg_spring: spring on leg (k = 3000 N/m, b = 5 N*s/m, rest = 0 m)" in out
