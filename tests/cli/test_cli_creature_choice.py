"""A file with several creatures: the commands that take one ask which, naming them all,
as a mistake of the whole file (no line of it is shown with a caret)."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.cli import main

TWO = """\
# Two creatures in one file.
creature ball {
  spatial
  body ball free { mass 1 kg  inertia (0.004, 0.004, 0.004) kg*m^2  initial z = 1 m }
}
creature cube {
  spatial
  body cube free { mass 2 kg  inertia (0.01, 0.01, 0.01) kg*m^2  initial z = 1 m }
}
"""


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        ([], "choose a creature with --creature (creature= in Python): this file has ball, cube"),
        (["--creature", "cub"], "there is no creature 'cub': this file has ball, cube"),
    ],
)
def test_show_asks_which_creature(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], extra: list[str], message: str
) -> None:
    leg = tmp_path / "two.leg"
    leg.write_text(TWO)
    assert main(["show", str(leg), *extra]) == 2
    assert capsys.readouterr().err == f"{leg}: error: {message}\n"
    assert main(["show", str(leg), "--creature", "cube"]) == 0
