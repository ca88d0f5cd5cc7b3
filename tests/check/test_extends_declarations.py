"""A derived controller's own declarations against its base's: a misspelt one that nothing
reads is an error naming the base's, and one of another unit than the base's is told at
the user's line, not at the base's uses of it."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.check.source import check_model
from legdsl.lang.errors import LegError

ROOT = Path(__file__).resolve().parents[2]
HOPPER = (ROOT / "creatures" / "hopper.leg").read_text()
LINES = HOPPER.count("\n")  # the derived controller's first line is LINES + 2


def _diagnostics(tmp_path: Path, derived: str) -> list[tuple[str, int, int, str]]:
    path = tmp_path / "hopper.leg"
    path.write_text(HOPPER + "\n" + derived)
    with pytest.raises(LegError) as info:
        check_model(path)
    return [
        (Path(d.span.file).name, d.span.line - LINES - 1, d.span.col, d.message)
        for d in info.value.diagnostics
    ]


def test_a_misspelt_parameter_of_a_derived_controller_is_an_error(tmp_path: Path) -> None:
    """'ful' for 'full' was a new parameter nobody reads: hop's 0.79 m was used, silently."""
    found = _diagnostics(tmp_path, "controller hop_long extends hop {\n  param ful = 0.85 m\n}\n")
    assert found == [
        (
            "hopper.leg",
            2,
            9,
            "param 'ful' is declared but never read; did you mean 'full' (of hop)? As written "
            "it is a parameter of its own, and hop's 'full' keeps its value; to give that one "
            "another, write 'param full = 0.85 m'",
        )
    ]


def test_a_new_parameter_the_derived_controller_reads_is_no_mistake(tmp_path: Path) -> None:
    path = tmp_path / "hopper.leg"
    path.write_text(
        HOPPER + "controller hop_long extends hop {\n  param fuller = 0.5 m/s\n"
        "  param extra = 1 s\n  signal reach = select(abs(speed_aim) < 1 mm/s, max_step, fuller)\n}\n"
    )
    assert [p.name for p in check_model(path).controller("hop_long").params][-2:] == [
        "fuller",
        "extra",  # read nowhere, but not like any of hop's: a parameter of its own
    ]


def test_an_overriding_parameter_of_another_unit_is_told_at_its_own_line(tmp_path: Path) -> None:
    """It was told at hop's line, where hop's table uses it (85:96), never at the user's."""
    found = _diagnostics(tmp_path, "controller hop_soft extends hop {\n  param stroke = 3 deg\n}\n")
    path = tmp_path / "hopper.leg"
    assert found == [
        (
            "hopper.leg",
            2,
            18,
            "param 'stroke' is an angle (deg), but controller 'hop', which this one "
            f"extends, declares it a length (m) ('3 cm', {path}:60:9) and uses it as one "
            f"({path}:85:96); write it with a unit of length (m)",
        )
    ]


def test_an_overriding_parameter_of_another_unit_its_own_table_uses_so_is_right(
    tmp_path: Path,
) -> None:
    creature = (ROOT / "tests" / "bad" / "ctl_dim_comparison.leg").read_text()
    path = tmp_path / "lean.leg"
    path.write_text(
        creature.split("controller")[0] + "controller hop {\n  param kv = 2 N*m*s/rad\n  table {\n"
        "    state A on liftoff(main): hip_servo.kv = kv\n"
        "    state B on touchdown(main): hip_servo.kv = 0 N*m*s/rad\n  }\n}\n"
        "controller lean extends hop {\n  param kv = 3 deg\n  table {\n"
        "    state A on liftoff(main): hip_servo.setpoint = kv\n"
        "    state B on touchdown(main): hip_servo.setpoint = 0 deg\n  }\n}\n"
    )
    (kv,) = check_model(path).controller("lean").params
    assert kv.dim == (0, 0, 0, 1)
