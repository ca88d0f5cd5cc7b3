"""The sweep's picture: a panel per value of a third swept name, falls marked everywhere."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from matplotlib.figure import Figure

from legdsl.analysis.sweep_plot import MOST_PANELS, plot_sweep


def crosses(ax: object) -> list[tuple[float, float]]:
    """The red crosses drawn on ``ax`` (the runs that fell)."""
    out = []
    for line in ax.get_lines():  # type: ignore[attr-defined]
        if line.get_marker() == "x":
            out += list(zip(line.get_xdata(), line.get_ydata(), strict=True))
    return out


def row(outcome: str = "ok", **values: float) -> dict[str, object]:
    metric = sum(values.values()) if outcome == "ok" else math.nan
    return {**values, "outcome": outcome, "speed_error": metric}


def test_a_third_swept_name_gets_a_panel_per_value(tmp_path: Path, drawn: list[Figure]) -> None:
    """Drawn over the first two names alone, the runs at kp 200 hid those at kp 100 (one dot
    a cell), and a fall at one of them had no cross."""
    rows = [
        row(speed=s, k_speed=k, kp=p) for s in (0.5, 1) for k in (0.02, 0.1) for p in (100, 200)
    ]
    rows[-1] = row("fell at 2.000 s", speed=1, k_speed=0.1, kp=200)
    plot_sweep(rows, ["speed", "k_speed", "kp"], "speed_error", tmp_path / "s.png", {"kp": "N"})
    panels = [ax for ax in drawn[0].axes if ax.get_title()]
    assert [ax.get_title() for ax in panels] == ["kp = 100 N", "kp = 200 N"]
    assert crosses(panels[0]) == [] and crosses(panels[1]) == [(1.0, 0.1)]


def test_too_many_panels_are_one_that_says_so(tmp_path: Path, drawn: list[Figure]) -> None:
    rows = [row(a=a, b=b, c=c) for a in (1, 2) for b in (1, 2) for c in range(MOST_PANELS + 1)]
    plot_sweep(rows, ["a", "b", "c"], "speed_error", tmp_path / "s.png")
    assert drawn[0].get_suptitle().replace("\n", " ").endswith("; c varies among the dots")


def test_a_grid_name_beside_drawn_ones_is_a_scatter_under_a_title_that_fits(
    tmp_path: Path, drawn: list[Figure]
) -> None:
    """An outside user's `--grid speed=1,2 --lhs kp=... --lhs kv=... --lhs k_speed=...`: each
    speed ran the same 20 draws, so speed by kp was a full grid and drew a heat map of
    one-draw stripes (kv and k_speed varying unseen among them), under a title cut off at both
    edges."""
    draws = [
        (100 + 45 * i, 5 + 4.5 * ((7 * i) % 20), 0.05 + 0.017 * ((3 * i) % 20)) for i in range(20)
    ]
    rows = [row(speed=s, kp=p, kv=v, k_speed=k) for s in (1, 2) for p, v, k in draws]
    plot_sweep(rows, ["speed", "kp", "kv", "k_speed"], "speed_error", tmp_path / "s.png")
    (ax,) = [a for a in drawn[0].axes if a.get_label() != "<colorbar>"]
    assert ax.collections[0].__class__.__name__ == "PathCollection"  # a scatter, no QuadMesh
    title = drawn[0]._suptitle
    box = title.get_window_extent(drawn[0]._get_renderer())
    assert box.x0 >= 0 and box.x1 <= drawn[0].bbox.width  # inside the picture


def test_falls_are_crosses_in_draws_and_lines(tmp_path: Path, drawn: list[Figure]) -> None:
    """Random draws marked no fall; in the lines, a run that fell had no metric to stand at,
    and a sweep where every run fell was an empty picture."""
    draws = [row(a=0.1, b=0.2), row(a=0.3, b=0.9), row("fell at 1.000 s", a=0.7, b=0.4)]
    plot_sweep(draws, ["a", "b"], "speed_error", tmp_path / "d.png")
    assert crosses(drawn[0].axes[0]) == [(0.7, 0.4)]
    fell = [row("fell at 1.000 s", speed=s) for s in (0.5, 1.0)]
    plot_sweep(fell, ["speed"], "speed_error", tmp_path / "l.png")
    assert [x for x, _ in crosses(drawn[1].axes[0])] == [0.5, 1.0]


def ticks(axis: object) -> list[str]:
    return [t.get_text() for t in axis.get_ticklabels()]  # type: ignore[attr-defined]


def test_a_heat_maps_cells_are_labelled_with_the_swept_values(
    tmp_path: Path, drawn: list[Figure]
) -> None:
    """An outside stilt's sweep of k_speed 0.04, 0.07 and 0.1 was ticked 0.04, 0.06, 0.08 and
    0.1 (its speeds 0.25 to 2.25 by 0.25): values no run had, between the cells."""
    rows = [row(speed=s, k_speed=k) for s in (0.5, 1.0, 1.5, 2.0) for k in (0.04, 0.07, 0.1)]
    plot_sweep(rows, ["speed", "k_speed"], "speed_error", tmp_path / "s.png")
    ax = drawn[0].axes[0]
    assert list(ax.get_yticks()) == [0.04, 0.07, 0.1] and ticks(ax.yaxis) == ["0.04", "0.07", "0.1"]
    assert list(ax.get_xticks()) == [0.5, 1.0, 1.5, 2.0] and ticks(ax.xaxis) == [
        "0.5",
        "1",
        "1.5",
        "2",
    ]
    values = [0.5 + 2.5 * i / 19 for i in range(20)]
    many = [row(a=a, b=b) for a in values for b in range(30)]
    plot_sweep(many, ["a", "b"], "speed_error", tmp_path / "m.png")  # some cells' values
    ax = drawn[1].axes[0]
    assert 2 <= len(ax.get_xticks()) <= 7 and 2 <= len(ax.get_yticks()) <= 12  # room for them
    step = values.index(ax.get_xticks()[1])  # every step-th value, from the first
    assert list(ax.get_xticks()) == values[::step]
    assert ticks(ax.xaxis) == [f"{v:.4g}" for v in values[::step]]


def test_three_random_names_are_one_scatter_not_a_heat_map_per_draw(
    tmp_path: Path, drawn: list[Figure]
) -> None:
    """An outside user's `--random speed --random kp --random stroke --samples 6`: every draw of
    stroke is its own value, so it drew six panels, each a single one-cell heat map."""
    rows = [row(speed=0.5 + i / 7, kp=100 + 17 * i, stroke=0.02 + 0.003 * i) for i in range(6)]
    plot_sweep(rows, ["speed", "kp", "stroke"], "speed_error", tmp_path / "s.png", {},
               ["speed", "kp", "stroke"])  # fmt: skip
    (ax,) = [a for a in drawn[0].axes if a.get_label() != "<colorbar>"]
    assert ax.collections[0].__class__.__name__ == "PathCollection"  # a scatter, no QuadMesh
    assert len(ax.collections[0].get_offsets()) == 6
    assert drawn[0].get_suptitle().replace("\n", " ").endswith("; stroke varies among the dots")


def test_a_grid_name_beside_random_ones_is_the_panels(tmp_path: Path, drawn: list[Figure]) -> None:
    """The grid's values are the panels, the draws a scatter in each: never a cell a draw."""
    rows = [row(speed=s, kp=100 + 17 * i, kv=3 + i) for s in (1, 2) for i in range(3)]
    plot_sweep(rows, ["speed", "kp", "kv"], "speed_error", tmp_path / "s.png", {"speed": "m/s"},
               ["kp", "kv"])  # fmt: skip
    panels = [ax for ax in drawn[0].axes if ax.get_title()]
    assert [ax.get_title() for ax in panels] == ["speed = 1 m/s", "speed = 2 m/s"]
    assert all(ax.collections[0].__class__.__name__ == "PathCollection" for ax in panels)
    assert panels[0].get_xlabel() == "kp" and panels[0].get_ylabel() == "kv"


def test_a_signed_metric_is_drawn_on_a_diverging_map_centred_on_zero(
    tmp_path: Path, drawn: list[Figure]
) -> None:
    """viridis drew a signed speed_error's most negative value darkest, which reads best; a
    magnitude keeps viridis over its range."""
    rows = [
        {"speed": s, "kp": p, "outcome": "ok", "speed_error": -0.4 + 0.1 * s * p / 100,
         "stride_length": 0.1 * s * p / 100}
        for s in (0.5, 1.0, 1.5) for p in (100, 200)
    ]  # fmt: skip
    plot_sweep(rows, ["speed", "kp"], "speed_error", tmp_path / "e.png")
    (mesh,) = drawn[0].axes[0].collections
    assert mesh.get_cmap().name == "PuOr"
    assert mesh.norm.vmin == -mesh.norm.vmax == pytest.approx(-0.35)  # zero in the middle: white
    plot_sweep(rows, ["speed", "kp"], "stride_length", tmp_path / "l.png")
    (mesh,) = drawn[1].axes[0].collections
    assert mesh.get_cmap().name == "viridis"
    assert (mesh.norm.vmin, mesh.norm.vmax) == pytest.approx((0.05, 0.3))
