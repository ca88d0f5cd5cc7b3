"""The grammar files, loaded once: the LALR parser and the friendly syntax-error entries.

Both live in ``grammar/`` at the top of the source tree, for people to read, and
are shipped inside the package (``legdsl/grammar/``) so an installed legdsl finds them.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import io
import os
import tomllib
from pathlib import Path
from typing import Any

import lark
from lark import Lark

from legdsl.files import cache_dir, remove, temp_sibling

_PACKAGE_GRAMMAR = Path(__file__).parents[1] / "grammar"
_SOURCE_GRAMMAR = Path(__file__).resolve().parents[3] / "grammar"


def grammar_dir() -> Path:
    """Where the grammar files are: inside the installed package, or the source tree."""
    for candidate in (_PACKAGE_GRAMMAR, _SOURCE_GRAMMAR):
        if (candidate / "legdsl.lark").is_file():
            return candidate
    raise FileNotFoundError("legdsl.lark not found in the package or the source tree")


# The parser's options; with the grammar's text and lark's version they name its kept tables.
OPTIONS: dict[str, Any] = {
    "parser": "lalr",
    "start": ["start", "value"],
    "propagate_positions": True,
    "maybe_placeholders": True,
}


@functools.cache
def lark_parser() -> Lark:
    """The LALR(1) parser of grammar/legdsl.lark, built once and its tables kept in legdsl's
    cache (``legdsl.files.cache_dir``), so that a later process loads them in a tenth of
    the time building takes (0.1 s here, a tenth of a short ``legdsl run``).

    One parser for both start symbols, a whole file (``start``, the default) and one
    ``value`` (``legdsl run --path "circle(...)"``): they share one table of parser states,
    so the friendly syntax errors, matched by state, mean the same in both.
    """
    text = (grammar_dir() / "legdsl.lark").read_text(encoding="utf-8")
    try:
        cache = cache_dir()
    except OSError:  # no HOME and no home in the user database: nowhere to keep them
        return Lark(text, **OPTIONS)
    return kept_parser(text, cache)


def kept_parser(text: str, cache: Path) -> Lark:
    """The parser of the grammar ``text``: loaded from its tables in ``cache`` if they are
    there and whole, else built and its tables kept there for the next process."""
    key = hashlib.sha256(f"{lark.__version__}\n{sorted(OPTIONS.items())}\n{text}".encode())
    kept = cache / "grammar" / f"legdsl-{key.hexdigest()[:20]}.lark-tables"
    try:
        with kept.open("rb") as f:
            return Lark.load(f)
    except Exception:  # not kept yet, no cache to read, or tables damaged (any unpickling error)
        pass  # so built again
    parser = Lark(text, **OPTIONS)
    tables = io.BytesIO()
    parser.save(tables)
    with contextlib.suppress(OSError):  # a cache that cannot be written is only slower
        kept.parent.mkdir(parents=True, exist_ok=True)
        part = temp_sibling(kept)
        try:
            part.write_bytes(tables.getvalue())
            # whole or not at all: two processes each rename a whole file (not write_atomic,
            # whose kill-test instants would then count differently by the cache's state)
            os.replace(part, kept)
        finally:
            remove(part)
    return parser


@functools.cache
def friendly_entries() -> tuple[dict[str, Any], ...]:
    """The [[error]] entries of grammar/friendly_errors.toml."""
    data = tomllib.loads((grammar_dir() / "friendly_errors.toml").read_text(encoding="utf-8"))
    return tuple(data["error"])
