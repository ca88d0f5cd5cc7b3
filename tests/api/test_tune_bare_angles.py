"""legdsl tune --param with bare numbers for an angle: noted as radians, as legdsl sweep notes
them (kangaroo's 'stroke = 5 deg' tuned with --param stroke=-0.2:0.2 searched ±11°, unsaid)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

import legdsl.api.tune_cli as tune_cli
from legdsl.cli import main

ROOT = Path(__file__).resolve().parents[2]


def stopped(*args: Any, **kwargs: Any) -> None:
    raise KeyboardInterrupt  # the notes come before the search: no run needed


@pytest.mark.parametrize(
    ("param", "note"),
    [
        ("stroke=-0.2:0.2", "a bare number is in rad: to give them in deg, write "
                            "stroke=-0.2deg:0.2deg"),
        ("stroke=1deg:9deg", None),
    ],
)  # fmt: skip
def test_bare_angle_bounds_are_noted_as_radians(
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
    param: str,
    note: str | None,
) -> None:
    monkeypatch.setattr(tune_cli, "_tune_into", stopped)
    main([
        "tune", str(ROOT / "creatures" / "kangaroo.leg"), "--controller", "hop",
        "--param", param, "--speeds", "1", "--out", str(tmp_path / "t"),
    ])  # fmt: skip
    err = capsys.readouterr().err
    if note is None:
        assert "a bare number" not in err
    else:
        assert f"legdsl: note: --param {param}: {note}" in err
