"""``--path``: a path given to a run on the command line, as a shape in the ``.leg`` file's
syntax or a file of waypoints, checked as the file's own paths are."""

from __future__ import annotations

import re
import stat
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path

from legdsl.check.paths import check_path
from legdsl.ir.paths import PathSpec
from legdsl.ir.waypoints import read_waypoints
from legdsl.lang import ast
from legdsl.lang.errors import Diagnostics, LegError, UsageError
from legdsl.lang.parser import parse_value


def parse_path_option(text: str) -> PathSpec:
    """``--path [NAME=]SHAPE`` (the .leg file's syntax) or ``--path FILE.csv`` (x,y per line).

    Without ``NAME=`` the name is empty: the controller's only path (see
    ``legdsl.sim.machine.resolve_paths``).
    """
    match = re.match(r"\s*([A-Za-z_][A-Za-z0-9_]*)\s*=(?!=)", text)
    name, shape = ("", text) if match is None else (match.group(1), text[match.end() :])
    # a waypoints file: named .csv or .txt (W.CSV too), or any file there without a shape's '('
    file = Path(shape.strip())
    named = re.fullmatch(r"\s*[^()]*\.(csv|txt)\s*", shape, re.IGNORECASE)
    if named or ("(" not in shape and shape.strip() and file.exists()):  # a directory: told
        if not file.is_file():
            raise UsageError(f"--path {text}: {_not_a_file(file)}; give a file of 'x,y' lines, "
                             "or a shape, as in --path 'circle(center = (0, 5) m, radius = 5 m)'")  # fmt: skip
        return replace(read_waypoints(file, name), lookahead_default=True)
    if not shape.strip():
        raise UsageError(
            f"--path {text!r} gives no path: write a shape, as in --path 'circle(center = "
            "(0, 5) m, radius = 5 m)', or a waypoints file, as in --path route.csv"
        )
    # parse the shape where it stands in the option, so the caret points into it
    padded = " " * (len(text) - len(shape)) + shape
    try:
        value = parse_value(padded, "--path")
    except LegError as e:  # the option's text, not a file, ends: said so ('circle(')
        said = [replace(d, message=d.message.replace("end of the file", "end of the --path value"))
                for d in e.diagnostics]  # fmt: skip
        raise LegError(said, e.sources) from None
    diag = Diagnostics({"--path": text})
    spec = check_path(name, value, diag)
    diag.raise_if_any()
    assert spec is not None
    written = isinstance(value, ast.Call) and any(
        a.keyword is not None and a.keyword.name == "lookahead" for a in value.args
    )
    return replace(spec, lookahead_default=not written)


def _not_a_file(file: Path) -> str:
    """What ``file``, not a regular file, is: none, a directory, or another kind (a device such
    as /dev/null, a pipe, a socket), which is not read (a pipe could wait for ever)."""
    try:
        mode = file.stat().st_mode
    except FileNotFoundError:
        return f"no such file {file}"
    except OSError as e:
        return f"{file} cannot be read ({e.strerror or e})"
    if stat.S_ISDIR(mode):
        return f"{file} is a directory"
    kinds = ((stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
             (stat.S_ISFIFO, "a pipe"), (stat.S_ISSOCK, "a socket"))  # fmt: skip
    kind = next((said for test, said in kinds if test(mode)), "not a regular file")
    return f"{file} is {kind}, not a file of waypoints"


def path_specs(paths: str | PathSpec | Sequence[str | PathSpec]) -> list[PathSpec]:
    """A run's paths, one or many, each given as ``--path`` text or already a ``PathSpec``."""
    given = [paths] if isinstance(paths, str | PathSpec) else list(paths)
    return [p if isinstance(p, PathSpec) else parse_path_option(p) for p in given]
