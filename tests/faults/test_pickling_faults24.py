"""Faults of the fault hunt of the newest features (faults24): a pickled creature whose
used file changed before it was unpickled."""

from __future__ import annotations

import pickle
import re
from pathlib import Path

import pytest

import legdsl
from legdsl.lang.errors import UsageError

HOPPER = Path(__file__).resolve().parents[2] / "creatures" / "hopper.leg"

pytestmark = pytest.mark.usefixtures("hopper_modules")


def test_a_change_in_a_used_file_is_told_as_such(tmp_path: Path) -> None:
    """The gain moved to a shared part in a used file, changed after pickling: refused, as it
    should be, but the message named only the creature's own file, unchanged, as changed."""
    text = re.sub(r"  param kp = 150 N\*m/rad[^\n]*\n", "", HOPPER.read_text())
    text = text.replace("controller hop {\n", "controller hop {\n  include gains\n")
    source = tmp_path / "h.leg"
    source.write_text(text.replace("use raibert\n", 'use raibert\nuse "part.leg"\n'))
    part = tmp_path / "part.leg"
    part.write_text("shared gains {\n  param kp = 150 N*m/rad\n}\n")
    sent = pickle.dumps(legdsl.load(source, generated=tmp_path / "generated"))
    part.write_text("shared gains {\n  param kp = 170 N*m/rad\n}\n")
    with pytest.raises(UsageError, match="h.leg or a file it uses has changed since"):
        pickle.loads(sent)
    part.unlink()
    source.unlink()
    source.mkdir()
    with pytest.raises(UsageError, match=r"h.leg is gone \(a folder is in its place\)"):
        pickle.loads(sent)
