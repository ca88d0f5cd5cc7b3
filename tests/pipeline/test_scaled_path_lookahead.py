"""A path's default lookahead (1 m) is a length of a creature of about a metre: under
``--scale L`` a ``--path`` given without one gets L m, the scaled creature's, so the run is the
original's on the original's path, scaled (it kept 1 m: the quadruped 4 times as large, on a
20 m circle, ran 1.24 m off it where the original's image is 0.24 m). ``legdsl scale`` writes
the scaled default into the paths it can (a shared part's too) and says what it cannot carry:
a ``--path`` given to the scaled file, and the standard library's numbers (its ``1 ms``)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from conftest import CREATURES

from legdsl.cli import main
from legdsl.ir.paths import PathSpec
from legdsl.pipeline.path_option import parse_path_option
from legdsl.pipeline.scaled import scale_path
from legdsl.sim.trajectory import Trajectory

SMALL = "circle(center = (0, 1.5) m, radius = 1.5 m, turn = left)"
BIG = "circle(center = (0, 6) m, radius = 6 m, turn = left)"  # SMALL at L = 4


def test_a_path_without_a_lookahead_takes_the_scaled_creatures_default(tmp_path: Path) -> None:
    given = parse_path_option(BIG)
    assert given.lookahead_default and given.lookahead == 1.0
    model = scale_path(given, 4.0)
    assert (model.radius, model.lookahead, model.lookahead_default) == (1.5, 1.0, False)
    # brought back for the scaled creature (run.json's paths): its lookahead is 4 m
    back = scale_path(model, 0.25)
    assert back.lookahead == 4.0 and "lookahead = 4 m" in back.describe()
    # one written is the user's: scaled as every length
    written = parse_path_option(BIG[:-1] + ", lookahead = 2 m)")
    assert not written.lookahead_default
    assert scale_path(written, 4.0).lookahead == 0.5
    # a waypoints file has no lookahead: the default, scaled
    route = tmp_path / "route.csv"
    route.write_text("0,0\n8,0\n8,8\n", encoding="utf-8")
    assert scale_path(parse_path_option(str(route)), 4.0).lookahead == 1.0
    # a PathSpec made in Python says its own lookahead
    assert scale_path(PathSpec("route", "circle", radius=6.0), 4.0).lookahead == 0.25


def test_a_scale_run_on_the_scaled_path_is_the_originals_run_scaled(
    generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """L = 4: every factor a power of two, so the --scale run is the original's exactly."""
    biped = str(CREATURES / "biped.leg")
    common = ["--controller", "run", "--generated", str(generated), "--backend", "python"]
    assert main(["run", biped, *common, "--path", SMALL, "--time", "0.6",
                 "--out", str(tmp_path / "a")]) == 0  # fmt: skip
    assert main(["run", biped, *common, "--path", BIG, "--time", "1.2", "--scale", "4",
                 "--out", str(tmp_path / "b")]) == 0  # fmt: skip
    capsys.readouterr()
    a, b = Trajectory.load(tmp_path / "a"), Trajectory.load(tmp_path / "b")
    assert len(a.t) == len(b.t) > 10
    assert np.array_equal(a.t * 2, b.t)
    assert np.array_equal(a.com * 4, b.com)
    assert np.array_equal(a.com_vel * 2, b.com_vel)
    assert np.array_equal(a.root_pos * 4, b.root_pos)


def test_legdsl_scale_says_what_a_path_and_the_library_keep_unscaled(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "q.leg"
    assert main(["scale", str(CREATURES / "quadruped.leg"), "--by", "0.01", "-o", str(out)]) == 0
    notes = [line for line in capsys.readouterr().err.splitlines() if "note:" in line]
    (library,) = [n for n in notes if "standard library" in n]
    assert "1 ms in ramp_speed (stdlib/raibert.leg:301; scaled, 0.1 ms)" in library
    assert "--scale 0.01 is the original's run scaled" in library
    (look,) = [n for n in notes if "lookahead" in n]
    assert "follows 1 m ahead" in look and "'lookahead = 0.01 m'" in look
    text = out.read_text(encoding="utf-8")
    assert "  path route  # a --path without a lookahead follows 1 m ahead" in text
    assert "give it 'lookahead = 0.01 m' (scaled by 0.01)" in text
    # the biped calls none of the library's timed actions, and scaled by 1 nothing changes
    for creature, by in (("biped", "2"), ("quadruped", "1")):
        assert main(["scale", str(CREATURES / f"{creature}.leg"), "--by", by,
                     "-o", str(tmp_path / f"{creature}.leg")]) == 0  # fmt: skip
        assert "standard library" not in capsys.readouterr().err


def test_a_shared_parts_path_gets_its_lookahead_scaled(tmp_path: Path) -> None:
    """Only a controller's own paths got the default lookahead written: one of a shared part
    kept 1 m in the scaled file."""
    from legdsl.check.source import check_file
    from legdsl.lang.scaling import scale_source

    text = (CREATURES / "biped.leg").read_text(encoding="utf-8")
    text = text.replace("  path route\n", "  include routes\n", 1) + (
        "\nshared routes {\n  path route = circle(center = (0, 5) m, radius = 5 m, turn = left)\n}\n"
    )
    out = tmp_path / "biped_x2.leg"
    out.write_text(scale_source(text, 2.0), encoding="utf-8")
    (big,) = check_file(out)
    (path,) = big.controller("run").paths
    assert (path.radius, path.lookahead) == (10.0, 2.0)
    assert math.isclose(path.center[1], 10.0)


def test_the_lookahead_note_under_scale_speaks_of_the_scaled_creatures_default(
    generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The note on a lookahead too long for a path's turns was worked out on the path as given
    with 1 m, before --scale: a biped 4 times as large followed 4 m ahead on a 2 m circle,
    unnoted."""
    biped = str(CREATURES / "biped.leg")
    assert main(["run", biped, "--controller", "run", "--generated", str(generated),
                 "--backend", "python", "--path", "circle(center = (0, 2) m, radius = 2 m)",
                 "--scale", "4", "--time", "0.01", "--out", str(tmp_path / "r")]) == 0  # fmt: skip
    assert "its lookahead (4 m) is longer than its radius (2 m)" in capsys.readouterr().err
