"""The grammar files, loaded once: the LALR parser and the friendly syntax-error entries.

Both live in ``grammar/`` at the top of the source tree, for people to read, and
are shipped inside the package (``legdsl/grammar/``) so an installed legdsl finds them.
"""

from __future__ import annotations

import functools
import tomllib
from pathlib import Path
from typing import Any

from lark import Lark

_PACKAGE_GRAMMAR = Path(__file__).parents[1] / "grammar"
_SOURCE_GRAMMAR = Path(__file__).resolve().parents[3] / "grammar"


def grammar_dir() -> Path:
    """Where the grammar files are: inside the installed package, or the source tree."""
    for candidate in (_PACKAGE_GRAMMAR, _SOURCE_GRAMMAR):
        if (candidate / "legdsl.lark").is_file():
            return candidate
    raise FileNotFoundError("legdsl.lark not found in the package or the source tree")


@functools.cache
def lark_parser() -> Lark:
    """The LALR(1) parser of grammar/legdsl.lark (built once; it takes a fraction of a second).

    One parser for both start symbols, a whole file (``start``, the default) and one
    ``value`` (``legdsl run --path "circle(...)"``): they share one table of parser states,
    so the friendly syntax errors, matched by state, mean the same in both.
    """
    text = (grammar_dir() / "legdsl.lark").read_text(encoding="utf-8")
    return Lark(
        text,
        parser="lalr",
        start=["start", "value"],
        propagate_positions=True,
        maybe_placeholders=True,
    )


@functools.cache
def friendly_entries() -> tuple[dict[str, Any], ...]:
    """The [[error]] entries of grammar/friendly_errors.toml."""
    data = tomllib.loads((grammar_dir() / "friendly_errors.toml").read_text(encoding="utf-8"))
    return tuple(data["error"])
