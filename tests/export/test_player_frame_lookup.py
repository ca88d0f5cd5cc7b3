"""The player's text panel reads the frame at the time shown, the last one included.

At the end of the timeline the panel showed the second-to-last frame's state
and speed (the frame lookup stopped one short of the last frame), and a time
typed as the double nearest a frame's float32 time could read the frame before.
"""

from __future__ import annotations

import re
from pathlib import Path

from anim_runs import creature_motion
from chromium import Chromium
from external_tools import chromium

from legdsl.export.player import write_player


def test_the_panel_shows_the_frame_at_the_time_shown(tmp_path: Path) -> None:
    motion = creature_motion("kangaroo", tmp_path / "run", duration=0.5)
    page = tmp_path / "animation.html"
    write_player(motion, page)
    last = motion.frames - 1
    # Frames whose speed differs from the frame before's, so a lookup one short is seen.
    chosen = [
        f
        for f in (last, last // 2, last // 3)
        if round(motion.speed[f], 2) != round(motion.speed[f - 1], 2)
    ]
    assert last in chosen
    with Chromium(chromium(), 900, 600) as browser:
        browser.open_player(page)
        for f in chosen:
            for t in (float(motion.times[f]), float(motion.times[f]) * (1 - 1e-9)):
                browser.evaluate(f"legdsl.setTime({t!r})")
                text = browser.evaluate("document.getElementById('hud').innerText")
                shown = re.search(r"speed: (-?[0-9.]+) m/s", text)
                assert shown, text
                assert float(shown.group(1)) == round(float(motion.speed[f]), 2) + 0.0, (f, t, text)
                if 0 <= motion.state[f] < len(motion.state_names):
                    name = motion.state_names[motion.state[f]]
                    assert f"state: {name}" in text, (f, t, text)


def test_a_tiny_run_s_readouts_are_in_ms_and_mm_per_s(tmp_path: Path) -> None:
    """A hopper scaled by 0.0001 read 'speed: 0.00 m/s' and '0.00 / 0.03 s'."""
    import dataclasses

    motion = creature_motion("kangaroo", tmp_path / "run", duration=0.5)
    small = dataclasses.replace(
        motion,
        times=motion.times * 0.05,
        speed=motion.speed * 0.01,
        speed_command=motion.speed_command * 0.01,
    )
    page = tmp_path / "animation.html"
    write_player(small, page)
    with Chromium(chromium(), 900, 600) as browser:
        browser.open_player(page)
        last = small.frames - 1
        browser.evaluate(f"legdsl.setTime({float(small.times[last])!r})")
        text = browser.evaluate("document.getElementById('hud').innerText")
        assert f"t = {small.times[last] * 1e3:.3f} ms" in text, text
        assert f"speed: {small.speed[last] * 1e3:.2f} mm/s" in text, text
        clock = browser.evaluate("document.getElementById('clock').textContent")
        assert clock == f"{small.times[last] * 1e3:.2f} / {small.times[last] * 1e3:.2f} ms"
