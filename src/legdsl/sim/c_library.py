"""A creature's C library loaded into this process, and the ctypes twin of its ``leg_sim``.

``load_library`` builds the library (``legdsl.codegen.c.build``: cached by the hash of its
sources) or takes it from the cache, loads it with ``ctypes`` and reads the struct's layout
from the text the library exports (``leg_sim_fields``, from ``LEG_SIM_FIELDS`` in
``legdsl_sim.h``), so that the two layouts cannot differ. ``legdsl.sim.c_backend`` runs
simulations on it.
"""

from __future__ import annotations

import ctypes
import os
import re
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from legdsl.codegen.c.build import (
    DYNAMICS_FILES,
    RUNTIME,
    RUNTIME_FILES,
    BuildFailed,
    Built,
    CompilerUnusable,
    build,
    find_compiler,
    no_compiler,
    sources,
)
from legdsl.files import cache_dir, free_bytes, refused_in
from legdsl.ir.model import Model

# Every pointer of the struct is a c_void_p on the Python side (the same layout as a typed
# pointer), set from the address of a numpy array: a run's setup points some 70 of them, and
# building a typed ctypes pointer for each took a tenth of a millisecond in all.
_CTYPES = {
    "double": ctypes.c_double,
    "int64_t": ctypes.c_int64,
    "double *": ctypes.c_void_p,
    "int64_t *": ctypes.c_void_p,
    "int8_t *": ctypes.c_void_p,
    "int16_t *": ctypes.c_void_p,
    "void *": ctypes.c_void_p,
}
_DTYPES = {
    "double": np.float64, "int64_t": np.int64, "int8_t": np.int8, "int16_t": np.int16,
}  # fmt: skip


_STRUCTS: dict[bytes, type[ctypes.Structure]] = {}  # leg_sim's ctypes class, by its layout


class CLibrary:
    """A creature's loaded shared library and the ctypes twin of its ``leg_sim`` struct."""

    def __init__(self, built: Built, model: Model, load_from: Path | None = None):
        self.built = built
        self.lib = ctypes.CDLL(str(load_from or built.path))
        text = _text(self.lib, "leg_sim_fields")
        fields = []
        self.pointee: dict[str, Any] = {}  # the dtype each pointer field points to
        for decl in text.decode().split(";")[:-1]:
            match = re.fullmatch(r"(\w+(?: \*)?) (\w+)", decl.strip())
            assert match is not None, decl
            fields.append((match.group(2), _CTYPES[match.group(1)]))
            if match.group(1).endswith(" *") and match.group(1) != "void *":
                self.pointee[match.group(2)] = _DTYPES[match.group(1)[:-2]]
        # one class per layout: a switching run hands one struct to its controllers' libraries
        if text not in _STRUCTS:
            _STRUCTS[text] = type("leg_sim", (ctypes.Structure,), {"_fields_": fields})
        self.Sim = _STRUCTS[text]
        self.lib.leg_sim_size.restype = ctypes.c_int64
        if ctypes.sizeof(self.Sim) != self.lib.leg_sim_size():
            raise RuntimeError("the C backend's struct layout does not match its description")
        sizes = (ctypes.c_int64 * 4)()
        self.lib.leg_sizes(sizes)
        self.nq, self.nv, self.nb, self.nc = list(sizes)
        if (self.nq, self.nv, self.nc) != (model.nq, model.nv, len(model.contacts)):
            raise NotThisLibrary(f"the C library of {model.name} is of another model")
        for name in ("leg_run", "leg_begin"):
            getattr(self.lib, name).restype = ctypes.c_int64
            getattr(self.lib, name).argtypes = [ctypes.POINTER(self.Sim)]
        # batch.c: (template, fields, n_fields, copies, copy_stride, codes, n, next, stop); the
        # fields are rows of four int64 (offset, stride, pointer, base), legdsl.pipeline.batch's
        self.lib.leg_run_copies.restype = ctypes.c_int64
        self.lib.leg_run_copies.argtypes = [
            ctypes.POINTER(self.Sim), ctypes.c_void_p, ctypes.c_int64, ctypes.c_void_p,
            ctypes.c_int64, ctypes.c_void_p, ctypes.c_int64, ctypes.c_void_p, ctypes.c_void_p,
        ]  # fmt: skip
        # the controller's state machine runs in C (else the Python one, at each control instant)
        self.c_controller = bool(ctypes.c_int64.in_dll(self.lib, "leg_has_c_controller").value)


class NotThisLibrary(RuntimeError):
    """A library in the cache under these sources' name that was not built from them (put
    there by hand, a mix-up): its stamps are another model's or controller's."""


def _text(lib: ctypes.CDLL, symbol: str) -> bytes:
    """The text of the ``const char symbol[]`` that ``lib`` exports."""
    text = ctypes.cast(ctypes.addressof(ctypes.c_char.in_dll(lib, symbol)), ctypes.c_char_p).value
    assert text is not None
    return text


def _stamps_match(lib: ctypes.CDLL, files: dict[str, str]) -> bool:
    """Whether the fingerprints ``lib`` carries are those its C sources print."""
    for file, symbol in (("dynamics.c", "legdsl_model_fingerprint"),
                         ("control.c", "legdsl_control_fingerprint")):  # fmt: skip
        printed = re.search(rf'{symbol}\[\] = "(\w+)"', files.get(file, ""))
        if printed is not None and _text(lib, symbol) != printed.group(1).encode():
            return False
    return True


def _loaded_afresh(built: Built, model: Model) -> CLibrary:
    """``built`` loaded through a name of its own: the system's loader gives the library it
    loaded before under the same name again (the wrong one, just replaced)."""
    alias = built.path.with_name(f".{built.path.stem}-{os.getpid()}-afresh.so")
    os.link(built.path, alias)
    try:
        return CLibrary(built, model, load_from=alias)
    finally:
        alias.unlink(missing_ok=True)  # mapped: the code stays


_LOADED: dict[Path, CLibrary] = {}
_BY_STAT: dict[tuple[Any, ...], CLibrary] = {}
_TRUSTED: dict[tuple[str, str], CLibrary] = {}  # the last library found for (name, folder)


def available() -> str | None:
    """None when the C backend can run here, else why not (one line)."""
    return no_compiler()


def load_library(
    model: Model,
    generated_dir: Path,
    controller: str | None = None,
    trust: bool = False,
    starting: Callable[[str], None] | None = None,
) -> CLibrary:
    """Build (or take from the cache) and load the library of ``generated_dir``'s C, with the
    controller's state machine in C when it has one. With ``trust`` (the runs of one batch), a
    library this process has loaded for these files is given again without looking at them.
    ``starting`` is told when the compiler is about to run (seconds, for a large creature)."""
    name = model.name if controller is None else f"{model.name}-{controller}"
    trusted = (name, str(generated_dir))
    if trust and trusted in _TRUSTED:
        return _TRUSTED[trusted]
    # Hashing the sources takes milliseconds (a batch of short runs would feel it): within a
    # process, files whose size and modification time are unchanged give the library again.
    files = [generated_dir / f for f in DYNAMICS_FILES]
    if controller is not None:
        files.append(generated_dir / f"control_{controller}.c")
    files += [RUNTIME / f for f in RUNTIME_FILES]
    stats = tuple((str(f), f.stat().st_mtime_ns, f.stat().st_size) for f in files)
    key = (name, stats, find_compiler())
    if key in _BY_STAT:
        _TRUSTED[trusted] = _BY_STAT[key]
        return _BY_STAT[key]
    files_text = sources(generated_dir, controller)
    built = _build(name, files_text, starting)
    if built.path not in _LOADED:
        try:
            library = CLibrary(built, model)
            if not _stamps_match(library.lib, files_text):
                raise NotThisLibrary(
                    f"the C library of {name} is of another creature or controller"
                )
            _LOADED[built.path] = library
        except NotThisLibrary:  # built again from the sources: it was trusted by its name
            built.path.unlink(missing_ok=True)
            built = _build(name, files_text, starting)
            _LOADED[built.path] = _loaded_afresh(built, model)
        except OSError:
            if built.path.exists():
                raise  # e.g. a cache on a file system that may not map code (noexec)
            built = _build(name, files_text, starting)  # another process trimmed the cache
            _LOADED[built.path] = CLibrary(built, model)
        except (ValueError, AttributeError) as e:  # a symbol missing: not built as legdsl's C
            built.path.unlink(missing_ok=True)  # so that no later run loads it again
            by = getattr(find_compiler(), "path", "the C compiler")
            raise CompilerUnusable(
                f"the library {by} built lacks legdsl's symbols ({e}); "
                "set LEGDSL_CC to a C compiler (gcc, clang)"
            ) from None
    _BY_STAT[key] = _TRUSTED[trusted] = _LOADED[built.path]
    return _LOADED[built.path]


def _build(
    name: str, files: dict[str, str], starting: Callable[[str], None] | None = None
) -> Built:
    """``build``, with a compiler that failed for want of room in the cache (it says "No space
    left on device") as the ``OSError`` of a full cache: legdsl's cause to say what to free,
    not a bug in its C (nor a compiler to install)."""
    try:
        return build(name, files, starting=starting)
    except (BuildFailed, CompilerUnusable) as e:
        disk = refused_in(str(e))
        if disk is None:
            raise
        why = os.strerror(disk)
        if _room(cache_dir()) and not _room(Path(tempfile.gettempdir())):
            why += f" in {tempfile.gettempdir()}, where the compiler writes its temporary files"
        raise OSError(disk, why, str(cache_dir())) from e


def _room(folder: Path) -> bool:
    """Whether ``folder``'s disk has a megabyte free (or cannot say)."""
    free = free_bytes(folder)
    return free is None or free >= 1 << 20


def address(array: np.ndarray) -> int:
    """The address of a contiguous array, for a pointer of the struct."""
    assert array.flags.c_contiguous
    return int(array.ctypes.data)
