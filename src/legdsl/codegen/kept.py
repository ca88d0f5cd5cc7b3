"""Generated modules kept in legdsl's cache (``legdsl.files.cache_dir()/modules/``), so that a
creature is lowered through sympy once: its modules are copied from here wherever they are
missing or stale (another ``--generated`` folder, a sweep's or a notebook's fresh one, a clone
without ``generated/``) in milliseconds instead of the seconds of a compile.

An entry is named by everything a compile prints from: the checked model exactly (its source
positions too, which the comments name), the path the headers name, legdsl's own files (an
edited compiler is another compiler) and the versions of Python, sympy and mpmath; so a kept
entry is byte for byte what a compile would print now. A model holding a value this module
cannot name exactly is not kept. An entry is one file, its texts compressed and sealed with
their SHA-256, written under a temporary name and renamed: a reader sees a whole entry or
none, and one cut short or damaged is compiled again. The entries share the C libraries'
budget (``legdsl.codegen.c.cache.trim``); a cache that cannot be written only compiles.
"""

from __future__ import annotations

import contextlib
import enum
import functools
import hashlib
import importlib.metadata
import json
import sys
import zlib
from dataclasses import fields, is_dataclass
from pathlib import Path
from typing import Any

import legdsl
from legdsl.codegen.c.cache import MODULES, keep_sealed, read_kept, trim
from legdsl.files import cache_dir
from legdsl.ir.model import Model

Files = tuple[tuple[str, str], ...]  # (file name, text), as a compile returns them


class _Unnamed(Exception):
    """A value in the model that the key cannot name exactly: the model is not kept."""


def kept_entry(model: Model, label: str) -> Path | None:
    """Where a compile of ``model`` (its headers naming ``label``) is kept; None when the model
    cannot be named exactly or there is no cache."""
    try:
        named = json.dumps([_exact(model), label, _compiler(), _versions()])
        folder = cache_dir() / MODULES
    except (_Unnamed, FileNotFoundError):
        return None
    return folder / f"{hashlib.sha256(named.encode()).hexdigest()}.json.z"


def kept_files(entry: Path | None) -> Files | None:
    """The files kept at ``entry`` (``kept_entry``), or None."""
    body = None if entry is None else read_kept(entry)
    if body is None:
        return None
    try:
        listed = json.loads(zlib.decompress(body))
    except (zlib.error, ValueError):  # sealed but not ours: compiled again, and kept anew
        return None
    if not isinstance(listed, list) or not all(_is_file(f) for f in listed):
        return None
    return tuple((name, text) for name, text in listed)


def _is_file(listed: Any) -> bool:
    """Whether an entry's item is a file as kept: [name, text]."""
    return isinstance(listed, list) and len(listed) == 2 and all(isinstance(x, str) for x in listed)


def keep_files(entry: Path | None, files: Files) -> None:
    """Keep what a compile printed at ``entry`` (``kept_entry``), if the cache can be written."""
    if entry is None:
        return
    body = zlib.compress(json.dumps([list(f) for f in files]).encode())
    with contextlib.suppress(OSError):  # no room, or not ours to write: the next run compiles
        keep_sealed(body, entry)
        trim(entry.parent.parent, entry)


def _exact(value: Any) -> Any:
    """``value`` as plain data that names it exactly: every field, floats by their repr."""
    if is_dataclass(value) and not isinstance(value, type):
        return [type(value).__name__, [_exact(getattr(value, f.name)) for f in fields(value)]]
    if isinstance(value, tuple | list):
        return [_exact(x) for x in value]
    if isinstance(value, dict):
        return [[_exact(k), _exact(v)] for k, v in value.items()]
    if isinstance(value, float | enum.Enum):
        return repr(value)
    if value is None or isinstance(value, bool | int | str):
        return value
    raise _Unnamed(type(value).__name__)


@functools.cache
def _compiler() -> str:
    """The SHA-256 of legdsl's own files: the code that lowers and prints."""
    root = Path(legdsl.__file__).parent
    digest = hashlib.sha256()
    for path in sorted(root.rglob("*")):
        if path.is_file() and "__pycache__" not in path.parts:
            digest.update(path.relative_to(root).as_posix().encode() + b"\0")
            digest.update(path.read_bytes() + b"\0")
    return digest.hexdigest()


@functools.cache
def _versions() -> tuple[str, ...]:
    return (sys.version, *(importlib.metadata.version(p) for p in ("sympy", "mpmath")))
