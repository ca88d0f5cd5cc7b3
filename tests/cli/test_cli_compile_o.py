"""`legdsl compile FILE -o DIR`: -o names the directory NAME/ is written under, as
--generated does (every other command takes -o for its output; compile refused it as an
unrecognized argument)."""

from __future__ import annotations

from pathlib import Path

from legdsl.cli import main

TINY = """
creature tiny {
  planar
  gravity 9.81 m/s^2
  body base free { mass 1 kg  inertia 0.01 kg*m^2 }
  contact foot on base
}
"""


def test_compile_takes_o_for_the_directory(tmp_path: Path) -> None:
    src = tmp_path / "tiny.leg"
    src.write_text(TINY, encoding="utf-8")
    out = tmp_path / "gen"
    assert main(["compile", str(src), "-o", str(out)]) == 0
    assert (out / "tiny" / "dynamics.py").is_file()
