"""An outside user's audit: runtime.md and compiler.md said MODEL_FINGERPRINT hashes "the link
tree, contacts and gravity", and animation.md that it "covers the whole file"; an edited
`initial ... z` changed it (`legdsl run` said "stale; compiling", the code printed again the
same but for that hash), and a ground or an actuator edit does not. The docs say what it
hashes, and this checks it against the function."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from conftest import CREATURES

from legdsl.codegen.fingerprints import model_fingerprint
from legdsl.pipeline.session import check_file

ROOT = Path(__file__).resolve().parents[2]
TEXT = (CREATURES / "hopper.leg").read_text(encoding="utf-8")


def _fingerprint(tmp_path: Path, text: str) -> str:
    leg = tmp_path / "hopper.leg"
    leg.write_text(text, encoding="utf-8")
    return model_fingerprint(check_file(str(leg), None, None, None)[0])


@pytest.mark.parametrize(
    ("old", "new", "changes"),
    [
        ("z = 0.95 m", "z = 1.0 m", True),  # a joint coordinate's initial value
        ('"#303030"', '"#303031"', True),  # a colour
        ("limits -60 deg to 60 deg", "limits -61 deg to 60 deg", True),
        ("normal spring(k = 3e4 N/m", "normal spring(k = 3.1e4 N/m", False),  # the ground
        ("k = 3000 N/m", "k = 3100 N/m", False),  # an actuator
        ("param stroke = 3 cm", "param stroke = 4 cm", False),  # a controller
        ("# A planar", "# B planar", False),  # a comment
    ],
)
def test_the_model_fingerprint_hashes_what_the_docs_say(
    tmp_path: Path, old: str, new: str, changes: bool
) -> None:
    assert old in TEXT
    before = _fingerprint(tmp_path, TEXT)
    assert (_fingerprint(tmp_path, TEXT.replace(old, new, 1)) != before) is changes


def test_the_docs_say_the_same_of_it() -> None:
    def said(doc: str) -> str:
        return " ".join(ROOT.joinpath("docs", doc).read_text(encoding="utf-8").split())

    for doc in ("runtime.md", "compiler.md"):
        text = said(doc)
        assert "a hash of the link tree, contacts and gravity" not in text
        assert re.search(r"MODEL_FINGERPRINT.{0,400}coordinates' `initial` values", text), doc
        assert re.search(r"MODEL_FINGERPRINT.{0,400}shape and colour", text), doc
    assert "fingerprint covers the whole file" not in said("animation.md")
    assert "nor a leg, an actuator, the ground or a controller" in said("runtime.md")
