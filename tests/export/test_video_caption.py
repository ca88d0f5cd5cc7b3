"""A video's caption wraps a long status message within the frame.

The caption of a run that did not end ok ran its message on one line, off the frame's right
edge (a diverged biped's last frame lost most of the cause).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest
from anim_runs import creature_motion

from legdsl.export.motion import Motion

LONG = "the simulation diverged at t = 0.1100 s: " + "a velocity reached 2.12e+03 rad/s; " * 30


@pytest.fixture(scope="module")
def kangaroo(tmp_path_factory: pytest.TempPathFactory) -> Motion:
    return creature_motion("kangaroo", tmp_path_factory.mktemp("kangaroo") / "run")


@pytest.mark.parametrize("size", [(9.6, 5.4), (3.2, 1.8)])
def test_a_long_status_message_is_wrapped_within_the_frame(
    kangaroo: Motion, tmp_path: Path, size: tuple[float, float]
) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from legdsl.export.player import OVERLAYS
    from legdsl.export.video_caption import CAPTION_LINES
    from legdsl.export.video_views import SideView

    diverged = dataclasses.replace(kangaroo, status="diverged", message=LONG)
    fig = plt.figure(figsize=size, dpi=100)
    try:
        ax = fig.add_axes((0, 0, 1, 1))
        view = SideView(diverged, ax, OVERLAYS, size[0] / size[1])
        view.update(diverged.at(float(diverged.times[-1])))
        text = view.text.get_text()
        assert "diverged: the simulation diverged" in text.replace("\n", " ")
        assert len(text.split("\n")) <= 3 + CAPTION_LINES
        fig.canvas.draw()
        box = view.text.get_window_extent()
        assert box.x1 <= fig.bbox.width, (box, fig.bbox.width)
    finally:
        plt.close(fig)
