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


def compiled_hopper(folder: Path) -> tuple[Path, Path]:
    """A copy of hopper.leg in ``folder`` and its generated tree, compiled."""
    source = folder / "hopper.leg"
    shutil.copy(CREATURES / "hopper.leg", source)
    generated = folder / "generated"
    RunSession.from_file(source, generated=generated).control("hop")
    return source, generated


def edited(source: Path, old: str, new: str, into: Path | None = None) -> Path:
    text = source.read_text()
    assert old in text
    (into or source).write_text(text.replace(old, new))
    return into or source


def test_an_edited_gain_lowers_its_controller_alone(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    source, generated = compiled_hopper(tmp_path)
    edited(source, "param kp = 150 N*m/rad", "param kp = 140 N*m/rad")
    calls = lowered(monkeypatch)
    session = RunSession.from_file(source, generated=generated)
    assert session.control("hop").PARAMS["kp"] == 140.0
    assert calls == []  # the dynamics kept
    assert written(generated / "hopper") == whole_compile(source)
    options = RunOptions(duration=0.5)
    result = session.run("hop", options=options, backend="c").result  # its C, rebuilt, runs
    assert result.status == "ok", result.message


@pytest.mark.parametrize(
    ("old", "new", "into"),
    [
        ("mass 10 kg", "mass 11 kg", None),  # the body: its dynamics are stale
        ("param kp = 150", "param kp = 140", "copy.leg"),  # the kept dynamics name hopper.leg
    ],
)
def test_an_edited_body_or_another_file_compiles_the_dynamics_too(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, old: str, new: str, into: str | None
) -> None:
    source, generated = compiled_hopper(tmp_path)
    calls = lowered(monkeypatch)
    changed = edited(source, old, new, None if into is None else tmp_path / into)
    RunSession.from_file(changed, generated=generated).control("hop")
    assert calls == ["hopper"]
    assert written(generated / "hopper") == whole_compile(changed)
