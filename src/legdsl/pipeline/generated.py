"""``generated/NAME/``: written atomically, and loaded fresh (compiled first when missing or stale).

A generated module is fresh when its fingerprint constant (``MODEL_FINGERPRINT`` in
``dynamics.py``, ``FINGERPRINT`` in ``control_CONTROLLER.py``) is the one the checked model
gives now, and the file is the one legdsl wrote: its SHA-256 is the one ``SHA256SUMS`` lists
(a file cut short or edited by hand would otherwise run, or fail deep inside a run). Otherwise
the creature is compiled and its directory replaced as a whole:
``write_generated`` writes into a temporary sibling directory that is then renamed into place,
so a failure leaves the previous directory untouched and never half-written. When only
controllers are stale (a gain edited) and the dynamics are the ones this legdsl and sympy
printed from the same file, only those controllers are lowered again: the same files, byte for
byte, as a whole compile, in a second rather than the seconds of the dynamics. A creature
compiled before, anywhere, is copied from legdsl's cache instead (``legdsl.codegen.kept``).
"""

from __future__ import annotations

import errno
import hashlib
import importlib.util
import os
import sys
from collections.abc import Iterator, Sequence
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING, Any

from legdsl.codegen.fingerprints import controller_fingerprint, model_fingerprint
from legdsl.codegen.kept import keep_files, kept_entry, kept_files
from legdsl.codegen.manifest import SUMS, render_init, sha256_sums, source_label
from legdsl.files import (
    REFUSED_WRITES,
    instant,
    recover_dir,
    remove,
    replace_dir,
    temp_sibling,
    write_atomic,
)
from legdsl.ir.model import Model
from legdsl.lang import ast
from legdsl.lang.errors import UsageError
from legdsl.pipeline.report import CompileProgress
from legdsl.pipeline.settings import require_controller
from legdsl.signals import import_held

if TYPE_CHECKING:
    from legdsl.pipeline.compile import Compiled, Done


def import_module_file(path: Path, name: str) -> ModuleType:
    spec = importlib.util.spec_from_file_location(name, path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def load_dynamics(
    model: Model,
    source: Path,
    generated: Path,
    log: Any = None,
    syntax: ast.SourceFile | None = None,
) -> ModuleType:
    """The creature's generated dynamics module, compiled first if missing or stale.

    ``syntax``, the file's syntax tree the model was checked from, saves parsing it again.
    """
    stamp = ("MODEL_FINGERPRINT", model_fingerprint(model))
    return _load(model, source, generated, "dynamics.py", stamp, log, syntax)


def load_controller(
    model: Model,
    controller: str,
    source: Path,
    generated: Path,
    log: Any = None,
    syntax: ast.SourceFile | None = None,
) -> ModuleType:
    """The generated control module of one of the creature's controllers (compiled if needed)."""
    require_controller(model, controller)
    stamp = ("FINGERPRINT", controller_fingerprint(model, model.controller(controller)))
    return _load(model, source, generated, f"control_{controller}.py", stamp, log, syntax)


def _load(
    model: Model,
    source: Path,
    generated: Path,
    file: str,
    stamp: tuple[str, str],
    log: Any,
    syntax: ast.SourceFile | None,
) -> ModuleType:
    """Import ``generated/NAME/file`` if its fingerprint constant matches, else compile first."""
    path = generated / model.name / file
    label = f"legdsl_generated_{model.name}_{path.stem}"
    if generated.is_dir():
        recover_dir(generated / model.name)  # after a compile that was killed
    reason = next((why for _, why in _changed(path.parent, [file])), "")  # "missing", ...
    if not reason:
        try:
            module = import_module_file(path, label)
        except Exception as e:  # a merge-conflict marker, an edit that kept its digest...
            reason = f"unreadable ({type(e).__name__}: {e})"
        else:
            if getattr(module, stamp[0], None) == stamp[1]:
                return module
            reason = "stale"
    _recompile(model, source, generated, syntax, log, f"{path} is {reason}")
    return import_module_file(path, label + "_new")


def c_sources(
    model: Model,
    source: Path,
    generated: Path,
    log: Any = None,
    syntax: ast.SourceFile | None = None,
    controller: str | None = None,
) -> Path:
    """``generated/NAME/``, with its ``dynamics.c``, ``dynamics_some.c`` and ``dynamics.h``
    (and the controller's ``control_CONTROLLER.c``) fresh, compiled first if missing or stale
    like the Python modules: the directory the C backend builds from."""
    folder = generated / model.name
    stamps = _dynamics_stamps(model)
    if controller is not None:
        stamps |= _controller_stamps(model, controller)
    wanted = {name: line for name, line in stamps.items() if name.endswith(".c")}
    if generated.is_dir():
        recover_dir(folder)
    names = [*wanted, "dynamics.h"]
    why = next((f"{name} is {reason}" for name, reason in _changed(folder, names)), None)
    for file, line in wanted.items():
        if why is None and line not in (folder / file).read_text(encoding="utf-8"):
            why = f"{file} is stale"
    if why:
        listed = ", ".join(names)
        _recompile(model, source, generated, syntax, log, f"{folder}/{{{listed}}}: {why}")
    return folder


def edited_by_hand(
    model: Model, source: Path, folder: Path, syntax: ast.SourceFile | None, names: Sequence[str]
) -> list[str]:
    """Which of ``folder``'s files ``names`` differ from what legdsl generates for ``model``
    now, below their first line (which names the .leg file as the compile that wrote them was
    given it). It compiles again, which takes seconds: for a build that failed, to tell the
    user's edit from legdsl's bug."""
    compiled = _compiled(model, source, syntax)
    made = {name: text.partition("\n")[2] for name, text in compiled.files}
    return [name for name in names if name in made and _body(folder / name) != made[name]]


def _body(path: Path) -> str | None:
    try:
        return path.read_text(encoding="utf-8").partition("\n")[2]
    except (OSError, UnicodeDecodeError):
        return None


def _compiled(
    model: Model, source: Path, syntax: ast.SourceFile | None, done: Done | None = None
) -> Compiled:
    """The creature compiled again (from its checked syntax tree when at hand)."""
    compiler = _compiler()
    if syntax is None:
        return compiler.compile_model(source, model.name, done=done)
    return compiler.compile_checked(syntax, model, done=done)


def _compiler() -> ModuleType:
    """``legdsl.pipeline.compile``, imported here: sympy alone takes some 0.4 s, and a fresh
    module needs none."""
    return import_held("legdsl.pipeline.compile")


def _recompile(
    model: Model,
    source: Path,
    generated: Path,
    syntax: ast.SourceFile | None,
    log: Any,
    why: str,
) -> None:
    """Write ``generated/NAME/`` again (``why``: which file is missing or stale, for ``log``):
    copied from legdsl's cache when this creature was compiled before, else compiled, with a
    bar and the time left on a terminal's standard error, and kept there. A tree that cannot
    be written (a read-only checkout, a shared install) is the user's to fix, and the message
    says how."""
    entry = kept_entry(model, source_label(model.source))
    files = kept_files(entry)
    if files is not None and not _of_model(files, model):  # another creature's, put there
        files = None  # (copied in again at every run, then an internal error): compiled anew
    if log is not None:
        copied = f"{source} was compiled before: its modules are copied from legdsl's cache"
        print(f"legdsl: {why}; {copied if files else f'compiling {source}'}", file=log)
    if files is None:
        files = _controllers_recompiled(model, generated / model.name)
        if files is None:
            progress = CompileProgress().done if log is sys.stderr else None
            files = _compiled(model, source, syntax, progress).files
        keep_files(entry, files)
    try:
        write_module_dir(generated, model.name, files)
    except OSError as e:
        fix = "free some space there" if e.errno in REFUSED_WRITES else "make it writable"
        if e.errno == errno.EFBIG:  # no disk to free: the process's own limit
            fix = "raise that limit"
        state = _state(generated / model.name, why)
        raise UsageError(
            f"the generated modules of {model.name} in {generated} {state} "
            f"and cannot be written there ({_why(e)}); {fix}, or give --generated a directory "
            "you can write"
        ) from None


def _state(folder: Path, why: str) -> str:
    """What is wrong with the generated modules in ``folder``, for a message that cannot write
    them (``why``: the first file found missing or stale): "are missing" when there are none
    (a fresh --generated; they were said to be out of date), "are incomplete" when a file is
    missing, else "are out of date"."""
    try:
        present = any(folder.iterdir())
    except OSError:
        present = False
    if not present:
        return "are missing"
    return "are incomplete" if why.endswith(" is missing") else "are out of date"


DYNAMICS = ("dynamics.py", "dynamics.c", "dynamics_some.c", "dynamics.h")  # as compiles write them


def _dynamics_stamps(model: Model) -> dict[str, str]:
    """The line of each dynamics file that names the model's fingerprint."""
    stamp = model_fingerprint(model)
    return {
        "dynamics.py": f'MODEL_FINGERPRINT = "{stamp}"',
        "dynamics.c": f'legdsl_model_fingerprint[] = "{stamp}";',
        "dynamics_some.c": f"model fingerprint {stamp} */",
        "dynamics.h": f'#define LEG_MODEL_FINGERPRINT "{stamp}"',
    }


def _of_model(files: Sequence[tuple[str, str]], model: Model) -> bool:
    """Whether kept ``files`` are this model's: its dynamics and controllers, stamped so."""
    texts = dict(files)
    stamps = _dynamics_stamps(model)
    for c in model.controllers:
        stamps |= _controller_stamps(model, c.name)
    return _stamped(texts, stamps)


def _controller_stamps(model: Model, controller: str) -> dict[str, str]:
    stamp = controller_fingerprint(model, model.controller(controller))
    return {
        f"control_{controller}.py": f'FINGERPRINT = "{stamp}"',
        f"control_{controller}.c": f'legdsl_control_fingerprint[] = "{stamp}";',
    }


def _fresh(folder: Path, stamps: dict[str, str]) -> dict[str, str] | None:
    """The texts of ``folder``'s files named in ``stamps`` if each is as legdsl wrote it and
    holds its stamp line, else None."""
    if next(_changed(folder, list(stamps)), None) is not None:
        return None
    texts = {name: (folder / name).read_text(encoding="utf-8") for name in stamps}
    return texts if _stamped(texts, stamps) else None


def _stamped(texts: dict[str, str], stamps: dict[str, str]) -> bool:
    """Whether each file named in ``stamps`` is in ``texts`` and holds its stamp line."""
    return all(line in texts.get(name, "") for name, line in stamps.items())


def _controllers_recompiled(model: Model, folder: Path) -> tuple[tuple[str, str], ...] | None:
    """The creature's files with its stale controllers alone lowered again, when its dynamics
    in ``folder`` are fresh and were printed from the same file by this legdsl and sympy (their
    first lines are a new controller's); None when the dynamics must be compiled too."""
    kept = _fresh(folder, _dynamics_stamps(model))
    if kept is None:
        return None
    files = [("__init__.py", render_init(model)), *((name, kept[name]) for name in DYNAMICS)]
    printed = []
    for controller in model.controllers:
        texts = _fresh(folder, _controller_stamps(model, controller.name))
        if texts is None:
            label = source_label(model.source)
            _, text, c_text = _compiler().controller_files(model, controller, label)
            texts = {f"control_{controller.name}.py": text, f"control_{controller.name}.c": c_text}
            printed.append((text, c_text))
        files += texts.items()
    if not printed:  # stale for another reason (__init__.py, SHA256SUMS): compiled whole
        return None
    text, c_text = printed[0]
    python_head, c_head = _head(text, 2), _head(c_text, 1)  # the file, legdsl's, sympy's version
    if python_head != _head(kept["dynamics.py"], 2) or c_head != _head(kept["dynamics.c"], 1):
        return None  # printed from another file, or by another version: compiled whole
    return (*files, (SUMS, sha256_sums(tuple(files))))


def _head(text: str, lines: int) -> list[str]:
    return text.split("\n", lines)[:lines]


def _changed(folder: Path, names: Sequence[str]) -> Iterator[tuple[str, str]]:
    """(name, why) for each file whose SHA-256 is not the one ``folder/SHA256SUMS`` lists."""
    try:
        lines = (folder / SUMS).read_text(encoding="utf-8").splitlines()
        listed = {name: digest for digest, _, name in (line.partition("  ") for line in lines)}
    except (OSError, UnicodeDecodeError):
        listed = {}
    for name in names:
        try:
            digest = hashlib.sha256((folder / name).read_bytes()).hexdigest()
        except OSError:
            yield name, "missing"
            continue
        if name not in listed:
            yield name, f"unchecked (not in a {SUMS} beside it)"
        elif listed[name] != digest:
            yield name, f"changed since it was written (its SHA-256 is not the one {SUMS} lists)"


def write_generated(compiled: Compiled, out_root: str | Path) -> Path:
    """Write ``out_root/NAME/`` as a whole: the old directory is replaced only once the new one is complete."""
    return write_module_dir(Path(out_root), compiled.name, compiled.files)


def write_module_dir(root: Path, name: str, files: Sequence[tuple[str, str]]) -> Path:
    """Write the files into a fresh hidden sibling ``.NAME.new-PID-RANDOM``, then swap it in
    (``NAME`` a link to a directory: the directory it names, and the link stays).

    A writer killed at any instant leaves ``root/NAME`` old or new and whole, or (killed
    between the two renames of the swap) missing with its old copy beside it, which
    ``recover_dir`` puts back: it runs here first and before every load.
    """
    try:
        root.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        why = "it is a file" if root.is_file() else _why(e)
        raise UsageError(
            f"cannot write generated modules into {root}: {why}; "
            "give --generated a directory you can write"
        ) from e
    shown = final = root / name
    if final.is_symlink():  # a link to modules kept elsewhere: they are replaced, it stays
        final = Path(os.path.realpath(final))
    recover_dir(final)
    fresh = temp_sibling(final, "new")
    try:
        fresh.mkdir()
        instant("made the new directory")
        for file, text in files:
            write_atomic(fresh / file, text)
            instant(f"wrote {file}")
        replace_dir(fresh, final)
    except BaseException:
        remove(fresh)
        raise
    return shown


def _why(e: OSError) -> str:
    return e.strerror or str(e)


def recorded_folder(generated: Path | None, out: Path) -> dict[str, Any]:
    """run.json's ``generated``: the folder of the run's generated modules, from the run
    directory ``out`` (found again where the two were moved together) and absolute (found
    again where the run directory alone was moved); {} for a run made without one."""
    if generated is None:
        return {}
    folder = os.path.abspath(generated)
    try:
        from_run = os.path.relpath(folder, os.path.abspath(out))
    except ValueError:  # another drive (Windows): no way from one to the other
        return {"generated": {"absolute": folder}}
    return {"generated": {"from_run": Path(from_run).as_posix(), "absolute": folder}}


def recorded_candidates(run: Path, info: dict[str, Any]) -> list[Path]:
    """Where run.json's ``generated`` (``recorded_folder``) says the run's modules are: from
    the run directory first, then the absolute path; [] for a run.json without it."""
    folder = info.get("generated")
    if not isinstance(folder, dict):
        return []
    from_run, absolute = folder.get("from_run"), folder.get("absolute")
    return [p for p in (run / from_run if isinstance(from_run, str) else None,
                        Path(absolute) if isinstance(absolute, str) else None) if p]  # fmt: skip
