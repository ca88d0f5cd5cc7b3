"""A controller edited in a creature's file: only that controller is lowered again (the
dynamics, seconds of sympy, are kept), and the generated directory is the one a whole compile
writes, byte for byte. An edit of the body, or another file of the same creature, compiles all."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from conftest import CREATURES

from legdsl.pipeline import compile as compile_stage
from legdsl.pipeline.compile import compile_model
from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions


def written(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in folder.iterdir() if p.name != "__pycache__"}


def whole_compile(source: Path) -> dict[str, bytes]:
    return {name: text.encode("utf-8") for name, text in compile_model(source).files}


def lowered(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """The creatures whose dynamics are lowered through sympy from here on."""
    names: list[str] = []
    lower = compile_stage.lower

    def noted(model, *args, **kwargs):  # type: ignore[no-untyped-def]
        names.append(model.name)
        return lower(model, *args, **kwargs)

    monkeypatch.setattr(compile_stage, "lower", noted)
    return names


def test_an_edited_gain_lowers_its_controller_alone(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    source = tmp_path / "hopper.leg"
    shutil.copy(CREATURES / "hopper.leg", source)
    generated = tmp_path / "generated"
    RunSession.from_file(source, generated=generated).control("hop")
    source.write_text(
        source.read_text().replace("param kp = 150 N*m/rad", "param kp = 140 N*m/rad")
    )
    calls = lowered(monkeypatch)
    session = RunSession.from_file(source, generated=generated)
    assert session.control("hop").PARAMS["kp"] == 140.0
    assert calls == []  # the dynamics kept
    assert written(generated / "hopper") == whole_compile(source)
    options = RunOptions(duration=0.5)
    result = session.run("hop", options=options, backend="c").result  # its C, rebuilt, runs
    assert result.status == "ok", result.message


def test_an_edited_body_or_another_file_compiles_the_dynamics_too(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    source = tmp_path / "hopper.leg"
    shutil.copy(CREATURES / "hopper.leg", source)
    generated = tmp_path / "generated"
    RunSession.from_file(source, generated=generated).control("hop")
    calls = lowered(monkeypatch)
    other = tmp_path / "copy.leg"  # the same creature, its gain edited: printed from copy.leg
    other.write_text(source.read_text().replace("param kp = 150", "param kp = 140"))
    RunSession.from_file(other, generated=generated).control("hop")
    assert calls == ["hopper"]
    assert written(generated / "hopper") == whole_compile(other)
