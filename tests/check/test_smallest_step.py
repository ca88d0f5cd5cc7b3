"""The smallest step a file's 'dt' and a run's --dt take is the same, and the advice gives it."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.check.source import check_model
from legdsl.lang.errors import LegError
from legdsl.lang.scaling import COMPUTABLE_STEP

TEXT = """creature slider {
  planar
  body mass free { mass 1 kg  inertia 0.01 kg*m^2 }
  simulation { dt DT s }
}
"""


def test_the_step_advised_is_the_least_that_passes(tmp_path: Path) -> None:
    """A file's 'dt 1e-300 s' was told 'give 1e-09 s or more', though 1e-10 s passed (as
    --dt advised 1e-161 s, the least that does)."""
    path = tmp_path / "slider.leg"
    path.write_text(TEXT.replace("DT", f"{COMPUTABLE_STEP:g}"))
    assert check_model(path).name == "slider"
    path.write_text(TEXT.replace("DT", f"{COMPUTABLE_STEP / 10:g}"))
    with pytest.raises(LegError, match=f"give {COMPUTABLE_STEP:g} s or more"):
        check_model(path)
