"""A run made with a relative .leg path, measured from another folder: run.json names the
file from the folder the run was made in, and the note said the file was gone. Every other
reason the rows on the creature's geometry are left out is said too, with advice that works:
copying the file as told left them out without a word (its generated modules were not found),
as did a file that does not load (its ``use`` not found) and stale modules. run.json records
the folder of the run's modules (``--generated``), which metrics then finds without it."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from legdsl.cli import main

ROOT = Path(__file__).resolve().parents[2]


def test_a_relative_source_not_found_from_here_says_where_to_measure_from(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    made_in = tmp_path / "work"
    made_in.mkdir()
    (made_in / "hopper.leg").write_text((ROOT / "creatures" / "hopper.leg").read_text("utf-8"))
    monkeypatch.chdir(made_in)
    argv = ["run", "hopper.leg", "--controller", "hop", "--time", "0.5", "--backend", "python",
            "--generated", str(ROOT / "generated"), "--out", "run"]  # fmt: skip
    assert main(argv) == 0
    monkeypatch.chdir(tmp_path)
    assert main(["metrics", "work/run"]) == 0
    err = capsys.readouterr().err
    assert "'hopper.leg' that work/run/run.json names is not found from here" in err
    assert "run legdsl metrics from the folder the run was made in" in err
    assert "is gone" not in err  # it is where it was
    monkeypatch.chdir(made_in)
    assert main(["metrics", "run", "--generated", str(ROOT / "generated")]) == 0
    assert "note" not in capsys.readouterr().err


GEOMETRY_ROWS = ("foot clearance at the apex", "foot speed over the ground at touchdown")


@pytest.fixture
def hopper_run(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, hopper_modules: None) -> Path:
    """A short hopper run made in ``tmp_path/work`` (its modules in ``tmp_path/generated``),
    measured from ``tmp_path/elsewhere``."""
    made_in = tmp_path / "work"
    made_in.mkdir()
    (made_in / "hopper.leg").write_text((ROOT / "creatures" / "hopper.leg").read_text("utf-8"))
    monkeypatch.chdir(made_in)
    argv = ["run", "hopper.leg", "--controller", "hop", "--time", "0.5", "--backend", "python",
            "--generated", str(tmp_path / "generated"), "--out", str(tmp_path / "run")]  # fmt: skip
    assert main(argv) == 0
    (tmp_path / "elsewhere").mkdir()
    monkeypatch.chdir(tmp_path / "elsewhere")
    return tmp_path / "run"


def measured(argv: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[str, str]:
    capsys.readouterr()
    assert main(["metrics", *argv]) == 0
    captured = capsys.readouterr()
    return captured.out, captured.err


def test_the_file_copied_as_told_and_its_modules_given_bring_the_rows_back(
    hopper_run: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out, err = measured([str(hopper_run)], capsys)
    assert not any(row in out for row in GEOMETRY_ROWS)
    assert "copy the file (and the files it uses) into" in err
    assert "give --generated" not in err  # run.json says where the modules are
    (hopper_run / "hopper.leg").write_text((ROOT / "creatures" / "hopper.leg").read_text())
    modules = hopper_run.parent / "generated"
    out, err = measured([str(hopper_run)], capsys)  # the modules run.json records
    assert all(row in out for row in GEOMETRY_ROWS) and "note" not in err, err
    modules.rename(hopper_run.parent / "moved")  # gone from where the run was made
    out, err = measured([str(hopper_run)], capsys)
    assert not any(row in out for row in GEOMETRY_ROWS)
    assert (
        "legdsl: note: generated/hopper/dynamics.py, the creature's generated kinematics, " in err
    )
    assert f"nor under {modules}, the folder run.json records" in err, err
    assert "give --generated the folder of the run's generated modules" in err, err
    (hopper_run.parent / "moved").rename(modules)
    out, err = measured([str(hopper_run), "--generated", str(modules)], capsys)
    assert all(row in out for row in GEOMETRY_ROWS) and "note" not in err, err
    dynamics = modules / "hopper" / "dynamics.py"
    text = dynamics.read_text()
    dynamics.write_text(text.replace('MODEL_FINGERPRINT = "', 'MODEL_FINGERPRINT = "0', 1))
    out, err = measured([str(hopper_run), "--generated", str(modules)], capsys)
    assert not any(row in out for row in GEOMETRY_ROWS)
    assert f"{dynamics} is not compiled from the creature of " in err, err


def test_a_file_that_does_not_load_is_said_with_its_error(
    hopper_run: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A copied file that uses another file, copied alone, cannot load."""
    (hopper_run / "hopper.leg").write_text('use "hopper_parts.leg"\n')
    out, err = measured(
        [str(hopper_run), "--generated", str(hopper_run.parent / "generated")], capsys
    )
    assert not any(row in out for row in GEOMETRY_ROWS)
    assert f"{hopper_run}/hopper.leg, the file {hopper_run}/run.json names, does not load (" in err
    assert "cannot find 'hopper_parts.leg' to use" in err, err
    assert "copy the files it uses to where its use lines name them" in err


def test_the_modules_folder_run_json_records_is_found_with_the_run_moved(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str],
    hopper_modules: None,
) -> None:  # fmt: skip
    """A run made with --generated gen: metrics said "give --generated ... (generated/ where
    the run was made)", run.json not recording it. It is recorded from the run directory and
    absolute: found with the whole folder moved, and with the run directory alone moved."""
    work = tmp_path / "work"
    (work / "runs").mkdir(parents=True)
    (work / "hopper.leg").write_text((ROOT / "creatures" / "hopper.leg").read_text("utf-8"))
    (tmp_path / "generated").rename(work / "gen")
    monkeypatch.chdir(work)
    argv = ["run", "hopper.leg", "--controller", "hop", "--time", "0.5", "--backend", "python",
            "--generated", "gen", "--out", "runs/h"]  # fmt: skip
    assert main(argv) == 0
    recorded = json.loads((work / "runs" / "h" / "run.json").read_text())["generated"]
    assert recorded == {"from_run": "../../gen", "absolute": str(work / "gen")}
    out, err = measured(["runs/h"], capsys)
    assert all(row in out for row in GEOMETRY_ROWS) and "note" not in err, err
    moved = tmp_path / "moved"
    work.rename(moved)  # the whole folder: found from the run directory
    monkeypatch.chdir(moved)
    out, err = measured(["runs/h"], capsys)
    assert all(row in out for row in GEOMETRY_ROWS) and "note" not in err, err
    work.mkdir()
    (moved / "gen").rename(work / "gen")  # the modules back where they were, the run not:
    out, err = measured(["runs/h"], capsys)  # found by the absolute path
    assert all(row in out for row in GEOMETRY_ROWS) and "note" not in err, err
