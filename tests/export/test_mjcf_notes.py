"""An MJCF export says what of the ground it leaves out (before, it said nothing): MuJoCo has
no torsion spring at a contact, and ``--no-anchor-pads`` keeps only the tangent damper."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import CREATURES

from legdsl.cli import main


def _export(tmp_path: Path, name: str, *extra: str) -> int:
    out = tmp_path / f"{name}.xml"
    return main(
        ["export", str(CREATURES / f"{name}.leg"), "--format", "mjcf", "-o", str(out), *extra]
    )


def test_a_3d_creatures_torsion_spring_is_said_to_be_left_out(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert _export(tmp_path, "biped") == 0
    err = capsys.readouterr().err
    assert "legdsl: note: MuJoCo has no torsion spring at a contact" in err
    assert "biped.leg is not in the MJCF" in err
    assert "tangent spring" not in err  # the anchor pads carry it


def test_without_anchor_pads_the_tangent_spring_is_said_to_be_left_out(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert _export(tmp_path, "hopper", "--no-anchor-pads") == 0
    err = capsys.readouterr().err
    assert "--no-anchor-pads: the ground's tangent spring is not in the MJCF" in err
    assert "torsion" not in err  # a planar creature has none


def test_a_planar_creature_with_its_pads_gets_no_note(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert _export(tmp_path, "hopper") == 0
    assert "note" not in capsys.readouterr().err
