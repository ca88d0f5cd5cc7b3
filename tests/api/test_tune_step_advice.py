"""A tune's runs take the file's step, as a sweep's do: a value too stiff for it was told "or a
step below 0.197 ms (--dt, or dt in the simulation block)", and `legdsl tune` has no --dt."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.cli import main

ROOT = Path(__file__).resolve().parents[2]


def test_a_tune_too_stiff_for_its_step_is_told_the_files_step(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    text = (ROOT / "creatures" / "hopper.leg").read_text(encoding="utf-8")
    stiff = text.replace("spring(k = 3000 N/m", "spring(k = 3e7 N/m")
    assert stiff != text
    (tmp_path / "hopper.leg").write_text(stiff, encoding="utf-8")
    code = main(["tune", str(tmp_path / "hopper.leg"), "--controller", "hop",
                 "--param", "kp=50:300", "--speeds", "0.5", "--time", "1", "--from", "0.5",
                 "--generations", "1", "--popsize", "2", "--jobs", "1",
                 "--out", str(tmp_path / "out"), "--generated", str(tmp_path / "gen")])  # fmt: skip
    err = capsys.readouterr().err
    assert code == 2, err
    assert "hopper.leg:39:3: error: actuator 'leg_spring' is too stiff" in err
    assert (
        "a step below 0.197 ms (dt in the file's simulation block; a sweep or a tune has no --dt)"
        in err
    )
    assert "--dt," not in err
