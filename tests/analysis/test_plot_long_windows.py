"""legdsl plot of a long window: stances narrower than a pixel, switch labels crowded together."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from conftest import CREATURES

from legdsl.analysis.plot import plot_footfall, plot_run
from legdsl.analysis.plot_marks import label_levels, visible_bars
from legdsl.sim.trajectory import empty


def _hops(folder: Path, seconds: float, stride: float, stance: float, rate: float = 100.0) -> Path:
    """A one-legged run of ``seconds``: a stance of ``stance`` s every ``stride`` s."""
    n = int(seconds * rate) + 1
    tr = empty(
        n, 3, 3, 1, 1, q_names=("x", "z", "pitch"), v_names=("x", "z", "pitch"),
        contact_names=("toe",), leg_names=("main",), leg_feet=(0,), total_mass=1.0,
    )  # fmt: skip
    tr.t[:] = np.arange(n) / rate
    tr.contact[:, 0] = (tr.t % stride) < stance
    tr.com[:, 2] = 0.5
    tr.save(folder)
    info = {"source": str(CREATURES / "hopper.leg"), "creature": "hopper"}
    (folder / "run.json").write_text(json.dumps(info))
    return folder


def _drawn(monkeypatch: pytest.MonkeyPatch) -> list[tuple[Any, np.ndarray]]:
    """The figures saved from now on, drawn, with their pixels' greys, instead of their files."""
    from matplotlib.figure import Figure

    figures: list[tuple[Any, np.ndarray]] = []

    def keep(fig: Figure, *_a: object, **_k: object) -> None:
        fig.canvas.draw()
        image = np.asarray(fig.canvas.buffer_rgba())[:, :, :3].mean(axis=2)  # type: ignore[attr-defined]
        figures.append((fig, image))

    monkeypatch.setattr(Figure, "savefig", keep)
    return figures


@pytest.mark.parametrize(
    ("seconds", "stride", "stance"),
    [(600.0, 0.66, 0.2), (160.0, 0.83, 0.17), (150.0, 0.35, 0.1)],
    ids=["a 600 s hopper", "a biped's 160 s", "a gallop's 0.1 s stances"],
)
def test_every_stance_of_a_long_window_is_drawn(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, seconds: float, stride: float, stance: float
) -> None:
    """Stances narrower than a pixel fell between pixel columns: a 600 s hopper's 913 became
    89 evenly spaced bars (a false slow gait), a biped's 0.17 s stances at 0.19 s a pixel left
    1.7 s blanks, a gallop left the rear legs' rows blank. Every stance is now ink in its
    pixel column, and no blank in the row is longer than a flight."""
    figures = _drawn(monkeypatch)
    plot_footfall(_hops(tmp_path, seconds, stride, stance), tmp_path / "f.png")
    ((fig, image),) = figures
    ax = fig.axes[0]
    row = image[int(round(image.shape[0] - ax.transData.transform((0, 0))[1]))]
    left, right = (int(x) for x in ax.transData.transform([(0, 0), (seconds, 0)])[:, 0])
    ink = row < 100
    starts = np.arange(0.0, seconds, stride)
    columns = ax.transData.transform(np.c_[starts, np.zeros_like(starts)])[:, 0]
    missing = [
        t for t, x in zip(starts, columns, strict=True) if not ink[int(x) : int(x) + 2].any()
    ]
    assert missing == []
    flight_px = (stride - stance) / seconds * (right - left)
    blanks = np.diff(np.flatnonzero(ink[left:right]))
    assert blanks.max() <= flight_px + 2


def test_a_short_window_s_bars_are_the_stances_themselves() -> None:
    """Bars a pixel wide or more are drawn as they were (the docs' pictures); one narrower is
    widened to a pixel, to the left at the window's end."""
    stances = [(0.5, 0.7), (1.0, 1.001), (1.9, 2.5)]
    bars = np.array(visible_bars(stances, 0.6, 2.0, 0.01))
    assert bars == pytest.approx(np.array([(0.6, 0.1), (1.0, 0.01), (1.9, 0.1)]))
    assert np.array(visible_bars([(1.999, 2.0)], 0.0, 2.0, 0.01)) == pytest.approx(
        np.array([[1.99, 0.01]])
    )


def test_labels_that_would_overlap_go_on_rows_above() -> None:
    assert label_levels([(0, 40), (50, 90), (100, 130)]) == [0, 0, 0]
    assert label_levels([(0, 40), (10, 50), (20, 40), (45, 60)]) == [0, 1, 2, 0]
    assert label_levels([(0, 40)] * 6, most=4) == [0, 1, 2, 3, None, None]


def test_switch_labels_of_a_long_run_do_not_overlap(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The quadruped's scene (bound at 6 s, gallop at 12 s, trot at 18 s) drawn over 150 s
    read 'boundgallotrot' in both pictures: every label is drawn, and none over another."""
    run = _hops(tmp_path, 150.0, 0.66, 0.2)
    info = json.loads((run / "run.json").read_text())
    switches = [("trot", 0.0), ("bound", 6.198), ("gallop", 12.378), ("trot", 18.032)]
    info["segments"] = [{"controller": c, "from": t} for c, t in switches]
    (run / "run.json").write_text(json.dumps(info))
    figures = _drawn(monkeypatch)
    plot_run(run, tmp_path / "f.png")
    plot_footfall(run, tmp_path / "f-footfall.png")
    for fig, _ in figures:
        labels = [t for ax in fig.axes for t in ax.texts if t.get_color() == "tab:red"]
        assert [t.get_text().strip() for t in labels] == ["bound", "gallop", "trot"]
        boxes = [t.get_window_extent() for t in labels]
        for k, box in enumerate(boxes):
            assert not any(box.overlaps(other) for other in boxes[k + 1 :])
            assert fig.bbox.contains(box.x0, box.y1) and fig.bbox.contains(box.x1, box.y0)
