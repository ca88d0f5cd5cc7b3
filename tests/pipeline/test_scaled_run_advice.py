"""What a ``legdsl run --scale L`` run advises when its step or a stiffness is wrong: values for
the command line being typed (``--dt``, ``--set`` are the scaled creature's), as the run of the
file ``legdsl scale`` writes advises them."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
from conftest import CREATURES

from legdsl.cli import main

HOPPER = str(CREATURES / "hopper.leg")


def _run(generated: Path, out: Path, *args: str) -> int:
    return main(["run", HOPPER, "--controller", "hop", "--generated", str(generated),
                 "--backend", "python", "--out", str(out), *args])  # fmt: skip


def test_a_scaled_runs_divergence_advises_the_step_its_dt_takes(
    generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """At L = 0.01 with --dt 0.4ms it advised 'a step of 0.5 ms (--dt ...)', the model's: --dt
    0.5ms diverged again with the same advice. Its numbers are the scaled creature's now, and
    the step it advises runs."""
    assert _run(generated, tmp_path / "a", "--time", "0.3", "--dt", "0.4ms",
                "--control-dt", "0.4ms", "--scale", "0.01") == 3  # fmt: skip
    err = capsys.readouterr().err
    advised = re.search(r"try a step of (\S+) ms \(--dt; ", err)
    assert advised is not None, err
    assert float(advised[1]) == pytest.approx(0.05)
    # the ground's k is the scaled creature's (3e4 N/m times L^2), its step 0.4 ms
    assert "the step 0.4 ms is too large" in err and "(k = 3 N/m, " in err
    assert _run(generated, tmp_path / "b", "--time", "0.3", "--dt", f"{advised[1]}ms",
                "--control-dt", "0.4ms", "--scale", "0.01") == 0  # fmt: skip


def test_a_scaled_energy_rise_says_when_the_run_fell_in_the_scaled_creatures_time(
    generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """'After it the run fell at t = 0.4098 s' was the model's time in a run that ended, scaled,
    at 0.1296 s; run.json's diverged_at was the model's too."""
    out = tmp_path / "a"
    assert _run(generated, out, "--time", "0.3", "--dt", "1.2ms", "--control-dt", "1.2ms",
                "--scale", "0.1") == 3  # fmt: skip
    err = capsys.readouterr().err
    info = json.loads((out / "run.json").read_text(encoding="utf-8"))
    rose = re.search(r"diverged at t = (\S+) s: the total energy rose .* to \S+ J at t = (\S+) s",
                     err)  # fmt: skip
    fell = re.search(r"After it the run fell at t = (\S+) s", err)
    assert rose is not None and fell is not None, err
    assert float(fell[1]) == pytest.approx(info["ended_at"], abs=1e-4)
    assert float(rose[1]) == float(rose[2]) == pytest.approx(info["diverged_at"], abs=1e-4)
    assert info["diverged_at"] < info["ended_at"] <= 0.3


def test_a_scaled_runs_too_stiff_set_is_told_as_given(
    generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--set leg_spring.k=1e7N/m at L = 0.1 was told 'k = 1e+09 N/m', the model's, with a bound
    and a step 100 and 3.2 times off for --set and --dt; following it was refused again."""
    scaled = ["--time", "0.05", "--scale", "0.1"]
    assert _run(generated, tmp_path / "a", *scaled, "--set", "leg_spring.k=1e7N/m") == 2
    err = capsys.readouterr().err
    said = re.search(r"k = 1e\+07 N/m with dt = (\S+) ms diverges at once; use k below (\S+) "
                     r"N/m, or a step below (\S+) ms \(--dt; ", err)  # fmt: skip
    assert said is not None, err
    assert float(said[1]) == pytest.approx(0.4 * 0.1**0.5, rel=1e-3)  # the scaled default step
    assert _run(generated, tmp_path / "b", *scaled, "--set", f"leg_spring.k={said[2]}N/m") == 0
    assert _run(generated, tmp_path / "c", *scaled, "--set", "leg_spring.k=1e7N/m",
                "--dt", f"{said[3]}ms") == 0  # fmt: skip
    assert "too stiff" not in capsys.readouterr().err


def test_a_scaled_runs_stop_too_stiff_is_told_as_the_scaled_creatures_and_its_lines(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The warning of a stop too stiff at L = 0.1 gave the model's k and a bound 3.2 times off
    for --dt: it gives the scaled creature's (as the scaled file's run does), and what the
    file's line, the unscaled creature's, should stay below."""
    text = (CREATURES / "hopper.leg").read_text(encoding="utf-8")
    limits = "    limits -0.25 m to 0.1 m\n"
    assert limits in text
    source = tmp_path / "hopper.leg"
    source.write_text(text.replace(limits, limits + "    stop k = 1e9 N/m\n"), encoding="utf-8")
    common = ["--time", "0.02", "--generated", str(tmp_path / "gen"), "--backend", "python"]
    assert main(["run", str(source), *common, "--scale", "0.1", "--out", str(tmp_path / "a")]) == 0
    err = capsys.readouterr().err
    said = re.search(r"\(k = 1e\+07 N/m\): use k below (\S+) N/m, or a step below (\S+) ms "
                     r"\(--dt; .* this line is the unscaled creature's: k = 1e\+09 N/m there, "
                     r"to stay below (\S+) N/m\)", err)  # fmt: skip
    assert said is not None, err
    assert float(said[3]) == pytest.approx(float(said[1]) * 100, rel=1e-2)
    fixed = source.read_text(encoding="utf-8").replace("1e9 N/m", f"{said[3]} N/m")
    source.write_text(fixed, encoding="utf-8")
    assert main(["run", str(source), *common, "--scale", "0.1", "--out", str(tmp_path / "b")]) == 0
    assert "too stiff" not in capsys.readouterr().err
