"""legdsl plot of a run that did not end ok, its legends, and its two time axes.

``plot`` never said a run fell, diverged or was interrupted (its titles and standard error
were silent where ``animate`` notes it); each panel's legend sat at its lower right, over
the curves; and with a window inside the run, Figure 6's axis ended at the last sample in
it while the footfall diagram's ended at --to.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from conftest import CREATURES

from legdsl.cli import main
from legdsl.sim.trajectory import empty

STEP = 0.0042  # s between samples: --to 0.3 falls between two


def _run(tmp_path: Path, status: dict[str, Any]) -> Path:
    n = 113  # the last sample at 0.4704 s
    tr = empty(
        n, 3, 3, 1, 1, q_names=("x", "z", "pitch"), v_names=("x", "z", "pitch"),
        contact_names=("toe",), leg_names=("main",), leg_feet=(0,), total_mass=1.0,
    )  # fmt: skip
    tr.t[:] = np.arange(n) * STEP
    tr.contact[:, 0] = (tr.t % 0.25) / 0.25 < 0.4
    tr.com[:, 2] = 0.5 + 0.05 * np.sin(2 * np.pi * 4 * tr.t)
    tr.com_vel[:, 0] = 1.0 + 0.5 * np.sin(2 * np.pi * 3 * tr.t)  # dips at the lower right too
    tr.q[:, 2] = -0.3 + 0.3 * np.sin(2 * np.pi * 4 * tr.t)
    tr.speed_command[:] = 1.0
    tr.save(tmp_path)
    info = {"source": str(CREATURES / "kangaroo.leg"), "creature": "kangaroo", **status}
    (tmp_path / "run.json").write_text(json.dumps(info))
    return tmp_path


@pytest.fixture
def figures(monkeypatch: pytest.MonkeyPatch) -> list[Any]:
    import matplotlib.pyplot as plt

    drawn: list[Any] = []
    close = plt.close
    monkeypatch.setattr(plt, "close", lambda fig: (drawn.append(fig), close(fig)))
    return drawn


FELL = {"status": "fell", "ended_at": 0.4704, "cause": "the root fell to 0.1 m above the ground"}


def test_a_run_that_fell_is_told_on_stderr_and_in_each_picture(
    tmp_path: Path, figures: list[Any], capsys: pytest.CaptureFixture[str]
) -> None:
    run = _run(tmp_path / "run", FELL)
    assert main(["plot", str(run), "-o", str(tmp_path / "f.png")]) == 0
    err = capsys.readouterr().err
    assert f"note: the run in {run} did not end ok (fell at t = 0.4704 s: the root fell" in err
    figure6, footfall = figures
    assert figure6._suptitle.get_text().startswith("fell at 0.4704 s: the root fell")
    assert footfall.axes[0].get_title().startswith("fell at 0.4704 s: the root fell")
    for ax in (*figure6.axes, footfall.axes[0]):  # a vertical line where it ended
        ends = [line for line in ax.lines if list(line.get_xdata()) == [0.4704, 0.4704]]
        assert ends, ax
        assert ax.get_xlim()[1] == pytest.approx(0.4704)


def test_a_run_that_ended_ok_says_nothing_of_it(
    tmp_path: Path, figures: list[Any], capsys: pytest.CaptureFixture[str]
) -> None:
    run = _run(tmp_path / "run", {"status": "ok"})
    assert main(["plot", str(run), "-o", str(tmp_path / "f.png")]) == 0
    assert "did not end ok" not in capsys.readouterr().err
    assert not figures[0]._suptitle.get_text().startswith("ok")


def test_legends_hide_no_curve(tmp_path: Path, figures: list[Any]) -> None:
    run = _run(tmp_path / "run", {"status": "ok"})
    assert main(["plot", str(run), "-o", str(tmp_path / "f.png")]) == 0
    fig = figures[0]
    fig.canvas.draw()
    legends = [ax.get_legend() for ax in fig.axes if ax.get_legend() is not None]
    assert legends
    for ax in fig.axes:
        box = ax.get_window_extent()
        for legend in legends:
            seen = legend.get_window_extent()
            assert seen.x0 >= box.x1 or seen.x1 <= box.x0 or seen.y0 >= box.y1 or seen.y1 <= box.y0


def test_figure6_and_the_footfall_share_a_window_s_time_axis(
    tmp_path: Path, figures: list[Any]
) -> None:
    run = _run(tmp_path / "run", {"status": "ok"})
    argv = ["plot", str(run), "-o", str(tmp_path / "f.png"), "--from", "0.1", "--to", "0.3"]
    assert main(argv) == 0
    figure6, footfall = figures
    assert figure6.axes[0].get_xlim() == pytest.approx(footfall.axes[0].get_xlim())
    assert figure6.axes[0].get_xlim()[1] == pytest.approx(71 * STEP)  # the last sample in it


def test_a_tiny_creature_s_axes_are_in_mm_um_and_ms(tmp_path: Path, figures: list[Any]) -> None:
    """A hopper scaled by 0.0001 was drawn in m and s: '1e-5' over its height ticks, time
    ticks of 0.01025 s."""
    from legdsl.sim.trajectory import Trajectory

    run = _run(tmp_path / "run", {"status": "ok"})
    tr = Trajectory.load(run)
    tr.t[:] *= 0.05
    tr.com[:, 2] *= 2e-4
    tr.com_vel[:] *= 0.01
    tr.speed_command[:] *= 0.01
    tr.save(run)
    assert main(["plot", str(run), "-o", str(tmp_path / "f.png")]) == 0
    figure6, footfall = figures
    figure6.canvas.draw()
    height, _, speed, joints = figure6.axes[:4]
    assert height.get_ylabel() == "centre-of-mass\nheight (\u00b5m)"
    assert speed.get_ylabel() == "centre-of-mass\nforward speed (mm/s)"
    assert joints.get_xlabel() == "time (ms)" and footfall.axes[0].get_xlabel() == "time (ms)"
    ticks = [t.get_text() for t in height.get_yticklabels() if t.get_text()]
    assert all(80 <= float(t) <= 120 for t in ticks), ticks  # 0.09 to 0.11 mm
    assert not height.yaxis.get_offset_text().get_text()


LONG = {  # an energy rise's cause, told whole on standard error and shortened in the titles
    "status": "diverged",
    "ended_at": 0.4704,
    "diverged_at": 0.3432,
    "cause": "the total energy rose from 171.3 J at t = 0.3380 s to 5.269e+04 J at t = 0.3432 s "
    "(one sample later) with only 0.0438 J of actuator work between, and nothing else in a "
    "creature adds energy. Likely cause: the step 0.4 ms is too large for the contact stiffness",
}


def test_a_long_title_fits_in_a_footfall_diagram_of_one_row(
    tmp_path: Path, figures: list[Any], recwarn: pytest.WarningsRecorder
) -> None:
    """Its 1.35 in had no room for the lines saying how the run diverged: "Tight layout not
    applied" on standard error and the title cut off at the picture's top."""
    run = _run(tmp_path / "run", LONG)
    assert main(["plot", str(run), "-o", str(tmp_path / "f.png")]) == 0
    assert not [w for w in recwarn if "layout" in str(w.message)]
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    for fig in figures:
        renderer = FigureCanvasAgg(fig).get_renderer()  # closed: its canvas is gone
        titles = [ax.title for ax in fig.axes] + ([fig._suptitle] if fig._suptitle else [])
        drawn = [t for t in titles if t.get_text()]
        assert drawn[-1].get_text().startswith("diverged at 0.3432 s: the total energy")
        for title in drawn:
            box = title.get_window_extent(renderer)
            assert box.y0 >= 0 and box.y1 <= fig.bbox.y1, (title.get_text(), box, fig.bbox)
