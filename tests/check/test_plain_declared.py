"""An input or parameter declared without its unit is told at its declaration, once, however
many statements or action calls use it as a quantity (it was told at each use, advising a
unit on the name)."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.check.source import check_file
from legdsl.lang.errors import LegError

HOPPER = Path(__file__).resolve().parents[2] / "creatures" / "hopper.leg"
KP = "  param kp = 150 N*m/rad       # eq. (4)\n"


def test_a_parameter_given_to_library_actions_without_its_unit(tmp_path: Path) -> None:
    text = HOPPER.read_text()
    assert KP in text and text.count("servo_pitch(active, body, 0 deg, kp, kv)") == 2
    path = tmp_path / "hopper.leg"
    path.write_text(text.replace(KP, "  param kp = 150\n"))
    with pytest.raises(LegError) as caught:
        check_file(path)
    (only,) = caught.value.diagnostics
    line = text[: text.index(KP)].count("\n") + 1
    assert (only.span.line, only.span.col) == (line, 14)
    assert only.message == (
        "parameter 'kp' is declared as a plain number (no unit), but it is used as an angular "
        "stiffness (N*m/rad); declare it with its unit, as in 'param kp = 150 N*m/rad'"
    )
