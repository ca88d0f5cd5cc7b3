"""``Run.plot()`` draws from what the run holds, as ``metrics()`` and ``animate()`` do.

It saved the run to a directory and drew that: a run never saved left a whole copy of itself
(run.json, trajectory.csv, .npz: 146 MB for a 1500 s run) in a temporary directory, never
removed, even for a picture written to a path given; and once the run's ``.leg`` file was
edited, ``plot()`` was refused in the command line's words ('run it again (legdsl run h.leg
... --out runs/e1)') while ``metrics()`` and ``animate()`` of the same run still worked."""

from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

import pytest
from conftest import ROOT

import legdsl
from legdsl.analysis.plot import first_leg_angles, plot_run
from legdsl.api import LegdslWarning
from legdsl.lang.errors import UsageError


@pytest.fixture
def scratch(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """The system's temporary folder, for this test alone."""
    folder = tmp_path / "tmp"
    folder.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(folder))
    return folder


def test_a_run_never_saved_leaves_no_copy_of_itself(
    scratch: Path, tmp_path: Path, generated: Path
) -> None:
    hopper = legdsl.load(ROOT / "creatures" / "hopper.leg", generated=generated)
    run = hopper.run(controller="hop", time=0.5)
    assert run.plot(tmp_path / "fig.svg").is_file() and list(scratch.iterdir()) == []
    figure, player = run.plot(), run.animate()
    assert figure.parent == player.parent and figure.parent.parent == scratch
    assert sorted(p.name for p in scratch.rglob("*")) == [
        "animation.html", "figure6.png", figure.parent.name]  # fmt: skip
    assert run.directory is None


def test_the_picture_is_the_command_s_and_survives_an_edit_of_the_file(
    scratch: Path, tmp_path: Path, generated: Path
) -> None:
    source = tmp_path / "hopper.leg"
    for name in ("hopper.leg", "actions.leg"):  # on terrain: a step
        shutil.copy(ROOT / "tests" / "good" / name, tmp_path / name)
    hopper = legdsl.load(source, generated=generated)
    run = hopper.run(controller="hop", set={"speed": "1 m/s"}, time=2)
    saved = run.save(tmp_path / "r")
    cli = plot_run(saved, tmp_path / "cli.png", first_leg_angles(saved), 0.5)
    assert run.plot(tmp_path / "api.png", start=0.5).read_bytes() == cli.read_bytes()
    source.write_text(source.read_text().replace("height = 5 cm", "height = 6 cm"))
    with pytest.raises(UsageError, match="has changed since the run"):
        plot_run(saved, tmp_path / "again.png", first_leg_angles(saved))  # legdsl plot refuses
    assert run.plot(tmp_path / "edited.png", start=0.5).read_bytes() == cli.read_bytes()
    assert run.plot() == saved / "figure6.png"
    assert run.status == "fell"  # off the step: measured up to its last touchdown before then
    with pytest.warns(LegdslWarning, match=r"did not end ok \(fell at t = 1.93 s"):
        measured = run.metrics()
    assert measured.status == "fell" and 0 < measured.t_to < run["t"][-1]
    assert list(scratch.iterdir()) == []


def test_a_window_past_the_end_is_told_in_the_call_s_words(generated: Path) -> None:
    run = legdsl.load(ROOT / "creatures" / "hopper.leg", generated=generated).run(
        controller="hop", time=0.2
    )
    with pytest.raises(UsageError, match=r"^plot\(\): nothing of this run to draw: start=1 s is "
                                         r"after its last sample, at .* s; give a start within"):  # fmt: skip
        run.plot(start=1)


def test_a_fallen_run_s_picture_says_so_as_the_command_s_does(
    tmp_path: Path, generated: Path
) -> None:
    """legdsl plot titles a run that fell with how it ended and marks the end; Run.plot drew
    the same run as if it had ended ok."""
    hopper = legdsl.load(ROOT / "creatures" / "hopper.leg", generated=generated)
    run = hopper.run(controller="hop", set={"speed": "1 m/s"}, time=3, fall_tilt="5 deg")
    assert run.status == "fell"
    saved = run.save(tmp_path / "r")
    svg = plot_run(saved, tmp_path / "cli.svg", first_leg_angles(saved))
    assert b"fell at" in svg.read_bytes()
    cli = plot_run(saved, tmp_path / "cli.png", first_leg_angles(saved))
    assert run.plot(tmp_path / "api.png").read_bytes() == cli.read_bytes()
