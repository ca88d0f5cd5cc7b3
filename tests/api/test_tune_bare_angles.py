"""legdsl tune --param with bare numbers for an angle: noted as radians, as legdsl sweep notes
them (kangaroo's 'stroke = 5 deg' tuned with --param stroke=-10:10 searched ±573°, unsaid),
where the note helps: where the range in degrees fits the file's value better. Its advice was
also given where the bare range was right: the heavy hopper's stroke=0.01:0.08 (m; 3 cm in the
file) was told 'write stroke=0.01cm:0.08cm', which is refused for leaving 3 cm out."""

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
        ("stroke=-10:10", "a bare number is in rad: to give them in deg, write "
                          "stroke=-10deg:10deg"),
        ("stroke=1deg:9deg", None),
        ("stroke=-0.2:0.2", None),  # ±11° of 5 deg: -0.2deg:0.2deg would leave it out
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


@pytest.mark.parametrize("param", ["stroke=0.01:0.08", "kp=50:600"])
def test_a_bare_range_that_holds_the_files_value_is_not_noted(
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
    param: str,
) -> None:
    """docs/api.md's heavy hopper tune: stroke is 3 cm in the file, and 0.01:0.08 m holds it."""
    monkeypatch.setattr(tune_cli, "_tune_into", stopped)
    main([
        "tune", str(ROOT / "creatures" / "hopper.leg"), "--controller", "hop",
        "--param", param, "--speeds", "1", "--out", str(tmp_path / "t"),
    ])  # fmt: skip
    assert "a bare number" not in capsys.readouterr().err
