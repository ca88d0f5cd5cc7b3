"""A creature scaled by L changes gait as the original does, its times sqrt(L) as long: the
handover's waits, its least free fall and its most turning follow the creature's size
(``switching.natural_scale``; docs/scaling.md, "Changing gait, scaled")."""

from __future__ import annotations

import json
from pathlib import Path

from conftest import CREATURES

from legdsl.cli import main

QUADRUPED = CREATURES / "quadruped.leg"


def _takeovers(out: Path) -> list[tuple[str, float, str]]:
    segments = json.loads((out / "run.json").read_text())["segments"]
    return [(s["controller"], s["from"], s["state"]) for s in segments]


def test_the_quadruped_scaled_by_a_quarter_takes_over_at_half_the_time(
    generated: Path, tmp_path: Path
) -> None:
    """The bound switched to the gallop at 0.4 s takes over at 0.904 s, in the gallop's FLIGHT;
    scaled by 0.25 (sqrt(L) = 0.5, exact in binary, so the two runs agree to 1e-9 m until then)
    at 0.452 s. With the handover's constants in absolute seconds and rad/s it waited for a
    calm flight 0.5 s (1 s of the original's) with half the turning allowed (the original's
    1.25 rad/s), and took over at 0.643 s (1.286 s of the original's)."""
    small = tmp_path / "quadruped_small.leg"
    assert main(["scale", str(QUADRUPED), "--by", "0.25", "-o", str(small)]) == 0
    common = ["--controller", "bound", "--generated", str(generated), "--backend", "python"]
    assert main(["run", str(QUADRUPED), *common, "--set", "speed=2.8m/s", "--switch",
                 "0.4s=gallop", "--set", "speed=4m/s@0.4s", "--time", "0.92",
                 "--out", str(tmp_path / "big")]) == 0  # fmt: skip
    assert main(["run", str(small), *common, "--set", "speed=1.4m/s", "--switch",
                 "0.2s=gallop", "--set", "speed=2m/s@0.2s", "--time", "0.46",
                 "--out", str(tmp_path / "small")]) == 0  # fmt: skip
    big, scaled = _takeovers(tmp_path / "big"), _takeovers(tmp_path / "small")
    assert big == [("bound", 0.0, "FLIGHT"), ("gallop", 0.904, "FLIGHT")]
    assert scaled == [("bound", 0.0, "FLIGHT"), ("gallop", 0.452, "FLIGHT")]
