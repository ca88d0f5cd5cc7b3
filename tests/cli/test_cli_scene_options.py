"""Options beside a scene: `--controller` may repeat the controller a gait table starts with
(docs/language.md, "Scenes"), with a note that the scene still changes controllers; the
message for another names that one; the notes on the scene's
lines that come after the run's end name those lines as written."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from legdsl.cli import main

BIPED = Path(__file__).resolve().parents[2] / "creatures" / "biped.leg"


def test_controller_may_repeat_the_gait_tables_first_band(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "run"
    args = ["run", str(BIPED), "--scene", "by_speed", "--time", "0.01", "--out", str(out)]
    assert main([*args, "--controller", "gallop"]) == 0  # 1.5 m/s: the gallop's band
    assert json.loads((out / "run.json").read_text())["controller"] == "gallop"
    # the gait table still switches: said, as it was not (the run seemed all gallop)
    assert (
        "note: --controller gallop repeats the controller --scene by_speed starts with (its gait "
        "table's band for the first command); the scene still changes controllers (run at 6.0 s, "
        "gallop at 18.0 s): --controller chooses only the first"
    ) in capsys.readouterr().err
    # 2 m/s first: only the run's band holds it, so the run starts, whatever the scene's order
    assert main([*args, "--set", "speed=2m/s", "--controller", "gallop"]) == 2
    err = capsys.readouterr().err
    assert "starts with controller run" in err and "leave out --controller" in err


def test_notes_name_the_scenes_lines_after_the_end_where_they_are_written(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    argv = ["run", str(BIPED), "--scene", "run_gallop_run", "--time", "0.01"]
    assert main([*argv, "--set", "speed=1m/s@9s", "--out", str(tmp_path)]) == 0
    err = capsys.readouterr().err
    line = next(n for n, text in enumerate(BIPED.read_text().splitlines(), 1)
                if "at 8 s set speed" in text)  # fmt: skip
    assert f"biped.leg:{line}:" in err and "'at 8 s set speed' of scene run_gallop_run" in err
    assert "--set speed=1.5m/s@8.0s" not in err  # the text it stands for, never written
    assert "--set speed=1m/s@9s comes after the run's end" in err  # the command line's own


def test_a_switch_beside_a_gait_table_says_what_to_do_instead(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    argv = ["run", str(BIPED), "--scene", "by_speed", "--switch", "1s=run", "--out", str(tmp_path)]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "chooses its controllers by its gait table; leave out --switch" in err
