"""An outside user's smaller findings: ``Quantity(np.array(1.5), 'm/s')`` was refused while
the run options take a 0-d array; ``f"{Quantity(2, 'm'):d}"`` raised float's ValueError
from inside quantity.py; and ``run_copies(progress=lambda: None)`` was a bare TypeError from
the batch, mid-run."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import legdsl
from legdsl.api import Quantity
from legdsl.lang.errors import UsageError

HOPPER = Path(__file__).resolve().parents[2] / "creatures" / "hopper.leg"


def test_a_0d_array_is_a_number() -> None:
    assert Quantity(np.array(1.5), "m/s") == Quantity(1.5, "m/s")
    assert Quantity(np.array(2), (0, 1, 0, 0)).value == 2.0
    for refused in (np.array(True), np.array([1.0]), np.array(1 + 1j)):
        with pytest.raises(UsageError, match="the value is a number"):
            Quantity(refused, "m")


def test_a_format_spec_formats_the_number_or_is_refused() -> None:
    assert f"{Quantity(2, 'm'):d}" == "2 m" and f"{Quantity(2, 'm'):>3d}" == "  2 m"
    assert f"{Quantity(2.5, 'm'):.2f}" == "2.50 m"
    with pytest.raises(UsageError, match="'d' formats whole numbers, and 2.5 is not one"):
        f"{Quantity(2.5, 'm'):d}"
    with pytest.raises(UsageError, match="'q' is no format for a number"):
        f"{Quantity(2.5, 'm'):q}"


@pytest.mark.usefixtures("hopper_modules")
@pytest.mark.parametrize("progress", [lambda: None, lambda done, n: None])
def test_a_progress_that_takes_other_arguments_is_refused_first(
    tmp_path: Path, progress: object
) -> None:
    creature = legdsl.load(str(HOPPER), generated=str(tmp_path / "generated"))
    with pytest.raises(UsageError, match=r"progress= is called with three arguments, \(done, n, "
                       r"seconds_left\)"):  # fmt: skip
        creature.run_copies(2, "hop", time=0.05, progress=progress)
    seen: list[tuple] = []
    creature.run_copies(2, "hop", time=0.05, progress=lambda *a: seen.append(a))
