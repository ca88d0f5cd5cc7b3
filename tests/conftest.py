from __future__ import annotations

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
CREATURES = ROOT / "creatures"


@pytest.fixture
def creatures_dir() -> Path:
    return CREATURES
