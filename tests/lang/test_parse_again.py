"""A text parsed again is the tree already built (trees are immutable), and an edited file
is read afresh: the memo is keyed by the text, never by the file's name alone."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

from legdsl.check.source import check_file
from legdsl.lang.errors import LegError
from legdsl.lang.parser import parse_file

HOPPER = Path(__file__).resolve().parents[2] / "creatures" / "hopper.leg"


def test_the_same_text_parses_to_the_same_tree() -> None:
    first, _ = parse_file(HOPPER, recover=True)
    again, _ = parse_file(HOPPER, recover=True)
    assert again is first
    with pytest.raises(dataclasses.FrozenInstanceError):
        first.path = "elsewhere"


def test_an_edited_file_is_parsed_afresh(tmp_path: Path) -> None:
    leg = tmp_path / "hopper.leg"
    text = HOPPER.read_text(encoding="utf-8")
    leg.write_text(text, encoding="utf-8")
    (model,) = check_file(leg)
    leg.write_text(text.replace("creature hopper", "creature hopper2"), encoding="utf-8")
    (edited,) = check_file(leg)
    assert (model.name, edited.name) == ("hopper", "hopper2")
    leg.write_text(text.replace("creature hopper {", "creature hopper {{"), encoding="utf-8")
    with pytest.raises(LegError):  # a mistake made after a good parse is still reported
        check_file(leg)
