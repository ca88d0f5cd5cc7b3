"""The compiler driver: ``.leg`` file -> syntax tree -> model and controller IR -> lowered
controllers and symbolic system -> printed modules.

``compile_file`` parses each file once and returns, per creature, a ``Compiled`` holding every
stage's product so each can be inspected and tested (like Devito's ``Operator._lower``);
``compile_checked`` starts from a model already checked (the run session's, when its generated
modules are stale). Writing ``generated/NAME/`` is ``legdsl.pipeline.generated``'s.
"""

from __future__ import annotations

import functools
import os
import pickle
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

from sympy.core.parameters import evaluate

from legdsl.check.source import check_tree, choose
from legdsl.codegen.c.control import render_control_c
from legdsl.codegen.c.dynamics import render_header, render_some_source, render_source
from legdsl.codegen.fingerprints import controller_fingerprint
from legdsl.codegen.manifest import SUMS, render_init, sha256_sums, source_label
from legdsl.codegen.python.control import control_programs, render_control
from legdsl.codegen.python.dynamics import render_dynamics
from legdsl.ir.model import Controller, Model
from legdsl.lang import ast
from legdsl.lang.errors import Diagnostic, LegError, UsageError
from legdsl.lang.parser import parse_file
from legdsl.lower.control import LoweredController, lower_controller
from legdsl.lower.symbolic import SymbolicSystem, lower
from legdsl.pipeline.forked import Forked

Progress = Callable[[str], None]
Done = Callable[[str, float], None]  # (creature, share of its compile done)
# Shares of a compile's time (the quadruped's and the kangaroo's): its dynamics lowered, then
# printed; the rest is waiting for the controllers, lowered and printed in other processes.
LOWERING, PRINTING = 0.4, 0.15


@dataclass(frozen=True)
class Compiled:
    """Every stage of compiling one creature."""

    source: str  # the .leg path as written in the generated header (relative)
    syntax: ast.SourceFile  # the whole file's syntax tree
    model: Model  # the creature's checked IR
    system: SymbolicSystem  # the lowered dynamics
    lowered: tuple[LoweredController, ...]  # one per controller, in ``controllers`` order
    files: tuple[tuple[str, str], ...]  # (file name, text) of generated/NAME/
    timings: tuple[tuple[str, float], ...]  # (stage, seconds)

    @property
    def name(self) -> str:
        return self.model.name

    @property
    def controllers(self) -> tuple[Controller, ...]:
        """The controller IR (checked with the model, so it lives in ``model.controllers``)."""
        return tuple(self.model.controllers)

    def text(self, file_name: str) -> str:
        return dict(self.files)[file_name]


@dataclass(frozen=True)
class Checked:
    """A ``.leg`` file parsed and checked: the first stages of ``compile_file``, which
    ``legdsl compile`` runs for every file before it lowers one (two creatures of one name
    in two files are refused before anything is written)."""

    path: str | Path
    syntax: ast.SourceFile
    text: str
    models: list[Model]
    timings: tuple[tuple[str, float], ...]


def check_for_compile(path: str | Path, progress: Progress | None = None) -> Checked:
    """Parse and check a ``.leg`` file as ``compile_file`` does (a mistake raises LegError)."""
    say = progress or (lambda _: None)
    start = time.perf_counter()
    syntax, text = parse_file(path, recover=True)
    parsed = time.perf_counter() - start
    start = time.perf_counter()
    models = check_tree(syntax, text, path)
    checked = time.perf_counter() - start
    say(f"{path}: parsed in {parsed:.2f} s, checked in {checked:.2f} s")
    return Checked(path, syntax, text, models, (("parse", parsed), ("check", checked)))


def refuse_same_names(files: list[Checked], out: str | Path) -> None:
    """Refuse two creatures of one name in the files of one ``legdsl compile``: both would be
    ``OUT/NAME/``, the second replacing the first (it did, with exit 0). Told at both
    declarations, before anything is written."""
    first: dict[str, tuple[Model, Checked]] = {}
    found: list[Diagnostic] = []
    sources: dict[str, str] = {}
    for checked in files:
        for model in checked.models:
            if model.name not in first:
                first[model.name] = (model, checked)
                continue
            before, where = first[model.name]
            folder = Path(out) / model.name
            found += [
                Diagnostic(
                    before.span,
                    f"creature '{model.name}' is also defined at {model.span}, and both would "
                    f"be written to {folder}/",
                ),
                Diagnostic(
                    model.span,
                    f"creature '{model.name}' is already defined at {before.span}: both would "
                    f"be written to {folder}/, this one replacing it; rename one of them, or "
                    "compile them into different --out folders",
                ),
            ]
            sources |= {str(where.path): where.text, str(checked.path): checked.text}
    if found:
        raise LegError(found, sources)


def compile_each(
    checked: Checked, progress: Progress | None = None, done: Done | None = None
) -> Iterator[Compiled]:
    """Lower and print each creature of a checked file, one after another."""
    try:
        for m in checked.models:
            yield compile_checked(checked.syntax, m, progress, checked.timings, done)
    except LegError as e:  # found in lowering: shown with its line, as the checker's are
        raise LegError(e.diagnostics, {**e.sources, str(checked.path): checked.text}) from None


def compile_file(
    path: str | Path, progress: Progress | None = None, done: Done | None = None
) -> list[Compiled]:
    """Compile every creature in a ``.leg`` file (parsed once, then checked and lowered)."""
    return list(compile_each(check_for_compile(path, progress), progress, done))


def check_lowered(path: str | Path) -> list[Model]:
    """Check a ``.leg`` file, then lower each controller as ``compile`` does (``legdsl
    check``): sympy's algebra finds what the checker cannot see (a division by a difference
    that is always 0), so a file this accepts also compiles. The dynamics always lower."""
    syntax, text = parse_file(path, recover=True)
    models = check_tree(syntax, text, path)
    try:
        for model in models:
            for controller in model.controllers:
                lower_controller(model, controller)
    except LegError as e:  # shown with its line, as the checker's are
        raise LegError(e.diagnostics, {**e.sources, str(path): text}) from None
    return models


def compile_model(
    path: str | Path,
    creature: str | None = None,
    progress: Progress | None = None,
    done: Done | None = None,
) -> Compiled:
    """Compile the one creature of a ``.leg`` file (or the named one)."""
    return choose(compile_file(path, progress, done), creature, path)


def compile_checked(
    syntax: ast.SourceFile,
    model: Model,
    progress: Progress | None = None,
    timings: tuple[tuple[str, float], ...] = (),
    done: Done | None = None,
) -> Compiled:
    """Lower and print a model already checked from ``syntax`` (the stages after the checker).

    A creature's controllers are lowered and printed in other processes while this one
    lowers its dynamics (``compile_jobs``): they depend on the model alone. ``done`` is told
    the creature's name and the share of its compile done, as it goes."""
    say = progress or (lambda _: None)
    source = source_label(model.source)

    def tick(share: float) -> None:
        if done is not None:
            done(model.name, share)

    others = None
    try:  # the processes closed also when Ctrl-C lands as they start
        others = _controller_processes(model, source)
        say(f"{model.name}: lowering {model.nv} DOF through sympy (ABA, RNEA, CRBA, kinematics)")
        start = time.perf_counter()
        system = lower(model, done=lambda share: tick(LOWERING * share))
        lowered = time.perf_counter() - start
        say(f"{model.name}: lowered in {lowered:.2f} s; printing")
        start = time.perf_counter()
        files: tuple[tuple[str, str], ...] = (
            ("__init__.py", render_init(model)),
            ("dynamics.py", render_dynamics(system, source)),
            ("dynamics.c", render_source(system, source)),
            ("dynamics_some.c", render_some_source(system, source)),
            ("dynamics.h", render_header(system, source)),
        )
        tick(LOWERING + PRINTING)
        controllers: tuple[LoweredController, ...] = ()
        for k, controller in enumerate(model.controllers):
            say(f"{model.name}: lowering controller {controller.name}")
            if others:
                answer = others.result(k)  # lowered here, evaluating, if its process is gone
                with evaluate(False):  # rebuilt as printed: evaluating them again is seconds
                    lowered_controller, text, c_text = pickle.loads(answer)
            else:
                lowered_controller, text, c_text = controller_files(model, controller, source)
            controllers += (lowered_controller,)
            files += (
                (f"control_{controller.name}.py", text),
                (f"control_{controller.name}.c", c_text),
            )
            tick(LOWERING + PRINTING + (1 - LOWERING - PRINTING) * (k + 1) / len(model.controllers))
    finally:
        if others:
            others.close()
    printed = time.perf_counter() - start
    lines = sum(text.count("\n") for _, text in files)
    files += ((SUMS, sha256_sums(files)),)
    tick(1.0)
    say(f"{model.name}: printed {lines} lines in {printed:.2f} s")
    return Compiled(
        source=source,
        syntax=syntax,
        model=model,
        system=system,
        lowered=controllers,
        files=files,
        timings=(*timings, ("lower", lowered), ("print", printed)),
    )


def compile_jobs() -> int:
    """Processes that lower a creature, this one (its dynamics) among them:
    ``$LEGDSL_COMPILE_JOBS`` if set, else one per core (1: all in this process). A value
    that is no count of processes is refused (``abc`` and ``-3`` were silently one per core),
    as ``$LEGDSL_BACKEND``'s is."""
    asked = os.environ.get("LEGDSL_COMPILE_JOBS", "").strip()
    if not asked:
        return os.cpu_count() or 1
    if not (asked.isascii() and asked.isdigit()) or int(asked) < 1:
        raise UsageError(
            f"LEGDSL_COMPILE_JOBS={asked}: give the number of processes that compile, a whole "
            "number from 1 (1 keeps the compile in one process), or unset it for one per core "
            "(docs/compiler.md)"
        )
    return int(asked)


def _controller_processes(model: Model, source: str) -> Forked | None:
    """``compile_jobs() - 1`` processes (at most one per controller) lowering the controllers,
    beside this one lowering the dynamics: on 2 cores a worker per core as well was no faster
    for the quadruped (6.6 and 6.7 s against 6.1 and 7.5 s), and slower before its workers
    sent their results at the end (9.6 to 11.3 s against 7.5 to 8.8 s)."""
    processes = min(compile_jobs() - 1, len(model.controllers))
    if processes < 1:
        return None
    work = functools.partial(_pickled_controller_files, model, source=source)
    return Forked(work, model.controllers, processes)


def controller_files(
    model: Model, controller: Controller, source: str
) -> tuple[LoweredController, str, str]:
    """One controller lowered, and its Python and C modules."""
    lowered = lower_controller(model, controller)
    events = {state.name: state.event_text for state in controller.states}
    stamp = controller_fingerprint(model, controller)
    programs = control_programs(lowered, events)  # both targets print these
    return (
        lowered,
        render_control(lowered, source, events, stamp, programs),
        render_control_c(model, lowered, source, events, stamp, programs),
    )


def _pickled_controller_files(model: Model, controller: Controller, source: str) -> bytes:
    """``controller_files`` in another process, pickled there (see ``compile_checked``)."""
    return pickle.dumps(controller_files(model, controller, source))
