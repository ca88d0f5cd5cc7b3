"""legdsl plot: the stance brackets and the picture of a run."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from conftest import CREATURES

from legdsl.analysis.plot import stance_phases
from legdsl.cli import main
from legdsl.sim.trajectory import empty


def _run(tmp_path: Path) -> Path:
    n = 1001
    tr = empty(
        n, 3, 3, 1, 1, q_names=("x", "z", "pitch"), v_names=("x", "z", "pitch"),
        contact_names=("toe",), leg_names=("main",), leg_feet=(0,), total_mass=1.0,
    )  # fmt: skip
    tr.t[:] = np.linspace(0.0, 1.0, n)
    phase = (tr.t % 0.25) / 0.25
    tr.contact[:, 0] = phase < 0.4  # stance 0.1 s of every 0.25 s, starting in stance
    tr.com[:, 2] = 0.5 + 0.05 * np.sin(2 * np.pi * 4 * tr.t)
    tr.save(tmp_path)
    (tmp_path / "run.json").write_text(
        json.dumps({"source": str(CREATURES / "kangaroo.leg"), "creature": "kangaroo"})
    )
    return tmp_path


def test_stance_phases_bracket_every_support(tmp_path: Path) -> None:
    from legdsl.sim.trajectory import Trajectory

    tr = Trajectory.load(_run(tmp_path))
    phases = stance_phases(tr, 0)
    assert len(phases) == 5
    assert phases[-1] == (1.0, 1.0)  # a stance that begins at the last sample ends with the run
    for k, (start, stop) in enumerate(phases[:-1]):
        assert start == pytest.approx(0.25 * k, abs=1e-3)
        assert stop - start == pytest.approx(0.1, abs=2e-3)


def test_plot_writes_a_png(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    run = _run(tmp_path)
    assert main(["plot", str(run)]) == 0
    png = run / "figure6.png"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert png.stat().st_size > 10_000
    assert main(["plot", str(tmp_path / "nothing")]) == 2


def test_footfall_bars_and_switch_times(tmp_path: Path) -> None:
    from legdsl.analysis.plot import footfall_bars, switch_times
    from legdsl.sim.trajectory import Trajectory

    run = _run(tmp_path)
    bars = footfall_bars(Trajectory.load(run))
    assert [name for name, _ in bars] == ["main"]
    stances = bars[0][1]
    assert len(stances) == 5 and stances[-1] == (1.0, 1.0)
    for k, (start, stop) in enumerate(stances[:-1]):
        assert start == pytest.approx(0.25 * k, abs=1e-3)
        assert stop - start == pytest.approx(0.1, abs=2e-3)
    assert switch_times(run) == []
    info = json.loads((run / "run.json").read_text())
    info["segments"] = [
        {"controller": "hop", "from": 0.0, "to": 0.5},
        {"controller": "bound", "from": 0.5, "to": 1.0},
    ]
    (run / "run.json").write_text(json.dumps(info))
    assert switch_times(run) == [(0.5, "bound")]


def test_plot_writes_the_footfall_diagram_beside_figure_6(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    run = _run(tmp_path)
    assert main(["plot", str(run), "--from", "0.2"]) == 0
    png = run / "footfall.png"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "footfall diagram" in capsys.readouterr().out
    other = tmp_path / "elsewhere" / "fig.png"
    assert main(["plot", str(run), "--output", str(other)]) == 0
    assert (other.parent / "fig-footfall.png").is_file()
    # a second run's pictures beside the first's overwrite none of them
    second = other.with_name("second.png")
    assert main(["plot", str(run), "--output", str(second), "--top"]) == 0
    assert (other.parent / "second-footfall.png").is_file()
    assert (other.parent / "second-top.png").is_file()
    assert (other.parent / "fig-footfall.png").is_file()


def test_a_window_without_samples_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """`plot --from 100` of a 1 s run wrote empty panels on axes matplotlib made up, exit 0."""
    run = _run(tmp_path)
    assert main(["plot", str(run), "--from", "100"]) == 2
    assert "--from 100s is after its last sample, at 1 s" in capsys.readouterr().err
    assert main(["plot", str(run), "--from", "0.1001", "--to", "0.1009"]) == 2
    assert "none lies from 0.1001 to 0.1009 s" in capsys.readouterr().err
    assert not (run / "figure6.png").exists() and not (run / "footfall.png").exists()


def test_a_window_of_one_sample_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A window holding one sample drew four empty panels on an axis of the stance around it
    (--from the last sample of a long run: 100 s past its end), exit 0: it is refused as an
    empty window is, with the record interval."""
    run = _run(tmp_path)
    assert main(["plot", str(run), "--from", "0.4999", "--to", "0.5009"]) == 2
    err = capsys.readouterr().err
    assert "only the sample at 0.5 s lies from 0.4999 to 0.5009 s" in err
    assert "widen the window: the run was recorded every 0.001 s" in err
    assert main(["plot", str(run), "--from", "0.9995"]) == 2
    assert "only the sample at 1 s lies from 0.9995 to 1 s" in capsys.readouterr().err
    assert not (run / "figure6.png").exists() and not (run / "footfall.png").exists()
    assert main(["plot", str(run), "--from", "0.998"]) == 0  # two samples: a curve


def test_a_run_of_one_sample_draws_without_warnings(tmp_path: Path) -> None:
    import warnings

    from legdsl.sim.trajectory import Trajectory

    tr = Trajectory.load(_run(tmp_path))
    tr.rows(0, 1).save(tmp_path / "one")
    (tmp_path / "one" / "run.json").write_text((tmp_path / "run.json").read_text())
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # matplotlib's "identical low and high xlims"
        assert main(["plot", str(tmp_path / "one")]) == 0


def test_a_command_near_the_largest_double_is_named_off_the_axis(tmp_path: Path) -> None:
    """A speed command of 1e308 m/s overflowed matplotlib's ticks (numpy's RuntimeWarnings
    leaked); one a million times the speeds drawn is named in the legend, not drawn."""
    import warnings

    from legdsl.analysis.plot import _command, pyplot

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fig, axes = pyplot().subplots()
        t = np.linspace(0.0, 1.0, 11)
        _command(axes, t, np.full(11, 1e308), np.full(11, 3.0))
        _command(axes, t, np.full(11, 2.0), np.full(11, 3.0))
        labels = [line.get_label() for line in axes.get_lines()]
        fig.savefig(tmp_path / "command.png")
    assert labels == ["command (up to 1e+308 m/s, off the axis)", "command"]
    assert len(axes.get_lines()[1].get_xdata()) == 11


def test_a_window_reaching_past_the_run_or_into_a_stance_draws_only_the_run_inside_it(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """--from 0.3 --to 5 of a 1 s run: the footfall axis ran to 5 s (the feet seemingly in
    the air from 1 s on) and Figure 6's to 0.25 s, where a stance begun before 0.3 s starts."""
    from matplotlib.figure import Figure

    limits: dict[str, tuple[float, float]] = {}

    def keep(fig: Figure, out: Path, **_kw: object) -> None:
        limits[Path(out).stem] = tuple(fig.axes[0].get_xlim())  # type: ignore[assignment]

    monkeypatch.setattr(Figure, "savefig", keep)
    run = _run(tmp_path)
    assert main(["plot", str(run), "--from", "0.3", "--to", "5"]) == 0, capsys.readouterr().err
    assert limits["figure6"] == pytest.approx((0.3, 1.0))
    assert limits["footfall"] == pytest.approx((0.3, 1.0))


def test_a_flip_s_pitch_is_drawn_as_the_turn_it_makes(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A planar creature's pitch is recorded in (-180, 180] degrees; a somersault is drawn as
    one climb to 360, not a jump from 180 to -180."""
    import matplotlib.figure

    from legdsl.sim.trajectory import Trajectory

    run = _run(tmp_path)
    tr = Trajectory.load(run)
    turned = np.linspace(0.0, 2 * np.pi, len(tr.t))
    tr.root_rpy[:, 1] = np.remainder(turned + np.pi, 2 * np.pi) - np.pi
    tr.save(run)
    drawn: list[matplotlib.figure.Figure] = []
    save = matplotlib.figure.Figure.savefig
    monkeypatch.setattr(
        matplotlib.figure.Figure,
        "savefig",
        lambda fig, *a, **k: (drawn.append(fig), save(fig, *a, **k)),
    )
    assert main(["plot", str(run)]) == 0
    pitch = drawn[0].axes[1].lines[0].get_ydata()
    assert np.all(np.diff(pitch) > 0) and pitch[-1] == pytest.approx(360.0)


def test_a_top_view_of_a_long_path_is_no_strip_and_its_words_fit(
    tmp_path: Path, generated: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A 100 m straight path drawn at true scale squashed the plot to a strip under a title
    that ran off the picture, with the legend over it: the plot is at least 2.5 inches tall,
    every title line fits, and the legend is under the axes."""
    import matplotlib.pyplot as plt

    from legdsl.analysis.plot import plot_top

    run = tmp_path / "run"
    argv = ["run", str(CREATURES / "biped.leg"), "--controller", "run", "--time", "0.3",
            "--path", "polyline((0, 0) m, (100, 0) m)", "--out", str(run),
            "--generated", str(generated)]  # fmt: skip
    assert main(argv) == 0
    figures: list = []
    monkeypatch.setattr(plt, "close", figures.append)
    plot_top(run, tmp_path / "top.png")
    (fig,) = figures
    ax = fig.axes[0]
    assert ax.get_position().height * fig.get_figheight() > 2.5
    assert all(len(line) <= 90 for line in ax.get_title().split("\n"))
    fig.canvas.draw()
    (legend,) = fig.legends  # the figure's, under the axes and their x label
    legend = legend.get_window_extent()
    assert legend.y1 <= ax.xaxis.label.get_window_extent().y0
    title = ax.title.get_window_extent()
    assert title.x0 >= 0 and title.x1 <= fig.bbox.width


def test_a_window_of_too_many_stances_leaves_their_lines_out_and_says_so(
    tmp_path: Path, generated: Path, monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:  # fmt: skip
    """A 30 min run's 2,390 dashed stance pairs were a grey wall over Figure 6, its footfall
    bars ran together, and nothing said to draw a window: past ``MOST_STANCES`` the lines
    are left out, the title says how many there were, and a note gives a window."""
    from legdsl.analysis import plot

    run = tmp_path / "run"
    argv = ["run", str(CREATURES / "hopper.leg"), "--controller", "hop", "--time", "3",
            "--out", str(run), "--generated", str(generated)]  # fmt: skip
    assert main(argv) == 0
    assert main(["plot", str(run)]) == 0
    assert "note" not in capsys.readouterr().err
    monkeypatch.setattr(plot, "MOST_STANCES", 3)
    assert main(["plot", str(run)]) == 0
    err = capsys.readouterr().err
    assert "stances of leg 'main' in 3 s: too many to tell apart" in err and "--from 0 --to" in err
    assert main(["plot", str(run), "--from", "2.5"]) == 0  # a window of a few: marked again
    assert "note" not in capsys.readouterr().err


def test_a_top_views_labels_are_inside_the_picture(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A tall quadruped's trot turning left from 3 s: its y (m) label was cut off at the left
    edge, tight_layout having measured the tick labels before the equal aspect widened the y
    limits to -0.5 (wider labels). Its track, from 0 to 4.9 m in x and -0.062 to 3.008 m in y."""
    import matplotlib.pyplot as plt

    from legdsl.analysis.plot import plot_top

    run = _run(tmp_path)
    from legdsl.sim.trajectory import Trajectory

    tr = Trajectory.load(run)
    track = np.array([(0.0, 0.0), (0.038, 0.0), (0.229, 0.0), (0.565, -0.016), (0.754, 0.017),
                      (1.202, -0.062), (1.487, 0.041), (2.171, 0.095), (2.911, 0.316),
                      (3.614, 0.794), (4.185, 1.412), (4.604, 2.082), (4.831, 2.834),
                      (4.899, 3.0076)])  # fmt: skip
    at = np.linspace(0, len(track) - 1, len(tr.t))
    for k in range(2):
        tr.com[:, k] = np.interp(at, np.arange(len(track)), track[:, k])
    tr.save(run)
    figures: list = []
    monkeypatch.setattr(plt, "close", figures.append)
    plot_top(run, tmp_path / "top.png")
    (fig,) = figures
    fig.canvas.draw()
    ax = fig.axes[0]
    for text in (ax.yaxis.label, ax.xaxis.label, ax.title, *fig.legends):
        box = text.get_window_extent()
        assert box.x0 >= 0 and box.y0 >= 0, (text, box)
        assert box.x1 <= fig.bbox.width and box.y1 <= fig.bbox.height, (text, box)
    drawn = ax.get_tightbbox()  # the tick labels drawn too
    assert drawn.x0 >= 0 and drawn.x1 <= fig.bbox.width, drawn


def test_the_pitch_panel_says_which_way_is_positive(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The docs read the plotted pitch as positive nose down; the panel said only 'body
    pitch (deg)'."""
    import matplotlib

    monkeypatch.setitem(matplotlib.rcParams, "svg.fonttype", "none")  # its text as text
    run = _run(tmp_path)
    assert main(["plot", str(run), "-o", str(tmp_path / "f.svg")]) == 0
    assert "+ nose down" in (tmp_path / "f.svg").read_text()
