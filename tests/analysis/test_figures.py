"""Figures in tables and summaries: a creature scaled down to millimetres reads as a creature,
not as rows of 0.000; one of ordinary size reads as before."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from conftest import CREATURES

from legdsl.cli import main
from legdsl.figures import figure, figures


@pytest.mark.parametrize(
    ("x", "like", "shown"),
    [
        (0.0, None, "0.000"),
        (0.845, None, "0.845"),
        (-246.004, None, "-246.004"),
        (0.042, None, "0.042"),  # three decimals already give two significant digits
        (0.0052, None, "0.0052"),
        (0.000812, None, "0.00081"),
        (1.234e-10, None, "1.23e-10"),
        (1.007e10, None, "1.007e+10"),
        (float("nan"), None, "n/a"),
        (1.11e-16, 0.0052, "0.0000"),  # a spread to its value's decimals: rounding shows as 0
        (3e-27, 1.2e-10, "0"),
        (2e-11, 1.2e-10, "2e-11"),
    ],
)
def test_a_figure_keeps_two_significant_digits(x: float, like: float | None, shown: str) -> None:
    assert figure(x, like) == shown


def test_a_vector_is_shown_to_the_decimals_of_its_largest_component() -> None:
    assert figures((0.001, 1e-17, 0.002)) == "(0.0010, 0.0000, 0.0020)"
    assert figures([0.12, 0.0, 0.845]) == "(0.120, 0.000, 0.845)"


def test_a_hopper_of_a_millimetre_reports_its_figures(
    generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Scaled by Table 1 to L = 0.001, every length, time and energy of its summary and its
    metrics printed as 0.000 (its strides last 14 ms, its energy is a few 1e-10 J)."""
    out = tmp_path / "run"
    argv = ["run", str(CREATURES / "hopper.leg"), "--scale", "0.001", "--time", "0.3",
            "--generated", str(generated), "--out", str(out)]  # fmt: skip
    assert main(argv) == 0
    summary = capsys.readouterr().out
    energy = re.search(r"total energy start -> end\s+(\S+) J -> (\S+) J", summary)
    assert energy is not None and float(energy[1]) > 0 and float(energy[2]) > 0, summary
    position = re.search(r"final root position\s+\(([^)]*)\) m", summary)
    assert position is not None and float(position[1].split(", ")[-1]) > 0, summary
    assert main(["metrics", str(out)]) == 0
    table = capsys.readouterr().out
    for label in ("stride duration (s)", "apex height of the centre of mass (m)",
                  "elastic energy stored per stride (J)"):  # fmt: skip
        row = next(line for line in table.splitlines() if line.startswith(label))
        assert float(row[len(label) :].split()[0]) > 0, row


def test_the_top_views_title_says_laps_only_of_a_closed_path() -> None:
    """An open path's title said '0.66 laps' where the summary says '0.663 of its 15.000 m'."""
    from legdsl.analysis.plot import path_title

    report = {"lateral_rms": 0.0424, "lateral_max": 0.131, "from": 3.0, "laps": 0.663,
              "length": 15.0, "closed": False, "progress_from": 0.0}  # fmt: skip
    assert path_title("route", report) == (
        "route: lateral deviation 0.042 m RMS, 0.131 m max (from 3 s), 0.66 of its 15.000 m "
        "(from 0 s)"
    )
    tiny = report | {"closed": True, "lateral_rms": 0.00042, "progress_from": 3.0}
    assert path_title("loop", tiny).startswith("loop: lateral deviation 0.00042 m RMS")
    assert path_title("loop", tiny).endswith("0.66 laps (from 3 s)")  # one window: said once
