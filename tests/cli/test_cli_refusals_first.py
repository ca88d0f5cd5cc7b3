"""A refused run is told its mistake alone (docs/runtime.md: "a refusal is one line"): the
notes about a run's length ("give a longer --time to see it", a drop whose fall outlasts the
run) came first, and advised a longer --time for a command no --time makes acceptable; and
a --drop the creature cannot take is refused before its modules are compiled."""

from __future__ import annotations

import warnings
from pathlib import Path

import pytest
from conftest import CREATURES, OUTSIDE

import legdsl
from legdsl.cli import main
from legdsl.lang.errors import UsageError


def _refused(capsys: pytest.CaptureFixture[str], argv: list[str]) -> list[str]:
    assert main(argv) == 2
    return capsys.readouterr().err.splitlines()


@pytest.mark.parametrize(
    ("controller", "extra", "refusal"),
    [
        ("trot", ["--set", "speed=1m/s@6s", "--set", "speed=2m/s@6s"], "at the same time (6 s)"),
        ("trot", ["--set", "trot.speed=1m/s@1s"], "is controller trot's own value"),
    ],
)
def test_a_refused_setting_is_not_preceded_by_notes_on_the_runs_length(
    generated: Path,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    controller: str,
    extra: list[str],
    refusal: str,
) -> None:
    argv = ["run", str(CREATURES / "quadruped.leg"), "--controller", controller, "--time",
            "0.1", *extra, "--generated", str(generated), "--out", str(tmp_path / "r")]  # fmt: skip
    err = _refused(capsys, argv)
    assert refusal in err[0] and not any("note:" in line for line in err), err
    assert not (tmp_path / "r").exists()


@pytest.mark.parametrize(
    ("leg", "drop", "refusal"),
    [
        (OUTSIDE / "rig.leg", "0.1", "--drop lifts a free root, but creature 'rig' is welded"),
        (CREATURES / "hopper.leg", "1.4e9", "so its geometry would be lost in rounding"),
    ],
)
def test_a_drop_the_creature_cannot_take_is_refused_before_compiling_and_alone(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], leg: Path, drop: str, refusal: str
) -> None:
    fresh = tmp_path / "generated"
    argv = ["run", str(leg), "--drop", drop, "--time", "0.1", "--generated", str(fresh),
            "--out", str(tmp_path / "r")]  # fmt: skip
    err = _refused(capsys, argv)
    assert len(err) == 1 and refusal in err[0], err  # no "compiling", no note of the fall
    assert not fresh.exists() and not (tmp_path / "r").exists()


def test_the_api_refuses_a_run_before_its_warnings(generated: Path) -> None:
    hopper = legdsl.load(CREATURES / "hopper.leg", generated=generated)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with pytest.raises(UsageError, match="lost in rounding"):
            hopper.run(controller="hop", time=0.1, drop=1.4e9)
    assert [str(w.message) for w in caught] == []
