"""tune.png, the objective per generation: an outside user's was ticked 1.0, 1.5, 2.0, 2.5...
(generations are whole numbers; one generation alone was ticked 0.945 to 1.05), and its legend
lay over the points it fell on."""

from __future__ import annotations

from pathlib import Path

import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from legdsl.api.tune import plot_history


def history(n: int) -> list[dict[str, float]]:
    return [{"generation": g, "best": 0.5 / g, "mean": 1.0 / g} for g in range(1, n + 1)]


@pytest.mark.parametrize("generations", [1, 2, 4, 25])
def test_the_generations_are_ticked_whole(
    tmp_path: Path, drawn: list[Figure], generations: int
) -> None:
    plot_history(history(generations), tmp_path / "tune.png", 2.0)
    ax = drawn[0].axes[0]
    low, high = ax.get_xlim()
    shown = [t for t in ax.get_xticks() if low <= t <= high]
    assert shown and all(float(t).is_integer() for t in shown), shown
    assert min(shown) >= 1 and max(shown) <= generations


def test_the_legend_is_outside_the_axes(tmp_path: Path, drawn: list[Figure]) -> None:
    plot_history(history(4), tmp_path / "tune.png", 2.0)
    fig = drawn[0]
    renderer = FigureCanvasAgg(fig).get_renderer()  # closed by plot_history: a canvas anew
    ax = fig.axes[0]
    legend = ax.get_legend().get_window_extent(renderer)
    assert legend.y1 <= ax.get_window_extent(renderer).y0  # below the axes
    assert legend.x0 >= 0 and legend.x1 <= fig.bbox.x1  # and whole in the picture
