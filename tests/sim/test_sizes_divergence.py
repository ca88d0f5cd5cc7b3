"""The divergence rule's speed limit follows the creature's size: 1000 m/s or rad/s for one
10 cm tall or taller (every shipped creature), more for a smaller one, whose joints turn
faster as 1/sqrt(its size) (Table 1)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from legdsl.cli import main
from legdsl.sim.sizes import DIVERGENCE_SPEED, divergence_speed

POGO = Path(__file__).resolve().parents[1] / "good" / "outside" / "insect_pogo.leg"


def test_the_limit_is_1000_from_10_cm_up_and_grows_as_one_over_sqrt_below() -> None:
    for height in (0.0, 0.1, 0.3351, 0.83, 24.0):  # 0: a root welded to the world
        assert divergence_speed(height) == DIVERGENCE_SPEED
    assert divergence_speed(0.001) == pytest.approx(1e4)


@pytest.mark.parametrize("backend", ["python", "c"])
def test_a_speck_scaled_from_the_insect_pogo_hops_without_being_called_diverged(
    backend: str, tmp_path: Path
) -> None:
    """The 3 g pogo scaled by 1/2000 (33 um tall) swings its hip at up to 1394 rad/s as it
    hops (the limit for it: about 55000): it was stopped as diverged at 5.9 ms, on either backend."""
    speck = tmp_path / "speck.leg"
    assert main(["scale", str(POGO), "--by", "0.0005", "-o", str(speck)]) == 0
    code = main(["run", str(speck), "--controller", "hop", "--time", "0.01", "--backend",
                 backend, "--generated", str(tmp_path / "gen"), "--out", str(tmp_path / "r")])  # fmt: skip
    assert code == 0
    assert json.loads((tmp_path / "r" / "run.json").read_text())["status"] == "ok"
