"""A leg's joints are the chain from its hip down to its foot; a weld on that chain (a foot
body welded to the shank) moves nothing, so it may be listed or left out. Left out, the
chain rule refused the leg ("write 'joints hip, leg, ankle'")."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.check.source import check_file

HOPPER = Path(__file__).resolve().parents[2] / "creatures" / "hopper.leg"
FOOT = """  body foot on shank via fixed ankle at tip {
    length 0.04 m  com 0.02 m  mass 0.05 kg  inertia 1e-4 kg*m^2
  }
  contact toe on foot at tip
"""


@pytest.mark.parametrize("joints", ["hip, leg", "hip, leg, ankle"])
def test_a_weld_on_the_chain_may_be_left_out(tmp_path: Path, joints: str) -> None:
    text = HOPPER.read_text(encoding="utf-8").replace("  contact toe on shank at tip\n", FOOT, 1)
    text = text.replace("joints hip, leg\n", f"joints {joints}\n", 1)
    leg = tmp_path / "hopper.leg"
    leg.write_text(text, encoding="utf-8")
    assert check_file(leg)
