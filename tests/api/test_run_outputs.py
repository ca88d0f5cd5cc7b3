"""A run's pictures and player as a Python user asks for them: a directory or a misleading
name for ``path=`` is a ``UsageError`` (a directory was an IsADirectoryError, and a player
named ``run.mp4`` was written as HTML); a run whose directory was deleted is drawn into a
temporary one (``plot()`` said its run.json was missing); a series asked for by a number is a
``KeyError`` (it was a TypeError)."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

import legdsl
from legdsl.lang.errors import UsageError

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def run(generated: Path) -> legdsl.api.Run:
    return legdsl.load(ROOT / "creatures" / "hopper.leg", generated=generated).run(
        controller="hop", time=0.3
    )


@pytest.mark.parametrize(
    ("call", "name", "message"),
    [
        ("plot", "", "this is a directory; give a file name"),
        ("animate", "", "this is a directory; give a file name"),
        ("plot", "fig", "this writes a PNG, SVG or PDF; give a name ending in .png"),
        ("plot", "fig.jpg", "this writes a PNG, SVG or PDF; give a name ending in .png"),
        ("animate", "run.mp4", "the HTML player (a video: legdsl animate DIR --video FILE.mp4)"),
    ],
)
def test_a_path_that_is_a_directory_or_misnamed_is_refused(
    run: legdsl.api.Run, tmp_path: Path, call: str, name: str, message: str
) -> None:
    with pytest.raises(
        UsageError, match=f"^{call}\\(\\) .*{message.replace('(', '.').replace(')', '.')}"
    ):
        getattr(run, call)(path=tmp_path / name if name else tmp_path)
    assert (
        list(tmp_path.iterdir()) == [] and not (tmp_path.parent / f"{tmp_path.name}.png").exists()
    )


def test_plot_and_animate_write_the_names_asked_for(run: legdsl.api.Run, tmp_path: Path) -> None:
    assert run.plot(path=tmp_path / "a" / "fig.png").is_file()
    assert run.animate(path=tmp_path / "run.html").is_file()
    assert sorted(p.name for p in tmp_path.rglob("*")) == ["a", "fig.png", "run.html"]


def test_a_run_whose_directory_was_deleted_is_drawn_into_one_of_its_own(
    run: legdsl.api.Run, tmp_path: Path
) -> None:
    saved = run.save(tmp_path / "r")
    shutil.rmtree(saved)
    figure = run.plot()
    assert figure.is_file() and figure.parent != saved and not saved.exists()
    assert run.animate().parent == figure.parent  # its pictures alone, no copy of the run
    assert sorted(p.name for p in figure.parent.iterdir()) == ["animation.html", "figure6.png"]


def test_a_series_asked_for_by_a_number_is_a_key_error(run: legdsl.api.Run) -> None:
    with pytest.raises(KeyError, match="named by a text"):
        run[0]  # type: ignore[index]


def test_a_series_is_read_only_so_the_run_stays_as_recorded(run: legdsl.api.Run) -> None:
    """``t = run["t"]; t += 100`` shifted the run's own times (its plots, metrics, save)."""
    start, first_x = float(run["t"][0]), float(run["q.x"][0])
    for name in ("t", "q.x", "state", "energy.kinetic"):
        with pytest.raises(ValueError, match="read-only"):
            run[name][0] = 100.0
    assert float(run["t"][0]) == start and float(run["q.x"][0]) == first_x
    own = run._session_run.result.trajectory  # the session's, still its own to write
    assert own.t.flags.writeable and own.state.flags.writeable
    shifted = run["t"].copy()
    shifted += 1
    assert run.to_pandas().index[0] == start


def test_a_run_without_samples_is_told_so_by_what_would_show_it(
    run: legdsl.api.Run, tmp_path: Path
) -> None:
    """A copy stopped before its first sample (Ctrl-C in run_copies): animate() was an
    IndexError from inside the player, metrics() a table of NaN, plot() a message naming a
    temporary folder the user never made."""
    empty = legdsl.api.Run(
        run.model, run.trajectory.head(0), {**run.info, "status": "interrupted"}, run._dynamics
    )
    told = "this run of 'hopper' recorded no samples (it ended interrupted before its first)"
    for call in (empty.animate, empty.plot, empty.metrics):
        with pytest.raises(UsageError, match=rf"^{call.__name__}\(\): {re.escape(told)}"):
            call()
    # save() wrote a directory that open_run and legdsl metrics then refused
    with pytest.raises(UsageError, match=rf"^save\(\): {re.escape(told)}"):
        empty.save(tmp_path / "empty")
    assert list(tmp_path.iterdir()) == []
    assert repr(empty) == "<legdsl run of 'hopper': interrupted, 0 samples>"  # not "to nan s"


def test_the_run_s_trajectory_and_a_batch_s_arrays_are_read_only_too(generated: Path) -> None:
    """``run.trajectory.q[0, 0] = 7`` changed ``run['q.x'][0]`` (the samples api.md calls
    read-only views), and ``copies.status[0] = 'fell'`` stored 'fe' (the array's width was
    'ok''s), which ``repr(copies)`` then counted: each is a read-only view, also after pickle."""
    import pickle

    hopper = legdsl.load(ROOT / "creatures" / "hopper.leg", generated=generated)
    run = hopper.run(controller="hop", time=0.1)
    copies = hopper.run_copies(2, "hop", vary={"speed": ([1, 2], "m/s")}, time=0.1)
    arrived = pickle.loads(pickle.dumps(run))
    for tr in (run.trajectory, copies[0].trajectory, arrived.trajectory):
        for name in ("t", "q", "force", "state", "work_positive"):
            with pytest.raises(ValueError, match="read-only"):
                getattr(tr, name)[0] = 7
    for kept in (copies, pickle.loads(pickle.dumps(copies))):
        for name in ("status", "sim_time"):
            with pytest.raises(ValueError, match="read-only"):
                getattr(kept, name)[0] = "fell" if name == "status" else 7
        assert repr(kept).endswith("2 (ok 2)>")
    assert run["q.x"][0] == arrived["q.x"][0] and run.metrics().n_strides == 0
