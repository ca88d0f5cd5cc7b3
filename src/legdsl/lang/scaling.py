"""Dynamic (Froude) scaling of Raibert & Hodgins (1991), Table 1, applied to ``.leg`` text.

With lengths scaled by L and gravity kept, times scale by L^(1/2) and masses by L^3 (constant
density), so a quantity of dimension kg^a m^b s^c rad^d scales by L^(3a + b + c/2): angles and
bare numbers by 1, speeds by L^(1/2), stiffness (kg s^-2) by L^2, damping (kg s^-1) by L^(5/2),
torsional stiffness (kg m^2 s^-2 rad^-1) by L^4, torsional damping by L^(9/2), inertia by L^5,
forces by L^3, torques and energies by L^4, frequencies by L^(-1/2), accelerations by 1 -- the
entries of Table 1, and every other unit by the same rule.

``scale_source`` rewrites only the number tokens of a file (found by their spans), so its
comments and layout stay as written; each new number is printed in the shortest form that
reads back as the scaled value, the same double, in the unit it was written in.
"""

from __future__ import annotations

import math
import os
import re
from collections.abc import Mapping
from dataclasses import fields, is_dataclass
from pathlib import Path
from typing import Any

from legdsl.lang import ast
from legdsl.lang.errors import Diagnostic, LegError
from legdsl.lang.parser import parse
from legdsl.lang.units import DIMENSIONLESS, Dim, parse_unit

_NUMBER = re.compile(r"(\d+(?:\.\d*)?|\.\d+)([eE][-+]?\d+)?")

# what the scaled file says about running it, when the creature has no simulation block
DEFAULT_DT = 0.0004
DEFAULT_CONTROL_DT = 0.002
DEFAULT_RECORD_RATE = 200.0
# The most steps a run or a control interval may count: the C loop counts them in an int64 (a
# larger count wrapped, and --time 1e300 ended at its start, 'ok'), and past 2**53 a double no
# longer tells one step from the next.
MOST_STEPS = 2**53
# The smallest step advised (s): a second of motion is then a billion steps. A stiffness that
# needs less (k = 1e100 N/m asked for 1e-50 s, whose run legdsl refuses to count) is lowered.
SMALLEST_STEP = 1e-9
# The smallest step that can be computed with at all: its square the least power of ten above
# 0 in doubles (the stiffness check divides by it); a step below it is refused, file or --dt.
COMPUTABLE_STEP = 10.0 ** math.ceil(math.log10(math.sqrt(5e-324)))
DEFAULT_LOOKAHEAD = 1.0  # m: a path's, legdsl.ir.paths.DEFAULT_LOOKAHEAD (a test keeps them equal)
NAME_MOST = (
    64  # a creature name's characters: legdsl.check.values.MAX_NAME (a test keeps them equal)
)


def exponent(dim: Dim) -> float:
    """The power of L that a quantity of dimension ``dim`` scales by (Table 1)."""
    mass, length, time, _angle = dim
    return 3 * mass + length + time / 2


def factor(dim: Dim | None, scale: float) -> float:
    """L^(3a + b + c/2) for dimension kg^a m^b s^c rad^d; 1 for a bare number."""
    if dim is None or dim == DIMENSIONLESS:
        return 1.0
    e = exponent(dim)
    if e == 0:
        return 1.0
    try:
        return scale**e
    except OverflowError:  # L = 1e100 on an inertia (L^5): past a double
        return math.inf


def format_number(value: float) -> str:
    """The shortest text that reads back as ``value``, the same double (``0.68``, ``2400``,
    ``1e-05``, ``1.4901161193847656e-07``): Python's ``repr``, without a ``.0`` or ``e+``."""
    if value == 0:
        return "0"
    text = repr(float(value)).replace("e+", "e")
    return text.removesuffix(".0")


def scale_name(name: str, scale: float) -> str:
    """``kangaroo`` scaled by 2 -> ``kangaroo_x2``; by 0.5 -> ``kangaroo_x0_5``. A name that
    would pass ``NAME_MOST`` characters keeps as much of its start as fits before ``_xL``."""
    suffix = f"_x{format_number(scale).replace('.', '_').replace('-', 'm')}"
    return name[: NAME_MOST - len(suffix)] + suffix


def _offset(lines: list[int], line: int, col: int) -> int:
    return lines[line - 1] + col - 1


def _walk(node: Any, unit_dim: Dim | None, out: list[tuple[ast.Span, Dim, float]]) -> None:
    """Collect (span, dimension, value) of every number with a unit under ``node``."""
    if isinstance(node, ast.Number | ast.EQuantity):
        q = node.quantity
        if not q.unitless:
            out.append((node.span, q.dim, q.value))
        elif unit_dim is not None:  # a bare number inside '( ... ) UNIT'
            out.append((node.span, unit_dim, q.value))
        return
    if isinstance(node, ast.Vector):
        dim = parse_unit(node.unit)[1] if node.unit is not None else unit_dim
        for item in node.items:
            _walk(item, dim, out)
        return
    if isinstance(node, tuple | list):
        for item in node:
            _walk(item, unit_dim, out)
        return
    if is_dataclass(node) and not isinstance(node, ast.Span):
        for f in fields(node):
            if f.name != "span":
                _walk(getattr(node, f.name), unit_dim, out)


def _quantities(tree: ast.SourceFile) -> list[tuple[ast.Span, Dim, float]]:
    """(span, dimension, value) of every number with a unit in a file."""
    found: list[tuple[ast.Span, Dim, float]] = []
    _walk((tree.creatures, tree.controllers, tree.actions, tree.shared, tree.scenes), None, found)
    return found


def _reached_names(node: Any, out: set[str]) -> None:
    """The actions invoked and the shared parts included anywhere under ``node``."""
    if isinstance(node, ast.InvokeStmt):
        out.add(node.action.name)
    elif isinstance(node, ast.IncludeDecl):
        out.update(n.name for n in node.names)
    if isinstance(node, tuple | list):
        for item in node:
            _reached_names(item, out)
    elif is_dataclass(node) and not isinstance(node, ast.Span | ast.Ident):
        for f in fields(node):
            _reached_names(getattr(node, f.name), out)


def scaled_text(written: str, dim: Dim, scale: float) -> str | None:
    """A quantity as written (``1 ms``) scaled by Table 1 in the unit it is written in
    (``0.1 ms`` at L = 0.01); None for text that does not start with a number."""
    number = _NUMBER.match(written)
    if number is None:
        return None
    return format_number(float(number[0]) * factor(dim, scale)) + written[number.end() :]


def _definitions(tree: ast.SourceFile) -> list[ast.ActionDef | ast.SharedDecl]:
    return [*tree.actions, *tree.shared]


def reached_quantities(
    tree: ast.SourceFile, used: list[ast.SourceFile]
) -> list[tuple[str, ast.Span, Dim]]:
    """The numbers that scaling changes (not 0, with a unit that is not an angle's or none) in
    the actions and shared parts of the ``used`` files (nearest first) that ``tree``'s
    creatures, controllers, actions and scenes invoke or include, directly or through them:
    each with the name of its action or part, its span and its dimension. ``scale_source``
    does not rewrite them (they are another file's)."""
    own = {d.name.name for d in _definitions(tree)}
    defs: dict[str, ast.ActionDef | ast.SharedDecl] = {}
    for used_tree in used:
        for d in _definitions(used_tree):
            defs.setdefault(d.name.name, d)
    todo: set[str] = set()
    _reached_names((tree.creatures, tree.controllers, tree.actions, tree.shared, tree.scenes), todo)
    seen: set[str] = set()
    found: list[tuple[str, ast.Span, Dim]] = []
    while todo:
        name = todo.pop()
        if name in seen or name in own or name not in defs:
            continue
        seen.add(name)
        _reached_names(defs[name], todo)
        numbers: list[tuple[ast.Span, Dim, float]] = []
        _walk(defs[name], None, numbers)
        found += [(name, span, dim) for span, dim, v in numbers if exponent(dim) and v]
    return sorted(found, key=lambda f: (f[1].file, f[1].line, f[1].col))


def scales_anything(text: str, file: str = "<string>") -> bool:
    """Whether a file holds a number that scaling changes (not 0, with a unit that is not an
    angle's or none): a used file that does is left as written by ``scale_source``."""
    return any(
        exponent(dim) != 0 and value != 0 for _, dim, value in _quantities(parse(text, file))
    )


def _beyond(value: float, dim: Dim, scale: float) -> str:
    """Why a scaled number cannot be written: it is past a double, or nearer 0 than one."""
    size = "past a double" if not math.isfinite(value) else "nearer 0 than a double holds"
    return (
        f"scaled by L^{format_number(exponent(dim))} with L = {format_number(scale)} this "
        f"number is {size}; scale by a factor nearer 1"
    )


def moved_use(use: ast.UseDecl, file: str | Path, out: Path) -> str | None:
    """The path of a ``use "path"`` of ``file`` as ``out``, written elsewhere, must say it to
    reach the same file (a path is relative to the file that says it); None where it stays
    (the standard library's, named bare, an absolute path, or a folder of the same place)."""
    if not (use.target.endswith(".leg") or "/" in use.target) or Path(use.target).is_absolute():
        return None  # an absolute path names the same file from anywhere
    moved = Path(os.path.relpath(Path(file).parent / use.target, out.parent)).as_posix()
    return moved if moved != use.target else None


def _uses_from(
    tree: ast.SourceFile, text: str, starts: list[int], file: str, out: Path
) -> list[tuple[int, int, str]]:
    """Edits that point each ``use "path"`` of the file at the same file from ``out``'s
    folder (``moved_use``)."""
    edits = []
    for use in tree.uses:
        moved = moved_use(use, file, out)
        if moved is not None:
            start = text.index('"', _offset(starts, use.span.line, use.span.col))
            edits.append((start, start + len(use.target) + 2, f'"{moved}"'))
    return edits


def _has_block(creature: ast.CreatureDecl, name: str) -> bool:
    return any(isinstance(i, ast.BlockDecl) and i.name.name == name for i in creature.items)


def _scaled_defaults(dt: float, scale: float) -> dict[str, str]:
    """The runner's defaults for a creature integrated at ``dt`` (the control interval is
    never below it), scaled, as the entries of a ``simulation`` block."""
    tick = math.sqrt(scale)
    return {
        "dt": f"{format_number(DEFAULT_DT * 1e3 * tick)} ms",
        "control_dt": f"{format_number(max(DEFAULT_CONTROL_DT, dt) * 1e3 * tick)} ms",
        "record_rate": f"{format_number(DEFAULT_RECORD_RATE / tick)} Hz",
    }


def _simulation_completed(
    creature: ast.CreatureDecl, text: str, starts: list[int], scale: float
) -> list[tuple[int, int, str]]:
    """An edit writing into a ``simulation`` block what it leaves to the runner's defaults
    (control interval, record rate, step), scaled: unwritten they stay unscaled in OUT."""
    block = next(
        i for i in creature.items if isinstance(i, ast.BlockDecl) and i.name.name == "simulation"
    )
    given = {p.key.name: p.value for p in block.props}
    step = given.get("dt")
    dt = (
        step.value.quantity.value
        if isinstance(step, ast.One) and isinstance(step.value, ast.Number)
        else DEFAULT_DT
    )
    defaults = _scaled_defaults(dt, scale)
    missing = [f"{key} {value}" for key, value in defaults.items() if key not in given]
    if not missing:
        return []
    end = _offset(starts, block.span.end_line, block.span.end_col) - 1
    assert text[end] == "}"
    line = text.rfind("\n", 0, end) + 1
    if text[line:end].strip():  # '}' after a property on its line: the rest beside it
        return [(end, end, f" {'  '.join(missing)} ")]
    indent = text[line:end] + "  "
    return [(line, line, "".join(f"{indent}{m}  # scaled with it\n" for m in missing))]


def path_decls(tree: ast.SourceFile) -> list[ast.PathDecl]:
    """The paths declared in a file's controllers and shared parts."""
    owners: list[ast.ControllerDecl | ast.SharedDecl] = [*tree.controllers, *tree.shared]
    return [i for owner in owners for i in owner.items if isinstance(i, ast.PathDecl)]


def unwritten_lookahead(scale: float) -> str:
    """What a scaled file's path without a shape (``path route``) needs of a ``--path``: the
    default lookahead is for a creature of about a metre, the unscaled one's."""
    look = format_number(DEFAULT_LOOKAHEAD * scale)
    return (
        f"a --path without a lookahead follows {format_number(DEFAULT_LOOKAHEAD)} m ahead, "
        f"the unscaled creature's default; give it 'lookahead = {look} m' (scaled by "
        f"{format_number(scale)})"
    )


def scale_source(
    text: str,
    scale: float,
    file: str = "<string>",
    out: str | Path | None = None,
    names: Mapping[str, str] | None = None,
) -> str:
    """The text of a ``.leg`` file with every quantity scaled by Table 1 for length factor ``scale``,
    its creatures renamed NAME_xL (``scale_name``), or as ``names`` maps them, with the
    controllers and scenes that name them, and a ``simulation``
    block giving the scaled integration step, control interval and record rate to a creature
    that has none; a ``use`` of a file by its path is pointed at that file from ``out``, where
    the text will be written. Raises ``LegError`` for a file that does not parse, and for a
    number that no double holds once scaled (L = 1e100 on an inertia, L^5)."""
    if not (scale > 0 and math.isfinite(scale)):
        raise ValueError(f"the scale factor must be a positive number, not {scale}")
    tree = parse(text, file)
    starts = [0]
    for line in text.splitlines(keepends=True):
        starts.append(starts[-1] + len(line))
    edits: list[tuple[int, int, str]] = []  # (start, end, replacement)

    beyond: list[Diagnostic] = []
    for span, dim, _ in _quantities(tree):
        start = _offset(starts, span.line, span.col)
        match = _NUMBER.match(text, start)
        assert match is not None, f"no number at {span}"
        f = factor(dim, scale)
        if f != 1.0:
            value = float(match.group(0)) * f
            if not math.isfinite(value) or (value == 0 and float(match.group(0)) != 0):
                beyond.append(Diagnostic(span, _beyond(value, dim, scale)))
                continue
            edits.append((start, match.end(), format_number(value)))
    if beyond:
        raise LegError(beyond, {file: text})
    if out is not None:
        edits += _uses_from(tree, text, starts, file, Path(out))

    renamed = {
        c.name.name: (names or {}).get(c.name.name) or scale_name(c.name.name, scale)
        for c in tree.creatures
    }
    for creature in tree.creatures:
        ident = creature.name
        start = _offset(starts, ident.span.line, ident.span.col)
        edits.append((start, start + len(ident.name), renamed[ident.name]))
        if not _has_block(creature, "simulation"):
            entries = "".join(
                f"    {k} {v}\n" for k, v in _scaled_defaults(DEFAULT_DT, scale).items()
            )
            block = (
                "\n  # the integration step, control interval and record rate scaled with it\n"
                f"  simulation {{\n{entries}  }}\n"
            )
            end = _offset(starts, creature.span.end_line, creature.span.end_col) - 1
            assert text[end] == "}"
            edits.append((end, end, block))
        else:
            edits += _simulation_completed(creature, text, starts, scale)
    look = format_number(DEFAULT_LOOKAHEAD * scale)
    for path in path_decls(tree):
        call = path.value
        if isinstance(call, ast.Call) and all(
            a.keyword is None or a.keyword.name != "lookahead" for a in call.args
        ):  # the default lookahead is a length too: write it, scaled
            end = _offset(starts, call.span.end_line, call.span.end_col) - 1
            assert text[end] == ")"
            edits.append((end, end, f", lookahead = {look} m"))
        elif path.value is None and scale != 1:  # a --path for it: said beside it
            end = _offset(starts, path.span.end_line, path.span.end_col)
            rest = text.find("\n", end)
            if not text[end : len(text) if rest < 0 else rest].strip():
                edits.append((end, end, f"  # {unwritten_lookahead(scale)}"))
    # 'for NAME' of a controller or a scene follows the creature's new name
    owners = [*(c.creature for c in tree.controllers), *(s.creature for s in tree.scenes)]
    for owner in owners:
        if owner is not None and owner.name in renamed:
            start = _offset(starts, owner.span.line, owner.span.col)
            edits.append((start, start + len(owner.name), renamed[owner.name]))

    out = text
    for start, end, new in sorted(edits, key=lambda e: e[0], reverse=True):
        out = out[:start] + new + out[end:]
    header = (
        f"# {file} scaled by L = {format_number(scale)} (legdsl scale; Raibert & Hodgins 1991, "
        "Table 1):\n# every quantity of dimension kg^a m^b s^c rad^d multiplied by "
        "L^(3a + b + c/2); bare numbers as they were.\n"
    )
    return header + out
