"""A creature whose numbers are each within a double but whose dynamics overflow one (a mass
times a length squared past 1.8e308) is refused at its body, not printed as ``inf``; and
refused by ``legdsl check`` alike, so that a file it accepts also compiles (it accepted this
one, which ``compile`` then refused)."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.cli import main
from legdsl.lang.errors import LegError
from legdsl.pipeline.compile import compile_model

LONG = """
creature longl {
  planar
  body t free { mass 1 kg  inertia 0.01 kg*m^2  initial x = 0 m, z = 1 m, pitch = 0 deg }
  body s on t via revolute hip { mass 1 kg  inertia 0.01 kg*m^2  length 1e200 m  com 0 m }
  body u on s via revolute knee at tip { mass 1 kg  inertia 0.01 kg*m^2 }
}
"""


def test_dynamics_past_a_double_are_refused_at_the_body(tmp_path: Path) -> None:
    leg = tmp_path / "longl.leg"
    leg.write_text(LONG, encoding="utf-8")
    with pytest.raises(LegError) as caught:
        compile_model(leg)  # was: dynamics.py and dynamics.c reading the undefined name inf
    (diagnostic,) = caught.value.diagnostics
    assert diagnostic.span.line == 5
    assert "past a double" in diagnostic.message and "legdsl scale" in diagnostic.message


def test_large_numbers_that_stay_finite_still_compile(tmp_path: Path) -> None:
    leg = tmp_path / "heavy.leg"
    leg.write_text(LONG.replace("1e200 m", "100 m").replace("1 kg", "1e6 kg"), encoding="utf-8")
    assert compile_model(leg).name == "longl"


@pytest.mark.parametrize("com", ["0 m", "0.2 m", "1e200 m"])
def test_legdsl_check_refuses_it_as_compile_does(
    tmp_path: Path, com: str, capsys: pytest.CaptureFixture[str]
) -> None:
    leg = tmp_path / "longl.leg"
    leg.write_text(LONG.replace("com 0 m", f"com {com}"), encoding="utf-8")
    assert main(["check", str(leg)]) == 2
    err = capsys.readouterr().err
    assert "longl.leg:5:3: error: creature 'longl' gives its dynamics numbers past a double" in err
    assert "Traceback" not in err
