"""Every creature written outside the team (tests/good/outside/) checks clean: they are
what the docs point new users at, and each takes the shipped files' parts through 'use'
and 'extends', so a change to those that breaks a user's file fails here."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.check.source import check_file

OUTSIDE = Path(__file__).resolve().parents[1] / "good" / "outside"


@pytest.mark.parametrize("name", sorted(p.name for p in OUTSIDE.glob("*.leg")))
def test_checks_clean(name: str) -> None:
    models = check_file(OUTSIDE / name)
    assert models and all(m.controllers for m in models)
