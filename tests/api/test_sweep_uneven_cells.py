"""A sweep's heat map over unevenly spaced values: an outside user's `--grid
swing_kp=50,100,1000` drew 100's cell from 75 to 550, its tick at the foot (cells between the
values' midpoints). Now each value has an equal cell, its tick at the centre; evenly spaced
values keep their places."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from legdsl.analysis import sweep_plot


def _drawn(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, xs: list[float], ys: list[float]
) -> Any:
    from matplotlib.figure import Figure

    seen: list[Any] = []
    real = Figure.savefig

    def kept(fig: Figure, *args: Any, **kw: Any) -> Any:
        seen.append(fig.axes[0])
        return real(fig, *args, **kw)

    monkeypatch.setattr(Figure, "savefig", kept)
    rows = [{"run": k, "a": x, "b": y, "outcome": "ok" if k else "fell at 1.000 s",
             "speed_error": 0.01 * k} for k, (x, y) in enumerate((x, y) for x in xs for y in ys)]  # fmt: skip
    sweep_plot.plot_sweep(rows, ["a", "b"], "speed_error", tmp_path / "s.png")
    return seen[0]


def _centred(ax: Any) -> None:
    mesh = ax.collections[0].get_coordinates()
    x_edges, y_edges = mesh[0, :, 0], mesh[:, 0, 1]
    for ticks, edges in ((ax.get_xticks(), x_edges), (ax.get_yticks(), y_edges)):
        centres = [(p + q) / 2 for p, q in zip(edges, edges[1:], strict=False)]
        assert list(ticks) == pytest.approx(centres)


def test_uneven_values_have_equal_cells_ticked_at_their_centres(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    ax = _drawn(tmp_path, monkeypatch, [0.5, 1.0, 3.0], [50.0, 100.0, 1000.0])
    _centred(ax)
    assert [t.get_text() for t in ax.get_yticklabels()] == ["50", "100", "1000"]
    assert [t.get_text() for t in ax.get_xticklabels()] == ["0.5", "1", "3"]
    widths = {round(b - a, 9) for a, b in zip(ax.get_yticks(), ax.get_yticks()[1:], strict=False)}
    assert len(widths) == 1
    cross = ax.lines[-1]  # the run that fell, on its cell's centre
    assert (cross.get_xdata()[0], cross.get_ydata()[0]) == (0.0, 0.0)


def test_even_values_keep_their_places(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    ax = _drawn(tmp_path, monkeypatch, [0.5, 1.0, 1.5], [50.0, 100.0, 150.0])
    _centred(ax)
    assert list(ax.get_yticks()) == [50.0, 100.0, 150.0]
