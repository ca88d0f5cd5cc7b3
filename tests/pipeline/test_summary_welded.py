"""The run summary's mean speed of a creature welded to the world: n/a, as its metrics say.

Reported from outside: a 2 km arm swinging on a fixed base printed "mean speed along x, start
to end 0.370 m/s", while docs/metrics.md says such a rig goes nowhere (its energy per metre and
cost of transport n/a): its centre of mass sways with the arm."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.cli import main

ARM = """\
creature arm {
  planar
  body base fixed at (0 m, 2 m) { mass 1 kg  inertia 0.01 kg*m^2 }
  body arm on base via revolute swing {
    length 1 m  com 0.8 m  mass 2 kg  inertia 0.05 kg*m^2
    initial 30 deg
  }
}
"""
FREE = ARM.replace("body base fixed at (0 m, 2 m) {", "body base free { initial x = 0 m, z = 2 m")


def _speed_row(tmp_path: Path, name: str, text: str, capsys: pytest.CaptureFixture[str]) -> str:
    leg = tmp_path / f"{name}.leg"
    leg.write_text(text, encoding="utf-8")
    code = main(["run", str(leg), "--time", "0.3", "--generated", str(tmp_path / "gen"),
                 "--out", str(tmp_path / name)])  # fmt: skip
    assert code in (0, 4)  # the free one falls: no ground
    rows = [r for r in capsys.readouterr().out.splitlines() if "mean speed along x" in r]
    assert len(rows) == 1
    return rows[0].split("start to end", 1)[1].strip()


def test_a_welded_creatures_mean_speed_is_na(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert _speed_row(tmp_path, "welded", ARM, capsys) == "n/a (its root is welded to the world)"
    # a free one's is its centre of mass's, as before
    assert _speed_row(tmp_path, "free", FREE, capsys).endswith(" m/s")
