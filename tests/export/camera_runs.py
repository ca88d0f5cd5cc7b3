"""Runs for the camera-height tests: the planar biped's front somersault, run once per test
session, and a synthetic hop (a creature's recorded motion lifted bodily).

``legdsl run tests/good/outside/planar_biped.leg --controller flip --set speed=2m/s
--fall-tilt 180deg`` (docs/biped.md, "The front somersault") up to its landing: at its apex
the mass centre is 1.35 m up and the legs above it, out of a fixed-height camera's frame.
"""

from __future__ import annotations

import dataclasses
import shutil
from pathlib import Path

import numpy as np
from anim_runs import generated_dir, session_dir
from conftest import ROOT

from legdsl.cli import main
from legdsl.export.motion import Motion, load_motion

LEG = ROOT / "tests" / "good" / "outside" / "planar_biped.leg"
APEX = 6.5  # s: upside down, near the apex of the flight (liftoff 6.19 s, landing 6.87 s)
DURATION = 7.3  # s: the camera is back down by then

_RUN: list[Path] = []


def flip_motion(out: Path, fps: float = 60.0) -> Motion:
    """A copy, at ``out``, of the flip's run, as the player and the video read it."""
    if not _RUN:
        run = session_dir() / "runs" / "planar_biped-flip"
        status = main(
            ["run", str(LEG), "--controller", "flip", "--set", "speed=2m/s", "--time",
             f"{DURATION:g}", "--fall-tilt", "180deg", "--out", str(run),
             "--generated", str(generated_dir())]
        )  # fmt: skip
        assert status == 0, f"legdsl run planar_biped --controller flip exited with {status}"
        _RUN.append(run)
    shutil.copytree(_RUN[0], out)
    return load_motion(out, fps=fps, generated=generated_dir())


def bumped(motion: Motion, height: float, at: float = 0.5) -> Motion:
    """The motion lifted bodily by a ballistic bump ``height`` high at ``at`` (a synthetic hop
    of 1 g, zero outside it), its contacts and mass centre with it."""
    z = np.maximum(0.0, height - 0.5 * 9.81 * (motion.times - at) ** 2)
    up = np.zeros((len(z), 3))
    up[:, 2] = z
    return dataclasses.replace(
        motion,
        positions=motion.positions + up[:, None],
        com=motion.com + up,
        contact_positions=motion.contact_positions + up[:, None],
    )
