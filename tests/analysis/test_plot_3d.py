"""legdsl plot of a 3D run draws its roll beside its pitch and its sideways speed beside its
forward speed: a 3D creature tips and drifts sideways too, which the panels left out."""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import pytest
from anim_runs import creature_run

from legdsl.analysis.plot import plot_run


def _labels(run: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> list[list[str]]:
    """The line labels of each panel of the run's picture."""
    figures, close = [], plt.close
    monkeypatch.setattr(plt, "close", figures.append)  # kept open to be looked at
    plot_run(run, tmp_path / "f.png")
    (fig,) = figures
    labels = [[line.get_label() for line in ax.get_lines()] for ax in fig.axes]
    close(fig)
    return labels


def test_a_3d_run_draws_roll_and_sideways_speed(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    labels = _labels(creature_run("quadruped", tmp_path / "run"), tmp_path, monkeypatch)
    assert "roll" in labels[1] and "pitch" in labels[1]
    assert "sideways speed" in labels[2] and "forward speed" in labels[2]


def test_a_planar_run_draws_pitch_and_forward_speed_alone(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    labels = _labels(creature_run("hopper", tmp_path / "run"), tmp_path, monkeypatch)
    assert "roll" not in labels[1] and "sideways speed" not in labels[2]
