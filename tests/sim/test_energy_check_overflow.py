"""A run whose energy leaves the doubles (a hopper started 1e308 m up) is read by the energy
check without numpy's 'invalid value' warning, which printed legdsl's own source line to the
user (an outside user's). Such a start is refused at checking now (``check/magnitudes.py``:
its m g z is past a double), told at its line, still with no warning."""

from __future__ import annotations

import warnings
from pathlib import Path

import pytest

from legdsl.cli import main

ROOT = Path(__file__).resolve().parents[2]


def test_an_energy_past_doubles_gives_no_numpy_warning(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    text = (ROOT / "creatures" / "hopper.leg").read_text(encoding="utf-8")
    high = text.replace("initial x = 0 m, z = 0.95 m", "initial x = 0 m, z = 1e308 m")
    assert high != text
    (tmp_path / "high.leg").write_text(high, encoding="utf-8")
    argv = ["run", str(tmp_path / "high.leg"), "--time", "0.2", "--backend", "python",
            "--generated", str(tmp_path / "gen"), "--out", str(tmp_path / "run")]  # fmt: skip
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        assert main(argv) == 2
    err = capsys.readouterr().err
    assert "high.leg:" in err and "the initial z, 1e+308 m" in err and "past a double" in err
