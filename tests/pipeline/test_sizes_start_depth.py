"""How deep a contact may start under the ground follows the creature's size: 1 cm for
anything from 25 cm to 4 m tall (the shipped creatures), 4% of the standing height below
that (an insect may not start with its foot sunk through its whole leg) and 0.25% above
(a scaled giant may rest in its own footprint)."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import CREATURES

from legdsl.cli import main
from legdsl.sim.sizes import START_DEPTH, start_depth

POGO = Path(__file__).resolve().parents[1] / "good" / "outside" / "insect_pogo.leg"


def test_start_depth_is_1_cm_for_creatures_of_the_shipped_sizes() -> None:
    for height in (0.25, 0.3351, 0.8, 0.83, 4.0):  # the shipped creatures stand 0.34-0.83 m
        assert start_depth(height) == START_DEPTH
    assert start_depth(0.0) == START_DEPTH  # a root welded to the world
    assert start_depth(0.056) == pytest.approx(0.04 * 0.056)
    assert start_depth(24.0) == pytest.approx(0.0025 * 24.0)


def _run(capsys: pytest.CaptureFixture[str], argv: list[str]) -> tuple[int, str]:
    try:
        code = main(argv)
    except SystemExit as stop:
        code = int(stop.code or 0)
    return code, capsys.readouterr().err


def test_an_insect_starting_4_mm_under_the_ground_is_refused(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """The 3 g pogo stands 5.6 cm over its toe: a toe 4 mm deep is most of its leg's
    stroke, and the ground spring throws it up. It was let through (under 1 cm)."""
    leg = tmp_path / "insect_pogo.leg"
    leg.write_text(POGO.read_text().replace("z = 66 mm", "z = 52 mm"))
    argv = ["run", str(leg), "--time", "0.01", "--backend", "python"]
    code, err = _run(
        capsys, [*argv, "--generated", str(tmp_path / "gen"), "--out", str(tmp_path / "r")]
    )
    assert code == 2
    assert "contact 'toe' of creature 'insect_pogo' starts 0.004 m under the ground" in err


def test_the_pogo_as_written_runs(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    argv = ["run", str(POGO), "--time", "0.2", "--backend", "python"]
    code, err = _run(
        capsys, [*argv, "--generated", str(tmp_path / "gen"), "--out", str(tmp_path / "r")]
    )
    assert code == 0, err


def test_a_scaled_run_allows_the_start_depth_of_the_scaled_creature(
    capsys: pytest.CaptureFixture[str], generated: Path, tmp_path: Path
) -> None:
    """The hopper with its toe 5 mm under the ground (within the 1 cm of its 0.8 m) scaled by
    10: the file 'legdsl scale' writes was refused (8 m tall, 2 cm allowed, its toe 5 cm
    under) and the --scale 10 run ran, held to the unscaled creature's 1 cm."""
    text = (CREATURES / "hopper.leg").read_text(encoding="utf-8")
    deep = tmp_path / "hopper.leg"
    deep.write_text(text.replace("z = 0.95 m,", "z = 0.795 m,"), encoding="utf-8")
    run = ["run", str(deep), "--controller", "hop", "--time", "0.05", "--backend", "python",
           "--generated", str(generated)]  # fmt: skip
    assert _run(capsys, [*run, "--out", str(tmp_path / "a")])[0] == 0
    scaled = tmp_path / "hopper_x10.leg"
    assert main(["scale", str(deep), "--by", "10", "-o", str(scaled)]) == 0
    code, by_file = _run(capsys, ["run", str(scaled), *run[2:], "--out", str(tmp_path / "f")])
    assert code == 2 and "starts 0.05 m under the ground" in by_file
    code, err = _run(capsys, [*run, "--scale", "10", "--out", str(tmp_path / "s")])
    assert code == 2, err
    assert (
        "starts 0.005 m under the ground (the ground would throw the body up; at --scale "
        "10 it starts 0.05 m under, where a creature of that size may start 0.02 m under" in err
    )
    assert (
        _run(capsys, [*run, "--scale", "10", "--drop", "1cm", "--out", str(tmp_path / "d")])[0] == 0
    )
