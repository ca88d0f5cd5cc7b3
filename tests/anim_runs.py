"""Short runs of the shipped creatures for the animation tests."""

from __future__ import annotations

from pathlib import Path

from conftest import CREATURES
from standin import ModelKinematics, synthetic_run

from legdsl.checker import check_model
from legdsl.motion import Motion, load_motion


def creature_run(name: str, out: Path, duration: float = 1.0) -> Path:
    """A run directory for creatures/NAME.leg."""
    source = CREATURES / f"{name}.leg"
    synthetic_run(check_model(source), source, out, duration=duration)
    return out


def creature_motion(name: str, out: Path, duration: float = 1.0, fps: float = 60.0) -> Motion:
    source = CREATURES / f"{name}.leg"
    creature_run(name, out, duration)
    return load_motion(out, fps=fps, kinematics=ModelKinematics(check_model(source)))
