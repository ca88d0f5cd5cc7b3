"""legdsl plot on terrain: the height panel is world z, so it draws the ground under the centre
of mass beside the body (on a slope down, the body's height alone reads as a creature sinking)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from conftest import CREATURES

from legdsl.analysis.plot import ground_under_com, plot_run
from legdsl.analysis.recorded import model_if_readable
from legdsl.sim.trajectory import Trajectory, empty

HOPPER = CREATURES / "hopper.leg"


def _run(tmp_path: Path, terrain: str, **info: object) -> Path:
    text = HOPPER.read_text()
    assert "    friction none\n  }" in text
    source = tmp_path / "hopper.leg"
    if terrain:
        text = text.replace("    friction none\n  }", f"    friction none\n    {terrain}\n  }}", 1)
    source.write_text(text)
    n = 201
    tr = empty(
        n, 3, 3, 1, 1, q_names=("x", "z", "pitch"), v_names=("x", "z", "pitch"),
        contact_names=("toe",), leg_names=("main",), leg_feet=(0,), total_mass=1.0,
    )  # fmt: skip
    tr.t[:] = np.linspace(0.0, 2.0, n)
    tr.com[:, 0] = tr.t * 1.5  # from x = 0 to 3 m
    tr.com[:, 2] = 0.9
    out = tmp_path / "run"
    tr.save(out)
    (out / "run.json").write_text(json.dumps({"source": str(source), "creature": "hopper", **info}))
    return out


@pytest.mark.parametrize(
    ("terrain", "expected"),
    [
        ("terrain slope(angle = -10 deg)", lambda x: x * math.tan(math.radians(-10))),
        ("terrain step(x = 2 m, height = 5 cm)", lambda x: np.where(x >= 2.0, 0.05, 0.0)),
    ],
)
def test_the_ground_under_the_centre_of_mass_follows_the_terrain(
    tmp_path: Path, terrain: str, expected: object
) -> None:
    run = _run(tmp_path, terrain)
    tr = Trajectory.load(run)
    ground = ground_under_com(run, tr, model_if_readable(run))
    assert ground is not None
    assert ground == pytest.approx(expected(tr.com[:, 0]))  # type: ignore[operator]


def test_a_scaled_run_stands_over_the_scaled_terrain(tmp_path: Path) -> None:
    # legdsl run --scale 2 records the creature twice as large: its step is at 4 m, 10 cm high
    run = _run(tmp_path, "terrain step(x = 2 m, height = 5 cm)", scale=2.0)
    tr = Trajectory.load(run)
    ground = ground_under_com(run, tr, model_if_readable(run))
    assert ground is not None
    assert ground == pytest.approx(np.where(tr.com[:, 0] >= 4.0, 0.1, 0.0))


def test_a_flat_floor_draws_no_ground_line(tmp_path: Path) -> None:
    run = _run(tmp_path, "")
    assert ground_under_com(run, Trajectory.load(run), model_if_readable(run)) is None


def test_the_height_panel_draws_the_ground_on_a_slope(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from matplotlib.axes import Axes

    drawn: list[tuple[str, np.ndarray]] = []
    plot = Axes.plot

    def recording(self: Axes, *args: object, **kwargs: object) -> object:
        drawn.append((str(kwargs.get("label", "")), np.asarray(args[1])))
        return plot(self, *args, **kwargs)

    monkeypatch.setattr(Axes, "plot", recording)
    run = _run(tmp_path, "terrain slope(angle = -10 deg)")
    plot_run(run, tmp_path / "fig.png")
    ground = [y for label, y in drawn if label == "ground under com"]
    assert len(ground) == 1
    assert ground[0][-1] == pytest.approx(3.0 * math.tan(math.radians(-10)))
