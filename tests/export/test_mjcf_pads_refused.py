"""The MJCF export's anchor pads (``mjpads.py``) that a body cannot carry: the error says the
real cause and its cure."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.check.source import check_model
from legdsl.export.mjcf import model_to_mjcf
from legdsl.lang.errors import LegError

# a 2 mm ball whose smallest moment is MuJoCo's least, 1e-14 kg*m^2, with a contact at its
# centre: its pad (2e-7 kg, 4e-16 kg*m^2 as a solid sphere) is raised to that least inertia
MITE = """creature mite {
  spatial
  body ball free {
    mass 1e-6 kg
    inertia (2e-14, 2e-14, 1e-14) kg*m^2
    initial z = 1 mm
    shape sphere(r = 1 mm)
  }
  contact toe on ball at (0 m, 0 m, 0 m)
  ground {
    normal spring(k = 1 N/m, b = 0.001 N*s/m)
    tangent spring(k = 1 N/m, b = 0.001 N*s/m)
  }
}
"""


def test_a_pad_under_mujocos_inertia_floor_says_so(tmp_path: Path) -> None:
    """The body can give its pad the pad's mass and own inertia, not MuJoCo's 1e-14 floor that
    the pad's inertia is raised to: the error blamed the mass and "not a rigid body", and told
    to make the body heavier, which does not help; it says the floor and to scale up."""
    leg = tmp_path / "mite.leg"
    leg.write_text(MITE)
    with pytest.raises(LegError) as refused:
        model_to_mjcf(check_model(leg))
    message = str(refused.value)
    assert "contact 'toe'" in message and "below the least MuJoCo loads (1e-14" in message
    assert "legdsl scale FILE --by 100" in message and "--no-anchor-pads" in message
    assert "heavier" not in message


# a test stand: a 10 g frame welded to the world with a contact on it, and a swinging arm
STAND = """creature stand {
  spatial
  body frame fixed at (0 m, 0 m, 0.3 m) { mass 0.01 kg  inertia (1e-6, 1e-6, 1e-6) kg*m^2 }
  contact plate on frame at (0 m, 0 m, -0.3 m)
  body arm on frame via revolute j { axis (1, 0, 0)  length 0.2 m  mass 0.5 kg  inertia (0.002, 0.002, 0.0002) kg*m^2  initial 30 deg }
  contact tip on arm at tip
  ground { normal spring(k = 1e4 N/m, b = 100 N*s/m)  tangent spring(k = 1e4 N/m, b = 100 N*s/m) }
}
"""


def test_a_body_welded_to_the_world_carries_its_pad_without_mass(tmp_path: Path) -> None:
    """A contact on a frame welded to the world was refused as too light to give its pad
    20 g, though MuJoCo never moves the frame: it keeps its declared mass, the pad has its
    own, and the moving arm still gives its pad's."""
    mujoco = pytest.importorskip("mujoco")
    leg = tmp_path / "stand.leg"
    leg.write_text(STAND)
    mj = mujoco.MjModel.from_xml_string(model_to_mjcf(check_model(leg)))
    frame, pad = mj.body("frame"), mj.body("plate_pad")
    assert mj.body_weldid[frame.id] == 0  # welded to the world
    assert frame.mass[0] == pytest.approx(0.01)
    assert pad.mass[0] == pytest.approx(mj.body("tip_pad").mass[0])
    assert mj.body("arm").mass[0] == pytest.approx(0.5 - pad.mass[0])
