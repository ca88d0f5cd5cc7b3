"""The compiler driver: ``.leg`` file -> AST -> model -> symbolic system -> printed modules.

``compile_model`` returns every stage so each can be inspected and tested
(like Devito's ``Operator._lower``); ``write_generated`` puts the printed
modules under ``generated/NAME/`` atomically: they are written into a
temporary sibling directory that is then renamed into place, so a failure
leaves the previous directory untouched and never half-written.
"""

from __future__ import annotations

import os
import shutil
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from legdsl.check.source import check_file, choose
from legdsl.codegen.python.control import render_control
from legdsl.codegen.python.dynamics import controller_fingerprint, render_dynamics, render_init
from legdsl.ir.model import Model
from legdsl.lang import ast
from legdsl.lang.parser import parse_file
from legdsl.lower.control import lower_controller
from legdsl.lower.symbolic import SymbolicSystem, lower

Progress = Callable[[str], None]


@dataclass(frozen=True)
class Compiled:
    """Every stage of compiling one creature."""

    source: str  # the .leg path as written in the generated header (relative)
    syntax: ast.SourceFile
    model: Model
    system: SymbolicSystem
    files: tuple[tuple[str, str], ...]  # (file name, text) of generated/NAME/
    timings: tuple[tuple[str, float], ...]  # (stage, seconds)

    @property
    def name(self) -> str:
        return self.model.name

    def text(self, file_name: str) -> str:
        return dict(self.files)[file_name]


def source_label(path: str | Path) -> str:
    """The path to print in generated headers: relative to the working directory when it can be,
    else its last two parts (``creatures/NAME.leg``), never absolute."""
    p = Path(path)
    if p.is_absolute():
        try:
            p = p.relative_to(Path.cwd())
        except ValueError:
            p = Path(*p.parts[-2:])
    return p.as_posix()


def compile_file(path: str | Path, progress: Progress | None = None) -> list[Compiled]:
    """Compile every creature in a ``.leg`` file."""
    say = progress or (lambda _: None)
    start = time.perf_counter()
    syntax, _ = parse_file(path)
    parsed = time.perf_counter() - start
    start = time.perf_counter()
    models = check_file(path)
    checked = time.perf_counter() - start
    say(f"{path}: parsed in {parsed:.2f} s, checked in {checked:.2f} s")
    return [_lower(syntax, m, (("parse", parsed), ("check", checked)), say) for m in models]


def compile_model(
    path: str | Path, creature: str | None = None, progress: Progress | None = None
) -> Compiled:
    """Compile the one creature of a ``.leg`` file (or the named one)."""
    return choose(compile_file(path, progress), creature, path)


def _lower(
    syntax: ast.SourceFile,
    model: Model,
    timings: tuple[tuple[str, float], ...],
    say: Progress,
) -> Compiled:
    say(f"{model.name}: lowering {model.nv} DOF through sympy (ABA, RNEA, CRBA, kinematics)")
    start = time.perf_counter()
    system = lower(model)
    lowered = time.perf_counter() - start
    say(f"{model.name}: lowered in {lowered:.2f} s; printing")
    start = time.perf_counter()
    source = source_label(model.source)
    files: tuple[tuple[str, str], ...] = (
        ("__init__.py", render_init(model)),
        ("dynamics.py", render_dynamics(system, source)),
    )
    for controller in model.controllers:
        say(f"{model.name}: lowering controller {controller.name}")
        lowered_controller = lower_controller(model, controller)
        events = {state.name: state.event_text for state in controller.states}
        stamp = controller_fingerprint(model, controller)
        text = render_control(lowered_controller, source, events, stamp)
        files += ((f"control_{controller.name}.py", text),)
    printed = time.perf_counter() - start
    lines = sum(text.count("\n") for _, text in files)
    say(f"{model.name}: printed {lines} lines in {printed:.2f} s")
    return Compiled(
        source,
        syntax,
        model,
        system,
        files,
        (*timings, ("lower", lowered), ("print", printed)),
    )


def write_generated(compiled: Compiled, out_root: str | Path) -> Path:
    """Write ``out_root/NAME/`` as a whole: the old directory is replaced only once the new one is complete."""
    root = Path(out_root)
    root.mkdir(parents=True, exist_ok=True)
    final = root / compiled.name
    fresh = root / f".{compiled.name}.new-{os.getpid()}"
    retired = root / f".{compiled.name}.old-{os.getpid()}"
    for leftover in (fresh, retired):
        if leftover.exists():
            shutil.rmtree(leftover)
    fresh.mkdir()
    try:
        for name, text in compiled.files:
            (fresh / name).write_text(text, encoding="utf-8", newline="\n")
        if final.exists():
            final.rename(retired)
        try:
            fresh.rename(final)
        except BaseException:
            if retired.exists() and not final.exists():
                retired.rename(final)  # put the old directory back
            raise
    except BaseException:
        shutil.rmtree(fresh, ignore_errors=True)
        raise
    shutil.rmtree(retired, ignore_errors=True)
    return final
