"""A leg's joints are the joints that move on the chain from its hip down to its foot. A weld
on that chain (a foot body welded to the shank, a bracket welded to the trunk) moves nothing
and has no coordinate: it is left out (the chain rule once refused a leg that left it out,
"write 'joints hip, leg, ankle'"), and listing it is refused at the weld, with the joints to
write (listed, it was taken without a word; listed first, it moved the leg's hip point off the
joint the leg turns about). A leg with no joint that moves, a peg welded on, names its weld."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.check.source import check_file
from legdsl.lang.errors import LegError

HOPPER = Path(__file__).resolve().parents[2] / "creatures" / "hopper.leg"
FOOT = """  body foot on shank via fixed ankle at tip {
    length 0.04 m  com 0.02 m  mass 0.05 kg  inertia 1e-4 kg*m^2
  }
  contact toe on foot at tip
"""


def _hopper(tmp_path: Path, joints: str) -> Path:
    text = HOPPER.read_text(encoding="utf-8").replace("  contact toe on shank at tip\n", FOOT, 1)
    text = text.replace("joints hip, leg\n", f"joints {joints}\n", 1)
    leg = tmp_path / "hopper.leg"
    leg.write_text(text, encoding="utf-8")
    return leg


def test_a_weld_on_the_chain_is_left_out(tmp_path: Path) -> None:
    assert check_file(_hopper(tmp_path, "hip, leg"))


def test_a_weld_listed_is_refused_at_the_weld(tmp_path: Path) -> None:
    leg = _hopper(tmp_path, "hip, leg, ankle")
    with pytest.raises(LegError) as caught:
        check_file(leg)
    message = str(caught.value)
    assert "joint 'ankle' is a weld ('fixed'): it moves nothing and has no coordinate" in message
    assert "leave it out: write 'joints hip, leg'" in message
    line = next(i for i, t in enumerate(leg.read_text().splitlines(), 1) if "joints hip" in t)
    column = leg.read_text().splitlines()[line - 1].index("ankle") + 1
    assert f"hopper.leg:{line}:{column}: error: joint 'ankle'" in message


WELDED = """creature w {
  planar
  body a free { mass 5 kg  inertia 0.1 kg*m^2  initial z = 0.7 m }
  body m on a via fixed mount at (0.1 m, 0 m) { length 0.05 m  mass 0.1 kg  inertia 1e-3 kg*m^2 }
  body b on m via revolute hip at tip { length 0.3 m  mass 1 kg  inertia 0.01 kg*m^2 }
  contact toe on b at tip
  leg l { joints JOINTS  foot toe }
  ground { normal spring(k = 1e4 N/m)  tangent spring(k = 1e4 N/m) }
}
"""


def test_a_weld_listed_above_the_hip_is_refused(tmp_path: Path) -> None:
    """Listed first, the bracket's weld would be the leg's hip point: not where it turns."""
    leg = tmp_path / "w.leg"
    leg.write_text(WELDED.replace("JOINTS", "mount, hip"), encoding="utf-8")
    with pytest.raises(LegError, match=r"w.leg:7:18: error: joint 'mount' is a weld.*'joints hip'"):
        check_file(leg)
    leg.write_text(WELDED.replace("JOINTS", "hip"), encoding="utf-8")
    (model,) = check_file(leg)
    assert model.legs[0].joints == ("hip",)


def test_a_peg_welded_on_names_its_weld(tmp_path: Path) -> None:
    """With no joint that moves, the weld it hangs from is the leg's one joint."""
    leg = tmp_path / "w.leg"
    text = WELDED.replace("via revolute hip at tip", "via fixed peg at tip")
    leg.write_text(text.replace("JOINTS", "peg"), encoding="utf-8")
    (model,) = check_file(leg)
    assert model.legs[0].joints == ("peg",)
