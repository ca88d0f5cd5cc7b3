"""Figure 6's joint curves told apart, its height panel named for what it draws, and a root
welded to the world said so.

Reported from outside: ``legdsl plot`` of a leg of five joints (a ball joint's sh_x, sh_y,
sh_z, then el and tw) drew sh_x and tw both solid black (four line styles, one colour): they
crossed and could not be told apart. The height panel, 'body height', drew the centre of
mass's height (0.60 m under a root fixed at 0.8 m), and a rig welded to the world had a pitch
panel of flat zeros with no word why."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

import legdsl
from legdsl.analysis.plot import Drawn, draw_run, pyplot
from legdsl.analysis.plot_panels import MOST_CURVES
from legdsl.cli import main
from legdsl.sim.trajectory import empty

RIG = """\
creature rig {
  spatial
  gravity 9.81 m/s^2
  body base fixed at (0 m, 0 m, 0.8 m) { mass 1 kg  inertia (0.01, 0.01, 0.01) kg*m^2 }
  body upper on base via ball sh {
    length 0.4 m  com 0.2 m  mass 4 kg  inertia (0.06, 0.06, 0.005) kg*m^2
    initial sh_x = 30 deg, sh_y = 20 deg
  }
  body lower on upper via revolute el at tip {
    axis (1, 0, 0)
    length 0.3 m  com 0.15 m  mass 1 kg  inertia (0.01, 0.01, 0.001) kg*m^2
    initial -40 deg
  }
  body twist on lower via revolute tw at tip {
    axis (0, 0, 1)
    length 0.05 m  com 0.025 m  mass 0.2 kg  inertia (0.0002, 0.0002, 0.0002) kg*m^2
  }
  contact toe on twist at tip
  leg only { joints sh, el, tw  foot toe }
}
"""


@pytest.fixture
def figures(monkeypatch: pytest.MonkeyPatch) -> list[Any]:
    import matplotlib.pyplot as plt

    drawn: list[Any] = []
    close = plt.close
    monkeypatch.setattr(plt, "close", lambda fig: (drawn.append(fig), close(fig)))
    return drawn


def _joint_panels(fig: Any) -> list[Any]:
    return [ax for ax in fig.axes if "joint angles" in ax.get_ylabel()]


def _styles(ax: Any) -> list[tuple[Any, str]]:
    from matplotlib.colors import to_rgba

    return [(to_rgba(line.get_color()), line.get_linestyle()) for line in ax.get_lines()
            if not line.get_label().startswith("_")]  # fmt: skip


@pytest.mark.parametrize("joints", [1, 4, 5, 8, 9, 20, 40])
def test_every_joint_curve_of_a_panel_is_told_apart(
    tmp_path: Path, figures: list[Any], joints: int
) -> None:
    names = tuple(f"j{k}" for k in range(joints))
    tr = empty(50, joints, joints, 1, 1, q_names=names, v_names=names, contact_names=("toe",),
               leg_names=("only",), leg_feet=(0,), total_mass=1.0)  # fmt: skip
    tr.t[:] = np.arange(50) * 0.01
    tr.q[:] = np.arange(joints) * 0.01  # every curve drawn, each apart from the others
    draw_run(pyplot(), tr, Drawn("many", "many", None, []), tmp_path / "f.png", names)
    (fig,) = figures
    panels = _joint_panels(fig)
    drawn = [line.get_label() for ax in panels for line in ax.get_lines()]
    assert sorted(drawn) == sorted(names)  # each joint once
    for ax in panels:
        styles = _styles(ax)
        assert 0 < len(styles) <= MOST_CURVES
        assert len(set(styles)) == len(styles), ax.get_ylabel()  # no two curves alike
    assert len(panels) == -(-joints // MOST_CURVES)  # as few panels as hold them
    if len(panels) > 1:
        assert f"1 of {len(panels)}" in panels[0].get_ylabel()
    assert fig.axes[-1].get_xlabel() == "time (s)"


def test_a_welded_rig_says_it_cannot_pitch_and_draws_its_centre_of_mass(
    tmp_path: Path, figures: list[Any]
) -> None:
    leg = tmp_path / "rig.leg"
    leg.write_text(RIG, encoding="utf-8")
    gen, run = tmp_path / "gen", tmp_path / "run"
    assert main(["run", str(leg), "--time", "0.3", "--generated", str(gen), "--out", str(run)]) == 0
    assert main(["plot", str(run), "-o", str(tmp_path / "f.png")]) == 0
    rig = legdsl.load(leg, generated=gen)
    rig.run(time=0.3).plot(tmp_path / "api.png")  # Run.plot the same
    for fig in (figures[0], figures[-1]):
        height, pitch, speed, joints = fig.axes
        assert height.get_ylabel() == "centre-of-mass\nheight (m)"
        assert "centre-of-mass" in speed.get_ylabel()
        assert pitch.get_lines() == []  # no flat zeros
        said = " ".join(text.get_text() for text in pitch.texts)
        assert "root body 'base' is welded to the world" in said and "cannot" in said
        labels = [line.get_label() for line in joints.get_lines()]
        assert labels == ["sh_x", "sh_y", "sh_z", "el", "tw"]
        assert len(set(_styles(joints))) == 5


def test_a_free_creature_draws_its_pitch(tmp_path: Path, figures: list[Any]) -> None:
    free = RIG.replace("body base fixed at (0 m, 0 m, 0.8 m) {",
                       "body base free { initial x = 0 m, y = 0 m, z = 0.8 m")  # fmt: skip
    leg = tmp_path / "free.leg"
    leg.write_text(free, encoding="utf-8")
    run = tmp_path / "run"
    code = main(["run", str(leg), "--time", "0.2", "--generated", str(tmp_path / "gen"),
                 "--out", str(run)])  # fmt: skip
    assert code in (0, 4)  # no ground: it falls
    assert main(["plot", str(run), "-o", str(tmp_path / "f.png")]) == 0
    pitch = figures[0].axes[1]
    assert [line.get_label() for line in pitch.get_lines()] == ["pitch", "roll"]
    assert len(pitch.texts) == 0
