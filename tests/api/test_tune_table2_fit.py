"""legdsl tune --table2 with a row whose pairs the creature has not: a usage error naming the
rows that fit it (it was an internal error, MetricsError, exit 70, advising metrics' --group)."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.cli import main

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize(
    ("creature", "controller", "row"),
    [("hopper.leg", "hop", "quadruped trot"), ("biped.leg", "run", "quadruped bound")],
)
def test_a_row_of_pairs_the_creature_has_not_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], creature: str, controller: str, row: str
) -> None:
    out = tmp_path / "t"
    code = main([
        "tune", str(ROOT / "creatures" / creature), "--controller", controller,
        "--param", "kp=20:300", "--speeds", "1,2", "--generations", "1", "--table2", row,
        "--out", str(out), "--generated", str(tmp_path / "generated"),
    ])  # fmt: skip
    err = capsys.readouterr().err
    assert code == 2, err
    assert "internal error" not in err and "--group" not in err
    assert f"--table2 '{row}'" in err and "leg" in err
    assert "give a row that fits it ('biped run', 'kangaroo hop')" in err
    assert not out.exists()  # refused before --out was made
