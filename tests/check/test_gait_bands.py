"""What a gait table can never do, told at check time with its fix: a band no command can
choose (the bands before it hold all its speeds), a band written high to low, a command no
band holds (check/gait_bands.py)."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.check.source import check_model
from legdsl.lang.errors import LegError

ROOT = Path(__file__).resolve().parents[2]
BIPED = ROOT / "creatures" / "biped.leg"


def _errors(tmp_path: Path, scene: str) -> str:
    path = tmp_path / "biped.leg"
    path.write_text(BIPED.read_text() + scene)
    with pytest.raises(LegError) as err:
        check_model(path)
    return err.value.render()


def test_an_open_band_before_another_shadows_it(tmp_path: Path) -> None:
    """'gait by speed { run; gallop from 3 m/s }' passed check, and the run kept running at 4
    m/s: the current band is kept while it holds the command, and run's holds every speed."""
    text = _errors(
        tmp_path,
        "scene shadow {\n  gait by speed { run; gallop from 3 m/s }\n  set speed = 1 m/s\n"
        "  at 3 s set speed = 4 m/s\n}\n",
    )
    line = BIPED.read_text().count("\n") + 2
    assert (
        f"biped.leg:{line}:24: error: no command of speed ever chooses gallop: the bands before "
        f"it (run, line {line}) hold every speed its band holds, and a command goes to the "
        "current band while it holds it, else to the first band that holds it; give the band "
        "before it an end at gallop's ('run to 3 m/s'; an end inside gallop's band overlaps "
        "it, a hysteresis)\n"
        "      gait by speed { run; gallop from 3 m/s }\n"
        "                           ^~~~~~~~~~~~~~~~~"
    ) in text, text


def test_a_band_within_several_before_it_is_never_chosen(tmp_path: Path) -> None:
    text = _errors(
        tmp_path,
        "scene s {\n  gait by speed { run to 2 m/s; run from 2 m/s; gallop from 1 m/s to 3 m/s }\n"
        "  set speed = 3.5 m/s\n}\n",
    )
    assert (
        "no command of speed ever chooses gallop: the bands before it (run to 2 m/s, line" in text
    )
    assert (
        "give the bands before it an end at gallop's ('run to 1 m/s' and 'run from 3 m/s';" in text
    )


def test_bands_that_leave_each_a_speed_pass(tmp_path: Path) -> None:
    """gallop's band within run's first and third is the hysteresis of run's: run is chosen."""
    path = tmp_path / "biped.leg"
    for table in ("run to 3 m/s; gallop from 3 m/s", "run to 3.5 m/s; gallop from 3 m/s",
                  "gallop from 3 m/s; run", "run to 2 m/s; gallop from 1.5 m/s; run from 2.5 m/s",
                  "gallop to 2 m/s; run from 1.5 m/s; gallop from 2.5 m/s; run from 3 m/s"):  # fmt: skip
        path.write_text(BIPED.read_text() + f"scene s {{ gait by speed {{ {table} }} }}\n")
        assert check_model(path).scene("s").bands


def test_a_controller_line_starts_a_shadowed_band(tmp_path: Path) -> None:
    """The scene's 'controller' line picks among the bands that hold the first command."""
    path = tmp_path / "biped.leg"
    path.write_text(BIPED.read_text() + "scene s { gait by speed { run; gallop from 3 m/s }; "
                    "controller gallop; set speed = 4 m/s }\n")  # fmt: skip
    assert check_model(path).scene("s").controller == "gallop"


def test_a_reversed_band_says_how_to_write_it(tmp_path: Path) -> None:
    text = _errors(tmp_path, "scene s {\n  gait by speed { run from 2 m/s to 1 m/s; gallop }\n}\n")
    assert (
        "error: a band runs from a lower speed to a higher one: write 'run from 1 m/s to 2 m/s'"
    ) in text, text


def test_a_command_no_band_holds_says_how_to_have_one_hold_it(tmp_path: Path) -> None:
    text = _errors(
        tmp_path,
        "scene gap {\n  gait by speed { gallop to 1.6 m/s; run from 3 m/s }\n"
        "  set speed = 1.2 m/s\n  at 4 s set speed = 2.5 m/s\n}\n",
    )
    assert (
        "no band of 'gait by speed' holds speed = 2.5 m/s (bands: gallop to 1.6 m/s; run from "
        "3 m/s): widen a band to hold it ('gallop to 2.5 m/s' or 'run from 2.5 m/s'), add a "
        "band that holds it, or give a command within the bands"
    ) in text, text
