"""The checker's entry: a ``.leg`` file and the files it uses, parsed and checked into models."""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path
from typing import Protocol, TypeVar

from legdsl.check.controller import check_controllers
from legdsl.check.creature import CreatureChecker
from legdsl.check.scene import check_scenes
from legdsl.check.templates import GIVEN_A_VALUE
from legdsl.check.used_controllers import UsedControllers
from legdsl.check.values import STDLIB, shown_path, stdlib_name
from legdsl.ir.model import Model
from legdsl.lang import ast
from legdsl.lang.errors import Diagnostic, Diagnostics, LegError, Span
from legdsl.lang.parser import parse_file

Def = TypeVar("Def", ast.ActionDef, ast.SharedDecl)  # what a used file defines by name


def check_file(path: str | Path) -> list[Model]:
    """Parse and check a .leg file; every creature in it becomes a model with its controllers."""
    tree, text = parse_file(path, recover=True)
    return check_tree(tree, text, path)


def check_tree(tree: ast.SourceFile, text: str, path: str | Path) -> list[Model]:
    """Check a file already parsed (``parse_file(path)`` gave ``tree`` and ``text``), so that a
    caller that keeps the syntax tree (the compile driver) parses the file only once."""
    sources = {str(path): text}
    diag = Diagnostics(sources)
    diag.items.extend(tree.pending)
    before = len(diag.items)
    library, shared, used = load_uses(tree, diag, sources)
    unread = diag.items[before:]  # used files missing or not read whole
    models = []
    # parts declared with a mistake reported there: a controller naming one is not an error
    broken: dict[str, set[str]] = {}
    seen: dict[str, Span] = {}
    for decl in tree.creatures:
        first = seen.setdefault(decl.name.name, decl.name.span)
        if first != decl.name.span:  # both would be generated/NAME/, runs/NAME/
            diag.error(
                decl.name.span,
                f"creature '{decl.name.name}' is defined twice (first at {first}); give each "
                "creature of a file a name of its own",
            )
            continue
        checker = CreatureChecker(decl, diag, str(path))
        model = checker.check()
        if model is not None:
            models.append(model)
            broken[model.name] = checker.unmade(model)
    if not tree.creatures:
        empty = "the file is empty" if not text.strip() else "no creature in this file"
        diag.error(tree.span, f"{empty}: write 'creature NAME {{ ... }}'")
    models = check_controllers(tree, models, library, shared, diag, broken, used)
    models = check_scenes(tree, models, diag)
    diag.items = _once_per_place(_unmade_names(_without_echoes(diag.items, tree.pending)))
    # what a used file would have defined is unknown: its absence is no news; and the names
    # of a part no file defines (a missing file's, or a misspelt 'include') are not told
    # unknown one by one, as a misspelt 'extends' leaves its controller unchecked
    blind = _blind_spans(shared, used)
    if unread or blind:
        diag.items = [
            d
            for d in diag.items
            if d in unread or not ((unread and _undefined(d.message)) or _unseen(d, blind))
        ]
    diag.raise_if_any()
    return models


def _undefined(message: str) -> bool:
    """A mistake that a used file which could not be read may be the cause of."""
    known = ("unknown action '", "unknown shared part '", "unknown controller '")
    # a controller extending a used one of its own name: 'extends itself' while unread
    return message.startswith(known) or message.endswith("or 'use' a file that has it")


def _blind_spans(shared: list[ast.SharedDecl], used: UsedControllers) -> list[Span]:
    """The controllers and shared parts, of the file and the files it uses, that include a
    shared part no file read defines (a missing used file's, say), directly or through
    another part or a base controller (its own file's, or a used one's): the names they use
    may be that part's declarations."""
    defined = {part.name.name for part in shared}
    trees = list(used.trees.values())
    parts = {p.name.name: _included(p.items) for tree in trees for p in tree.shared}
    controllers = [c for tree in trees for c in tree.controllers]
    included = {id(c): _included(c.items) for c in controllers}
    blind_parts = {n for names in (*parts.values(), *included.values()) for n in names}
    blind_parts -= defined
    if not blind_parts:
        return []
    bases = {id(c): _bases(c, used) for c in controllers}
    blind: set[int] = set()  # the blind controllers, by id
    while True:  # parts including blind parts, controllers extending blind ones
        more = {n for n, names in parts.items() if names & blind_parts} - blind_parts
        more_controllers = {
            id(c)
            for c in controllers
            if included[id(c)] & blind_parts or any(id(b) in blind for b in bases[id(c)])
        } - blind
        if not more and not more_controllers:
            break
        blind_parts |= more
        blind |= more_controllers
    spans = [c.span for c in controllers if id(c) in blind]
    spans += [p.span for tree in trees for p in tree.shared if p.name.name in blind_parts]
    if blind:  # a scene's set may name what such a controller would declare
        spans += [scene.span for tree in trees for scene in tree.scenes]
    return spans


def _bases(decl: ast.ControllerDecl, used: UsedControllers) -> list[ast.ControllerDecl]:
    """The controllers ``decl`` may extend: its file's of that name, else the nearest used
    file's (as ``control_shared`` resolves them)."""
    if decl.base is None:
        return []
    own = [c for c in used.own(decl.span.file) if c.name.name == decl.base.name and c is not decl]
    found = own or used.find(decl.span.file, decl.base.name)
    return found if isinstance(found, list) else []


def _included(items: tuple[object, ...]) -> set[str]:
    return {
        ident.name for item in items if isinstance(item, ast.IncludeDecl) for ident in item.names
    }


def _unseen(found: Diagnostic, blind: list[Span]) -> bool:
    """A name reported unknown where it may be declared by a shared part never read."""
    words = ("unknown name '", "no controller of this scene has an input or parameter '")
    if (
        not found.message.startswith(words)
        and ": no controller of the table has an input '" not in found.message
    ):
        return False
    span = found.span
    return any(b.file == span.file and b.line <= span.line <= b.end_line for b in blind)


def _once_per_place(found: list[Diagnostic]) -> list[Diagnostic]:
    """A body or contact the creature lacks, or a path no controller declares, is the same
    mistake in every controller that reads it (the same line of a shared part or a base
    controller): told once at each place."""
    seen: set[tuple[Span, str]] = set()  # a span's equality leaves out the controller
    kept = []
    for d in found:
        lacking = d.message.startswith("creature '") and "' has no " in d.message
        if lacking or "reads a path, declared with 'path " in d.message:
            key = (d.span, d.message.removesuffix(d.span.within))
            if key in seen:
                continue
            seen.add(key)
        kept.append(d)
    return kept


def _unmade_names(found: list[Diagnostic]) -> list[Diagnostic]:
    """Where a template's name could not be made (``seg_P`` with ``P = 0``, a value), that
    is the mistake told there: that no body or joint has the name as written is no news."""
    unmade = {d.span for d in found if GIVEN_A_VALUE in d.message}
    return [d for d in found if d.span not in unmade or GIVEN_A_VALUE in d.message]


def _without_echoes(found: list[Diagnostic], repaired: tuple[Diagnostic, ...]) -> list[Diagnostic]:
    """The checker's findings without those on a misspelt unit the parser already reported
    (the unit read in its place may not be what was meant)."""

    def overlaps(a: Span, b: Span) -> bool:
        return (
            a.file == b.file
            and a.line <= b.end_line
            and b.line <= a.end_line
            and (a.line != b.line or (a.col < b.end_col and b.col < a.end_col))
        )

    return [
        d for d in found if d in repaired or not any(overlaps(d.span, r.span) for r in repaired)
    ]


def load_uses(
    tree: ast.SourceFile, diag: Diagnostics, sources: dict[str, str]
) -> tuple[list[ast.ActionDef], list[ast.SharedDecl], UsedControllers]:
    """Named actions and shared controller parts from the file itself and the files it
    ``use``s, and the files those use; and those files' controllers, which a controller
    may extend.

    ``use raibert`` names a file of the standard library, ``use "lib/gaits.leg"`` a file
    relative to the one that says it. Each file is read once however often it is used; a
    file that uses itself, directly or through others, is an error naming the chain. The
    nearer file wins (the fewest 'use's away): a file's own actions override those of the
    files it uses, and those of a file it uses override those of a file used through another.
    """
    root = Path(tree.path).resolve()
    loaded = {root}
    files: dict[Path, ast.SourceFile] = {}  # each used file, in the order it was read
    edges: dict[Path, list[Path]] = {root: []}  # what each file uses

    def name(path: Path) -> str:
        """A file in a chain: the stdlib's by name, others relative to the first file's folder."""
        library = stdlib_name(path)
        if library is not None:
            return library
        try:
            return path.relative_to(root.parent).as_posix()
        except ValueError:
            return path.as_posix()

    def visit(current: ast.SourceFile, chain: tuple[Path, ...], first: ast.UseDecl | None) -> None:
        for use in current.uses:
            path = use_path(current, use)
            if path.is_file():
                edges[chain[-1]].append(path.resolve())
            at = first or use  # a mistake in a used file is reported at the user's own 'use'
            if path.is_file() and path.resolve() in chain:
                names = [name(p) for p in (*chain, path.resolve())]
                diag.error(
                    at.span,
                    f"'use' makes a cycle: {' -> '.join(names)}; a file cannot use itself, "
                    "directly or through the files it uses",
                )
                continue
            if path.is_file() and path.resolve() in loaded:
                continue
            if not path.is_file():
                known = sorted(p.stem for p in STDLIB.glob("*.leg"))
                where = (
                    "" if first is None else f" (asked for in {name(Path(current.path).resolve())})"
                )
                advice = (
                    _not_there(use.target, path, Path(current.path))
                    if _is_a_path(use)
                    else f"the standard library has {', '.join(known) or 'nothing'}; other "
                    "files are named by a path in quotes"
                )
                if path.exists():  # a folder or a device (/dev/zero): there, but not a file
                    kind = "a folder" if path.is_dir() else "not a file (a device or a pipe)"
                    advice = f"{shown_path(path)} is {kind}; 'use' takes a .leg file"
                diag.error(
                    at.span,
                    f"cannot {'use' if path.exists() else 'find'} '{use.target}'"
                    f"{'' if path.exists() else ' to use'}{where}: {advice}",
                )
                continue
            try:
                lib, text = parse_file(path, recover=True)
            except LegError as e:
                diag.items.extend(e.diagnostics)
                sources.update(e.sources)
                continue
            loaded.add(path.resolve())
            edges[path.resolve()] = []
            sources[lib.path] = text
            diag.items.extend(lib.pending)
            visit(lib, (*chain, path.resolve()), at)
            files[path.resolve()] = lib

    visit(tree, (root,), None)
    # the nearer file wins: the farthest files' definitions come first, to be replaced
    # (how many 'use's away, the fewest), the same-distance ones in the order they were read
    depth = {root: 0}
    frontier = [root]
    while frontier:
        following = []
        for f in frontier:
            for u in edges.get(f, []):
                if u not in depth:
                    depth[u] = depth[f] + 1
                    following.append(u)
        frontier = following
    order = sorted(files, key=lambda f: -depth[f])
    found = [a for f in order for a in files[f].actions]
    parts = [p for f in order for p in files[f].shared]
    # two files the same distance away that define one action or part: neither wins
    actions = {f: files[f].actions for f in files}
    found = _mark_ties(found, actions, depth, name, lambda a, n, d: ast.AmbiguousAction(
        a.name, a.params, a.body, a.span, n, d))  # fmt: skip
    shared = {f: files[f].shared for f in files}
    parts = _mark_ties(parts, shared, depth, name, lambda p, n, d: ast.AmbiguousShared(
        p.name, p.items, p.span, n, d))  # fmt: skip
    used = UsedControllers({root: tree, **files}, edges, name)
    return [*found, *tree.actions], [*parts, *tree.shared], used


def _mark_ties(
    found: list[Def],
    per_file: dict[Path, tuple[Def, ...]],
    depth: dict[Path, int],
    name: Callable[[Path], str],
    mark: Callable[[Def, tuple[str, ...], int], Def],
) -> list[Def]:
    """``found`` (farthest first, so the last of a name wins) with the winner of each name
    that files the same fewest 'use's away define replaced by ``mark``'s (files, distance)."""
    definers: dict[str, list[Path]] = {}
    for f in sorted(per_file, key=lambda f: depth[f]):
        for d in per_file[f]:
            near = definers.setdefault(d.name.name, [])
            if f not in near and (not near or depth[near[0]] == depth[f]):
                near.append(f)
    last = {d.name.name: i for i, d in enumerate(found)}  # the one that would win
    out = list(found)
    for key, near in definers.items():
        if len(near) > 1:
            out[last[key]] = mark(out[last[key]], tuple(name(f) for f in near), depth[near[0]])
    return out


def _is_a_path(use: ast.UseDecl) -> bool:
    return use.target.endswith(".leg") or "/" in use.target


def _not_there(target: str, path: Path, user: Path) -> str:
    """Where a used file was looked for: users run from the folder of their project and take
    a path from there (``use "lib/x.leg"`` in ``sub/hop.leg``)."""
    elsewhere = user.resolve().parent != Path.cwd()
    told = (
        f"looked for {shown_path(path)}: a path in 'use' is relative to the file that says "
        f"it ({shown_path(user)})" + (", not to the working directory" if elsewhere else "")
    )
    if Path(target).is_file():  # the path the user meant, from the working directory
        fixed = Path(os.path.relpath(Path(target).resolve(), user.resolve().parent))
        told += f"; for the {target} of the working directory write 'use \"{fixed.as_posix()}\"'"
    return told


def use_path(tree: ast.SourceFile, use: ast.UseDecl) -> Path:
    """A quoted path is relative to the file that says ``use``; a bare name is the stdlib's."""
    if _is_a_path(use):
        path = Path(tree.path).parent / use.target
        # "lib/../parts.leg" is told as "parts.leg", unless a symlinked folder gives '..'
        # another meaning than the text's
        shorter = Path(os.path.normpath(path))
        return shorter if shorter.resolve() == path.resolve() else path
    return STDLIB / f"{use.target}.leg"


def check_model(path: str | Path, creature: str | None = None) -> Model:
    """The one creature of a file (or the named one)."""
    return choose(check_file(path), creature, path)


class _HasName(Protocol):
    @property
    def name(self) -> str: ...


Named = TypeVar("Named", bound=_HasName)


def choose(items: list[Named], creature: str | None, path: str | Path) -> Named:
    """The only item, or the one whose ``name`` is ``creature``; else an error naming them all."""
    if creature is None and len(items) == 1:
        return items[0]
    for item in items:
        if item.name == creature:
            return item
    names = ", ".join(item.name for item in items)
    wanted = (
        f"there is no creature '{creature}'"
        if creature
        else "choose a creature with --creature (creature= in Python)"
    )
    # the whole file (line 0): no line of it is the mistake, so none is shown with a caret
    raise LegError.at(Span(str(path), 0, 0, 0, 0), f"{wanted}: this file has {names}")
