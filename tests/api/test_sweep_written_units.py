"""A sweep's picture shows each swept name in the unit its values were given in: a panel of
'--grid heading=0deg,90deg' was titled 'heading = 1.5708 rad' for an outside user (the table
keeps SI units, as docs/api.md says)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import pytest

from legdsl.analysis import sweep_plot
from legdsl.api.sweep import parse_axis
from legdsl.api.sweep_cli import in_written_units
from legdsl.lang.units import parse_unit

DIMS = {n: parse_unit(u)[1] for n, u in
        (("heading", "deg"), ("speed", "m/s"), ("k_speed", "s"))}  # fmt: skip


def test_a_panel_is_titled_in_the_unit_given(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    axes = [parse_axis("grid", "speed=0.5:1:2", DIMS), parse_axis("grid", "k_speed=40ms,60ms", DIMS),
            parse_axis("grid", "heading=0deg,90deg", DIMS)]  # fmt: skip
    assert [a.written for a in axes] == ["", "ms", "deg"]
    rows = [{"run": k, "speed": s, "k_speed": ks, "heading": h, "outcome": "ok", "speed_error": 0.1}
            for k, (s, ks, h) in enumerate((s, ks, h) for s in (0.5, 1.0) for ks in (0.04, 0.06)
                                           for h in (0.0, math.pi / 2))]  # fmt: skip
    units = {"speed": "m/s", "k_speed": "s", "heading": "rad", "speed_error": "m/s"}
    shown, labels = in_written_units(rows, axes, units)
    assert labels == {**units, "k_speed": "ms", "heading": "deg"}
    assert sorted({r["heading"] for r in shown}) == pytest.approx([0.0, 90.0])
    assert rows[1]["heading"] == math.pi / 2  # the table's rows untouched
    titles: list[str] = []
    from matplotlib.figure import Figure

    real = Figure.savefig

    def noted(fig: Figure, *args: Any, **kw: Any) -> Any:
        titles.extend(ax.get_title() for ax in fig.axes)
        return real(fig, *args, **kw)

    monkeypatch.setattr(Figure, "savefig", noted)
    sweep_plot.plot_sweep(shown, [a.name for a in axes], "speed_error", tmp_path / "s.png", labels)
    assert "heading = 90 deg" in titles and "heading = 0 deg" in titles
