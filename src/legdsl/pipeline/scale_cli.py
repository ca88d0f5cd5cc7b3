"""The ``legdsl scale`` command: a creature and its controllers dynamically scaled (Table 1)."""

from __future__ import annotations

import argparse
import os
import re
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

from legdsl.check.source import check_file, check_tree, load_uses, use_path
from legdsl.check.values import MAX_NAME, did_you_mean, stdlib_name
from legdsl.files import write_atomic
from legdsl.ir.model import Model
from legdsl.lang import ast
from legdsl.lang.errors import Diagnostics, LegError, UsageError
from legdsl.lang.parser import parse, parse_file
from legdsl.lang.scaling import (
    DEFAULT_LOOKAHEAD,
    format_number,
    path_decls,
    reached_quantities,
    scale_name,
    scale_source,
    scaled_text,
    scales_anything,
)
from legdsl.pipeline.options import check_output_file
from legdsl.pipeline.outputs import is_stream, made_note, named_as, new_directory
from legdsl.pipeline.scaled import scale_factor


def add_scale_parser(sub: Any) -> Callable[[argparse.Namespace], int]:
    sc = sub.add_parser(
        "scale",
        help="write a creature and its controllers dynamically scaled (Table 1)",
        description="Write FILE with every quantity of dimension kg^a m^b s^c rad^d multiplied by "
        "L^(3a + b + c/2) (lengths L, masses L^3, times L^(1/2), ...; bare numbers and angles as "
        "they were), comments and layout kept, each creature renamed NAME_xL (or as --name "
        "says), and a simulation block with the scaled integration step, control interval and "
        "record rate. OUT is written only once it passes legdsl check. See docs/scaling.md.",
        epilog="Example: legdsl scale creatures/kangaroo.leg --by 2 -o kangaroo_x2.leg",
    )
    sc.add_argument("file", metavar="FILE", help="a .leg file")
    sc.add_argument(
        "--by", type=scale_factor, required=True, metavar="L", help="the length factor L"
    )
    sc.add_argument("-o", "--output", required=True, metavar="OUT", help="the .leg file to write")
    sc.add_argument(
        "--name",
        action="append",
        default=[],
        metavar="NEW",
        help="the scaled creature's name (default NAME_xL, its start cut to fit 64 characters); "
        "OLD=NEW names one of a file's several creatures (repeat it for each)",
    )
    return cmd_scale


def cmd_scale(args: argparse.Namespace) -> int:
    if not 0 < args.by < float("inf"):
        raise UsageError(f"--by {args.by:g}: the scale factor is a positive, finite number")
    if is_stream(args.output):  # the scaled file is checked where it is written, uses and all
        raise UsageError(f"-o {args.output}: legdsl scale writes a .leg file and checks it there "
                         "(its 'use' paths are relative to it); name a file, e.g. -o scaled.leg")  # fmt: skip
    out = named_as(check_output_file(args.output, "-o"), "-o", (".leg",), "a .leg file")
    tree, text = parse_file(args.file)  # read as the checker reads it (a byte-order mark, CRLF)
    used: dict[str, str] = {}  # the files it uses, by path (a missing one is check_file's)
    load_uses(tree, Diagnostics(used), used)
    _not_an_input(out, [Path(p) for p in used], Path(args.file), args.by)
    if args.name and not tree.creatures:
        raise UsageError(f"--name {args.name[0]}: {args.file} has no creature to name")
    if not tree.creatures and (tree.actions or tree.shared):
        # a file of actions and shared parts, for a scaled file to 'use': checked where used
        _write(out, scale_source(text, args.by, args.file, out))
        print(
            f"wrote {out} (the actions and shared parts of {args.file}, scaled by {args.by:g}); "
            "point the scaled creature's 'use' at it"
        )
        return 0
    check_file(args.file)
    names = _new_names([c.name.name for c in tree.creatures], args.name, args.by, args.file)
    scaled = scale_source(text, args.by, args.file, out, names)
    models = _checked(scaled, out)  # before it is written: a file that fails is never left
    _write(out, scaled)
    written = ", ".join(m.name for m in models)
    print(f"wrote {out} (creature {written}, scaled by {args.by:g}); legdsl check passes on it")
    for old, new in names.items():
        if new != f"{old}{_suffix(args.by)}" and not _given(old, args.name, len(names)):
            print(
                f"legdsl: note: creature {old} scaled is named {new}: {old}{_suffix(args.by)} "
                f"would pass {MAX_NAME} characters; choose its name with --name "
                f"{'NEW' if len(names) == 1 else f'{old}=NEW'}",
                file=sys.stderr,
            )
    if path_decls(tree) and args.by != 1:
        print(f"legdsl: note: {_lookahead_note(written, args.file, args.by)}", file=sys.stderr)
    used_trees = [parse(text, path) for path, text in used.items()]
    users = _users([tree, *used_trees])
    library = _library_note(tree, used, used_trees, written, args.file, args.by)
    if library is not None:
        print(f"legdsl: note: {library}", file=sys.stderr)
    for path in _unscaled(used, Path(args.file)):
        user = users[Path(path).resolve()]
        by = "it" if user == Path(args.file).resolve() else _readable(str(user))
        point = "the 'use' at it" if by == "it" else f"the 'use' in {by} at it (a copy, for OUT)"
        print(
            f"legdsl: note: {_readable(path)}, which {by} uses, is not scaled and has numbers "
            f"with units: scale it too (legdsl scale {_readable(path)} --by {args.by:g} -o "
            f"OUT.leg) and point {point}, unless its numbers are meant for any size",
            file=sys.stderr,
        )
    return 0


def _lookahead_note(creatures: str, file: str, scale: float) -> str:
    """A ``--path`` given to the scaled file without a lookahead gets the default, 1 m, which
    the scaled file cannot carry (a ``path NAME`` without a shape has no lookahead to scale):
    said, with the lookahead that follows the original's motion scaled."""
    by, default = format_number(scale), format_number(DEFAULT_LOOKAHEAD)
    return (
        f"a --path given to {creatures} without a lookahead follows {default} m ahead, the "
        f"default for a creature of about a metre, not scaled; give it 'lookahead = "
        f"{format_number(DEFAULT_LOOKAHEAD * scale)} m' ({default} m scaled by {by}) to "
        f"follow it as {file} does "
        f"with the path scaled down (legdsl run {file} --scale {by} makes that the default)"
    )


def _library_note(
    tree: ast.SourceFile,
    used: dict[str, str],
    used_trees: list[ast.SourceFile],
    creatures: str,
    file: str,
    scale: float,
) -> str | None:
    """The standard library's numbers that scaling would change, in the actions and parts the
    file reaches (``reached_quantities``): OUT uses them as written, for the unscaled size."""
    if scale == 1:
        return None
    reached = reached_quantities(tree, used_trees)
    told = []
    for name, span, dim in reached:
        library = stdlib_name(Path(span.file))
        if library is None:  # a file of the user's own: its note is below
            continue
        line = used[span.file].splitlines()[span.line - 1]
        written = line[span.col - 1 : span.end_col - 1] if span.end_line == span.line else ""
        scaled = scaled_text(written, dim, scale)
        if scaled is None:  # a number told by its place alone
            told.append(f"a number in {name} ({library}:{span.line})")
        else:
            told.append(f"{written} in {name} ({library}:{span.line}; scaled, {scaled})")
    if not told:
        return None
    return (
        f"{creatures} uses numbers of the standard library, which is not scaled: "
        f"{', '.join(told)}; they stay as written, for the unscaled size, so its run can "
        "part from the original's run scaled, the more the further L is from 1 "
        f"(docs/scaling.md, 'Why it parts'); legdsl run {file} --scale {format_number(scale)} "
        "is the original's run scaled, these numbers included"
    )


def _write(out: Path, text: str) -> None:
    """``text`` written to ``out``, a folder it makes said as every ``-o`` says it
    (``made directory sc/new/``), before the "wrote" line."""
    made = new_directory(out)
    write_atomic(out, text)
    if made is not None:
        print(made_note(made, out))


def _users(trees: list[ast.SourceFile]) -> dict[Path, Path]:
    """The file (of ``trees``: FILE first, then those it uses) that uses each used file
    first: FILE itself where it does, else the used file through which it is reached."""
    users: dict[Path, Path] = {}
    for tree in trees:
        for use in tree.uses:
            users.setdefault(use_path(tree, use).resolve(), Path(tree.path).resolve())
    return users


def _suffix(scale: float) -> str:
    """``_xL``, what ``scale_name`` puts after a creature's name."""
    return scale_name("", scale)


def _given(old: str, given: list[str], creatures: int) -> bool:
    """Whether ``--name`` named the scaled ``old``."""
    return any(g.partition("=")[0] == old if "=" in g else creatures == 1 for g in given)


def _new_names(creatures: list[str], given: list[str], scale: float, file: str) -> dict[str, str]:
    """Each creature's scaled name: ``--name NEW`` (a file of one creature) or ``--name
    OLD=NEW``, checked as the checker checks a creature's name, else NAME_xL cut to fit."""
    names: dict[str, str] = {}
    for text in given:
        old, sep, new = text.partition("=")
        if not sep:  # --name NEW
            if len(creatures) > 1:
                raise UsageError(
                    f"--name {text}: {file} has {len(creatures)} creatures "
                    f"({', '.join(creatures)}); say which with --name OLD=NEW, e.g. --name "
                    f"{creatures[0]}={text}"
                )
            old, new = creatures[0], text
        if old not in creatures:
            raise UsageError(
                f"--name {text}: {file} has no creature '{old}' (its creatures: "
                f"{', '.join(creatures)}){did_you_mean(old, creatures)}"
            )
        if old in names:
            raise UsageError(f"--name {text}: creature {old} is named twice (also {names[old]})")
        names[old] = _valid_name(new, text)
        if new in creatures:  # the scaled creature would take an unscaled one's generated/NEW/
            again = f"{old}={new}_big" if sep else f"{new}_big"
            raise UsageError(
                f"--name {text}: {new} is the name of {file}'s creature {new}, unscaled; a scaled "
                f"creature needs a name of its own, or its generated code and runs are that "
                f"creature's (generated/{new}/): give another, e.g. --name {again}"
            )
    for old in creatures:
        names.setdefault(old, scale_name(old, scale))
    seen: dict[str, str] = {}
    for old, new in names.items():
        if new in seen:
            which = [o for o in (seen[new], old) if not _given(o, given, len(creatures))]
            if len(which) < 2 and all(names[o] == f"{o}{_suffix(scale)}" for o in which):
                _name_taken(seen[new], old, new, given, len(creatures))
            raise UsageError(
                f"creatures {seen[new]} and {old} of {file} would both be named {new} once "
                f"scaled (a name has at most {MAX_NAME} characters); name "
                f"{'them' if len(which) > 1 else 'one'} with "
                + " ".join(f"--name {o}=NEW" for o in (which or [old]))
            )
        seen[new] = old
    return names


def _name_taken(first: str, second: str, new: str, given: list[str], creatures: int) -> None:
    """Two creatures named ``new`` once scaled, neither cut to fit: a ``--name`` gave one the
    other's name (it was told as a cut to 64 characters, which it is not)."""
    named = [o for o in (first, second) if _given(o, given, creatures)]
    other = second if named[0] == first else first
    how = "given with --name too" if len(named) > 1 else "its name scaled"
    raise UsageError(
        f"--name {named[0]}={new}: {new} is also creature {other}'s name ({how}); two "
        f"creatures of a file need two names: give {named[0]} another"
    )


def _valid_name(new: str, given: str) -> str:
    """``--name``'s NEW, as the checker takes a creature's name, else a ``UsageError``."""
    what = (
        "a creature's name is a letter or _ followed by letters, digits and _ "
        f"(at most {MAX_NAME} characters), e.g. --name hopper_big"
    )
    if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", new):
        raise UsageError(f"--name {given}: {what}")
    if len(new) > MAX_NAME:
        raise UsageError(
            f"--name {given}: this name is {len(new)} characters long; a creature's name has at "
            f"most {MAX_NAME} (it names files, such as generated/NAME/)"
        )
    try:
        (creature,) = parse(f"creature {new} {{ planar }}", "--name").creatures
    except (LegError, ValueError):
        creature = None
    if creature is None or creature.name.name != new:
        raise UsageError(f"--name {given}: '{new}' is a word of the language; {what}")
    return new


def _checked(text: str, out: Path) -> list[Model]:
    """The scaled text checked as ``legdsl check OUT`` would check it (its 'use' paths from
    OUT's folder), before anything is written: a mistake is shown at the line OUT would have."""
    try:
        tree = parse(text, str(out), recover=True)
        return check_tree(tree, text, out)
    except LegError as e:
        print(e.render(), file=sys.stderr)
        raise UsageError(
            f"-o {out}: not written: the scaled file would not pass legdsl check (above, at "
            "the lines it would have)"
        ) from None


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
