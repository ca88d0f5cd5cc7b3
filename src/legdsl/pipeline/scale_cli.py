"""The ``legdsl scale`` command: a creature and its controllers dynamically scaled (Table 1)."""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

from legdsl.check.source import check_file, load_uses
from legdsl.check.values import stdlib_name
from legdsl.files import write_atomic
from legdsl.lang.errors import Diagnostics, UsageError
from legdsl.lang.parser import parse_file
from legdsl.lang.scaling import scale_name, scale_source, scales_anything
from legdsl.pipeline.options import check_output_file
from legdsl.pipeline.outputs import is_stream, named_as
from legdsl.pipeline.scaled import scale_factor


def add_scale_parser(sub: Any) -> Callable[[argparse.Namespace], int]:
    sc = sub.add_parser(
        "scale",
        help="write a creature and its controllers dynamically scaled (Table 1)",
        description="Write FILE with every quantity of dimension kg^a m^b s^c rad^d multiplied by "
        "L^(3a + b + c/2) (lengths L, masses L^3, times L^(1/2), ...; bare numbers and angles as "
        "they were), comments and layout kept, each creature renamed NAME_xL, and a simulation "
        "block with the scaled integration step, control interval and record rate. See docs/scaling.md.",
        epilog="Example: legdsl scale creatures/kangaroo.leg --by 2 -o kangaroo_x2.leg",
    )
    sc.add_argument("file", metavar="FILE", help="a .leg file")
    sc.add_argument(
        "--by", type=scale_factor, required=True, metavar="L", help="the length factor L"
    )
    sc.add_argument("-o", "--output", required=True, metavar="OUT", help="the .leg file to write")
    return cmd_scale


def cmd_scale(args: argparse.Namespace) -> int:
    if not 0 < args.by < float("inf"):
        raise UsageError(f"--by {args.by}: the scale factor is a positive, finite number")
    if is_stream(args.output):  # the scaled file is checked where it is written, uses and all
        raise UsageError(f"-o {args.output}: legdsl scale writes a .leg file and checks it there "
                         "(its 'use' paths are relative to it); name a file, e.g. -o scaled.leg")  # fmt: skip
    out = named_as(check_output_file(args.output, "-o"), "-o", (".leg",), "a .leg file")
    tree, text = parse_file(args.file)  # read as the checker reads it (a byte-order mark, CRLF)
    used: dict[str, str] = {}  # the files it uses, by path (a missing one is check_file's)
    load_uses(tree, Diagnostics(used), used)
    _not_an_input(out, [Path(p) for p in used], Path(args.file), args.by)
    if not tree.creatures and (tree.actions or tree.shared):
        # a file of actions and shared parts, for a scaled file to 'use': checked where used
        write_atomic(out, scale_source(text, args.by, args.file, out))
        print(
            f"wrote {out} (the actions and shared parts of {args.file}, scaled by {args.by:g}); "
            "point the scaled creature's 'use' at it"
        )
        return 0
    check_file(args.file)
    write_atomic(out, scale_source(text, args.by, args.file, out))
    names = ", ".join(m.name for m in check_file(out))
    print(f"wrote {out} (creature {names}, scaled by {args.by:g}); legdsl check passes on it")
    for path in map(_readable, _unscaled(used, Path(args.file))):
        print(
            f"legdsl: note: {path}, which it uses, is not scaled and has numbers with units: "
            f"scale it too (legdsl scale {path} --by {args.by:g} -o OUT.leg) and point the "
            "'use' at it, unless its numbers are meant for any size",
            file=sys.stderr,
        )
    return 0


def _unscaled(used: dict[str, str], source: Path) -> list[str]:
    """The files of the user's own among those used (by path, with their text), holding
    numbers that scaling would change (the standard library's hold none)."""
    return [
        path
        for path, text in used.items()
        if stdlib_name(Path(path)) is None
        and Path(path).resolve() != source.resolve()
        and scales_anything(text, path)
    ]


def _readable(path: str) -> str:
    """A used file as a user reads it: ``a/b/../../c.leg`` (a 'use' followed from another
    folder) resolved, relative to the current directory when that is shorter."""
    full = Path(path).resolve()
    try:
        relative = os.path.relpath(full, Path.cwd().resolve())
    except ValueError:  # another drive
        return str(full)
    return relative if len(relative) < len(str(full)) else str(full)


def _not_an_input(out: Path, used: list[Path], source: Path, scale: float) -> None:
    """-o naming FILE or a file it uses is refused: the scaled text replaced the user's own."""
    for given in (source, *used):
        if out.exists() and given.exists() and out.samefile(given):
            raise UsageError(
                f"-o {out}: this is {given}, an input that writing would destroy; give another "
                f"file name, such as {scale_name(source.stem, scale)}.leg"
            )
