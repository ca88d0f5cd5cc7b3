"""The player's panel and its help text never overlap.

Each was placed at its own top corner, so a long status message (a diverged run's cause),
wrapped in the panel, ran under the help text at the top right.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

from anim_runs import creature_motion
from chromium import Chromium
from external_tools import chromium

from legdsl.export.player import write_player

LONG = "the simulation diverged at t = 0.1100 s: " + "a velocity reached 2.12e+03 rad/s; " * 20


def test_a_long_status_message_does_not_run_under_the_help(tmp_path: Path) -> None:
    motion = creature_motion("kangaroo", tmp_path / "run", duration=0.5)
    page = tmp_path / "animation.html"
    write_player(dataclasses.replace(motion, status="diverged", message=LONG), page)
    box = "(id) => { const r = document.getElementById(id).getBoundingClientRect(); return [r.left, r.top, r.right, r.bottom]; }"
    with Chromium(chromium(), 1200, 800) as browser:
        for width in (1200, 800, 500):
            browser.call("Emulation.setDeviceMetricsOverride", width=width, height=800,
                         deviceScaleFactor=1, mobile=False)  # fmt: skip
            browser.open_player(page)
            browser.evaluate(f"legdsl.setTime({motion.duration})")
            hud = browser.evaluate(f"({box})('hud')")
            help_ = browser.evaluate(f"({box})('help')")
            assert "diverged" in browser.evaluate("document.getElementById('hud').innerText")
            apart = (
                hud[2] <= help_[0] or help_[2] <= hud[0] or hud[3] <= help_[1] or help_[3] <= hud[1]
            )
            assert apart, (width, hud, help_)
            assert hud[2] <= width and help_[2] <= width, (width, hud, help_)
