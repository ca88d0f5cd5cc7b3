"""Parse .leg text into the syntax tree of ``legdsl.lang.ast``.

The grammar is ``grammar/legdsl.lark`` (loaded by ``legdsl.lang.lalr``). Syntax
errors become a ``LegError`` with the position and friendly words
(``legdsl.lang.syntax_errors``).
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from lark import Token, Transformer, Tree, v_args
from lark.exceptions import UnexpectedInput

from legdsl.lang import ast
from legdsl.lang.errors import Diagnostic, LegError, Span
from legdsl.lang.file_kinds import refusal
from legdsl.lang.keyword_slips import misspelt_declaration
from legdsl.lang.lalr import grammar_dir, lark_parser
from legdsl.lang.spellings import hidden_line_breaks, other_numbers, read_past_units, unshown_units
from legdsl.lang.stray_words import stray_key
from legdsl.lang.syntax_errors import repaired_unit, syntax_error
from legdsl.lang.unit_words import unit_word
from legdsl.lang.units import DIMENSIONLESS, Quantity, parse_unit
from legdsl.lang.value_slips import not_a_number_name

__all__ = ["grammar_dir", "parse", "parse_file"]


# ------------------------------------------------------------ spans and values
def _span(file: str, meta: Any) -> Span:
    return Span(file, meta.line, meta.column, meta.end_line, meta.end_column)


def _tspan(file: str, tok: Token) -> Span:
    assert tok.line is not None and tok.column is not None
    return Span(file, tok.line, tok.column, tok.end_line or tok.line, tok.end_column or tok.column)


def _quantity(text: str) -> Quantity:
    number = text.rstrip()
    unit = ""
    for i, ch in enumerate(text):
        if ch in " \t" or (ch.isalpha() and ch not in "eE"):
            number, unit = text[:i], text[i:].strip()
            break
        if ch in "eE" and not (
            i + 1 < len(text) and (text[i + 1].isdigit() or text[i + 1] in "+-")
        ):
            number, unit = text[:i], text[i:].strip()
            break
    if not unit:
        return Quantity(float(number), DIMENSIONLESS, unitless=True)
    factor, dim = parse_unit(unit)
    return Quantity(float(number) * factor, dim)


@dataclass(frozen=True)
class _Goal:
    """One ``NAME = expr`` of a place statement, while the statement is being built."""

    name: ast.Ident
    value: ast.Expr


@v_args(meta=True)
class _ToAst(Transformer):
    """Parse tree to AST; every node gets the span of what it was written as."""

    def __init__(self, file: str):
        super().__init__()
        self.file = file

    def _id(self, tok: Token) -> ast.Ident:
        return ast.Ident(str(tok), _tspan(self.file, tok))

    def _s(self, meta: Any) -> Span:
        return _span(self.file, meta)

    # values
    def quantity(self, meta: Any, c: list[Any]) -> ast.Number:
        return ast.Number(_quantity(str(c[0])), str(c[0]), self._s(meta))

    def name(self, meta: Any, c: list[Any]) -> ast.NameValue:
        return ast.NameValue(self._id(c[0]))

    def neg(self, meta: Any, c: list[Any]) -> ast.Neg:
        return ast.Neg(c[0], self._s(meta))

    def string(self, meta: Any, c: list[Any]) -> ast.String:
        return ast.String(str(c[0])[1:-1], self._s(meta))

    def vector(self, meta: Any, c: list[Any]) -> ast.Vector:
        unit = c[-1]
        items = tuple(c[:-1])
        return ast.Vector(
            items,
            str(unit) if unit is not None else None,
            _tspan(self.file, unit) if unit is not None else None,
            self._s(meta),
        )

    def call(self, meta: Any, c: list[Any]) -> ast.Call:
        return ast.Call(self._id(c[0]), tuple(c[1] or ()), self._s(meta))

    def args(self, meta: Any, c: list[Any]) -> list[ast.Arg]:
        return list(c)

    def pos_arg(self, meta: Any, c: list[Any]) -> ast.Arg:
        return ast.Arg(None, c[0], self._s(meta))

    def kw_arg(self, meta: Any, c: list[Any]) -> ast.Arg:
        return ast.Arg(self._id(c[0]), c[1], self._s(meta))

    # properties
    def assign(self, meta: Any, c: list[Any]) -> ast.Assign:
        return ast.Assign(self._id(c[0]), c[1], self._s(meta))

    def pval_one(self, meta: Any, c: list[Any]) -> ast.One:
        return ast.One(c[0], self._s(meta))

    def pval_range(self, meta: Any, c: list[Any]) -> ast.Range:
        return ast.Range(c[0], c[1], self._s(meta))

    def pval_list(self, meta: Any, c: list[Any]) -> ast.Many:
        return ast.Many(tuple(c), self._s(meta))

    def pval_assigns(self, meta: Any, c: list[Any]) -> ast.Assigns:
        return ast.Assigns(tuple(c), self._s(meta))

    def prop(self, meta: Any, c: list[Any]) -> ast.Prop:
        return ast.Prop(self._id(c[0]), c[1], self._s(meta))

    # creature
    def planar(self, meta: Any, c: list[Any]) -> ast.Flag:
        return ast.Flag("planar", self._s(meta))

    def spatial(self, meta: Any, c: list[Any]) -> ast.Flag:
        return ast.Flag("spatial", self._s(meta))

    def attach_free(self, meta: Any, c: list[Any]) -> ast.AttachFree:
        return ast.AttachFree(self._s(meta))

    def attach_fixed(self, meta: Any, c: list[Any]) -> ast.AttachFixed:
        return ast.AttachFixed(c[0], self._s(meta))

    def attach_joint(self, meta: Any, c: list[Any]) -> ast.AttachJoint:
        return ast.AttachJoint(self._id(c[0]), self._id(c[1]), self._id(c[2]), c[3], self._s(meta))

    def body(self, meta: Any, c: list[Any]) -> ast.BodyDecl:
        return ast.BodyDecl(self._id(c[0]), c[1], tuple(c[2:]), self._s(meta))

    def actuator(self, meta: Any, c: list[Any]) -> ast.ActuatorDecl:
        return ast.ActuatorDecl(
            self._id(c[0]), self._id(c[1]), self._id(c[2]), tuple(c[3] or ()), self._s(meta)
        )

    def contact(self, meta: Any, c: list[Any]) -> ast.ContactDecl:
        return ast.ContactDecl(self._id(c[0]), self._id(c[1]), c[2], self._s(meta))

    def leg(self, meta: Any, c: list[Any]) -> ast.LegDecl:
        return ast.LegDecl(self._id(c[0]), tuple(c[1:]), self._s(meta))

    def block(self, meta: Any, c: list[Any]) -> ast.BlockDecl:
        return ast.BlockDecl(self._id(c[0]), tuple(c[1:]), self._s(meta))

    def template(self, meta: Any, c: list[Any]) -> ast.TemplateDecl:
        params = tuple(self._id(t) for t in c[1:] if isinstance(t, Token))
        items = tuple(i for i in c[1:] if i is not None and not isinstance(i, Token))
        return ast.TemplateDecl(self._id(c[0]), params, items, self._s(meta))

    def instance(self, meta: Any, c: list[Any]) -> ast.InstanceDecl:
        args = tuple(a for a in c[2:-1] if a is not None)
        return ast.InstanceDecl(self._id(c[0]), self._id(c[1]), args, c[-1], self._s(meta))

    def mirror(self, meta: Any, c: list[Any]) -> ast.Ident:
        return self._id(c[0])

    def creature(self, meta: Any, c: list[Any]) -> ast.CreatureDecl:
        return ast.CreatureDecl(self._id(c[0]), tuple(c[1:]), self._s(meta))

    # expressions
    def e_quantity(self, meta: Any, c: list[Any]) -> ast.EQuantity:
        return ast.EQuantity(_quantity(str(c[0])), str(c[0]), self._s(meta))

    def e_name(self, meta: Any, c: list[Any]) -> ast.EName:
        return ast.EName(self._id(c[0]))

    def e_call(self, meta: Any, c: list[Any]) -> ast.ECall:
        return ast.ECall(self._id(c[0]), tuple(c[1] or ()), self._s(meta))

    def exprs(self, meta: Any, c: list[Any]) -> list[Any]:
        return list(c)

    def attr(self, meta: Any, c: list[Any]) -> ast.EAttr:
        return ast.EAttr(c[0], self._id(c[1]), self._s(meta))

    def uneg(self, meta: Any, c: list[Any]) -> ast.EUnary:
        return ast.EUnary("-", c[0], self._s(meta))

    def not_op(self, meta: Any, c: list[Any]) -> ast.EUnary:
        return ast.EUnary("not", c[0], self._s(meta))

    def _bin(op: str) -> Callable[..., ast.EBinary]:  # type: ignore[misc]  # noqa: N805
        def method(self: _ToAst, meta: Any, c: list[Any]) -> ast.EBinary:
            return ast.EBinary(op, c[0], c[1], self._s(meta))

        return method

    add, sub, mul, div, pow = _bin("+"), _bin("-"), _bin("*"), _bin("/"), _bin("^")
    lt, gt, le, ge, eq, ne = _bin("<"), _bin(">"), _bin("<="), _bin(">="), _bin("=="), _bin("!=")
    and_op, or_op = _bin("and"), _bin("or")

    # controller
    def input(self, meta: Any, c: list[Any]) -> ast.InputDecl:
        return ast.InputDecl(self._id(c[0]), c[1], self._s(meta))

    def param(self, meta: Any, c: list[Any]) -> ast.ParamDecl:
        return ast.ParamDecl(self._id(c[0]), c[1], self._s(meta))

    def signal(self, meta: Any, c: list[Any]) -> ast.SignalDecl:
        return ast.SignalDecl(self._id(c[0]), c[1], self._s(meta))

    def role_one(self, meta: Any, c: list[Any]) -> ast.RoleDecl:
        return ast.RoleDecl(self._id(c[0]), (self._id(c[1]),), self._s(meta))

    def role_group(self, meta: Any, c: list[Any]) -> ast.RoleDecl:
        return ast.RoleDecl(self._id(c[0]), tuple(self._id(t) for t in c[1:]), self._s(meta))

    def roles(self, meta: Any, c: list[Any]) -> ast.RolesDecl:
        return ast.RolesDecl(tuple(c), self._s(meta))

    def path_decl(self, meta: Any, c: list[Any]) -> ast.PathDecl:
        return ast.PathDecl(self._id(c[0]), c[1], self._s(meta))

    def start_state(self, meta: Any, c: list[Any]) -> ast.StartDecl:
        return ast.StartDecl(self._id(c[0]), self._s(meta))

    def own(self, meta: Any, c: list[Any]) -> ast.OwnDecl:
        return ast.OwnDecl(tuple(self._id(t) for t in c), self._s(meta))

    def stmts(self, meta: Any, c: list[Any]) -> tuple[Any, ...]:
        return tuple(x for x in c if x is not None)

    def target(self, meta: Any, c: list[Any]) -> tuple[ast.Ident, ...]:
        return tuple(self._id(t) for t in c)

    def assign_stmt(self, meta: Any, c: list[Any]) -> ast.AssignStmt:
        return ast.AssignStmt(c[0], c[1], self._s(meta))

    def swap_stmt(self, meta: Any, c: list[Any]) -> ast.SwapStmt:
        return ast.SwapStmt(self._id(c[0]), self._id(c[1]), self._s(meta))

    def record_stmt(self, meta: Any, c: list[Any]) -> ast.RecordStmt:
        return ast.RecordStmt(self._id(c[0]), c[1], self._s(meta))

    def let_stmt(self, meta: Any, c: list[Any]) -> ast.LetStmt:
        return ast.LetStmt(self._id(c[0]), c[1], self._s(meta))

    def invoke_stmt(self, meta: Any, c: list[Any]) -> ast.InvokeStmt:
        return ast.InvokeStmt(self._id(c[0]), tuple(c[1] or ()), self._s(meta))

    def each_stmt(self, meta: Any, c: list[Any]) -> ast.EachStmt:
        return ast.EachStmt(self._id(c[0]), self._id(c[1]), tuple(c[2]), self._s(meta))

    def goal(self, meta: Any, c: list[Any]) -> _Goal:
        return _Goal(self._id(c[0]), c[1])

    def place_stmt(self, meta: Any, c: list[Any]) -> ast.PlaceStmt:
        goals = tuple((g.name, g.value) for g in c[1:] if isinstance(g, _Goal))
        servos = tuple(t for t in c[1:] if not isinstance(t, _Goal))
        return ast.PlaceStmt(self._id(c[0]), goals, servos, self._s(meta))

    def action_def(self, meta: Any, c: list[Any]) -> ast.ActionDef:
        params = tuple(self._id(t) for t in c[1:-1] if t is not None)
        return ast.ActionDef(self._id(c[0]), params, c[-1], self._s(meta))

    def row(self, meta: Any, c: list[Any]) -> ast.Row:
        return ast.Row(self._id(c[0]), c[1], c[2], self._s(meta))

    def table(self, meta: Any, c: list[Any]) -> ast.TableDecl:
        return ast.TableDecl(tuple(c), self._s(meta))

    def controller(self, meta: Any, c: list[Any]) -> ast.ControllerDecl:
        creature = self._id(c[1]) if c[1] is not None else None
        base = self._id(c[2]) if c[2] is not None else None
        return ast.ControllerDecl(self._id(c[0]), creature, tuple(c[3:]), self._s(meta), base)

    def shared(self, meta: Any, c: list[Any]) -> ast.SharedDecl:
        return ast.SharedDecl(self._id(c[0]), tuple(c[1:]), self._s(meta))

    def include(self, meta: Any, c: list[Any]) -> ast.IncludeDecl:
        return ast.IncludeDecl(tuple(self._id(n) for n in c), self._s(meta))

    def scene(self, meta: Any, c: list[Any]) -> ast.SceneDecl:
        creature = self._id(c[1]) if c[1] is not None else None
        return ast.SceneDecl(self._id(c[0]), creature, tuple(c[2:]), self._s(meta))

    def scene_controller(self, meta: Any, c: list[Any]) -> ast.SceneController:
        return ast.SceneController(self._id(c[0]), self._s(meta))

    def scene_set(self, meta: Any, c: list[Any]) -> ast.SceneSet:
        return ast.SceneSet(c[0], c[1], None, self._s(meta))

    def scene_switch(self, meta: Any, c: list[Any]) -> ast.SceneSwitch:
        return ast.SceneSwitch(self._id(c[0]), None, self._s(meta))

    def scene_at(self, meta: Any, c: list[Any]) -> ast.SceneSet | ast.SceneSwitch:
        from dataclasses import replace

        return replace(c[1], at=c[0], span=self._s(meta))

    def scene_time(self, meta: Any, c: list[Any]) -> ast.SceneTime:
        return ast.SceneTime(c[0], self._s(meta))

    def gait_from(self, meta: Any, c: list[Any]) -> tuple[str, Any]:
        return ("from", c[0])

    def gait_to(self, meta: Any, c: list[Any]) -> tuple[str, Any]:
        return ("to", c[0])

    def gait_band(self, meta: Any, c: list[Any]) -> ast.GaitBand:
        ends = dict(x for x in c[1:] if x is not None)
        return ast.GaitBand(self._id(c[0]), ends.get("from"), ends.get("to"), self._s(meta))

    def scene_gaits(self, meta: Any, c: list[Any]) -> ast.SceneGaits:
        return ast.SceneGaits(self._id(c[0]), tuple(c[1:]), self._s(meta))

    def use(self, meta: Any, c: list[Any]) -> ast.UseDecl:
        text = str(c[0])
        return ast.UseDecl(text[1:-1] if text.startswith('"') else text, self._s(meta))


# How deeply the syntax tree may nest (an expression of this many nested operators, say).
# Every later stage walks expressions recursively; past this a 600-term sum or 600 nested
# minus signs would meet Python's recursion limit, so it is refused here, with its position.
MAX_NESTING = 120
# The same limit in what the user writes: a statement around an expression takes about 10
# levels, an operator one and a call two (itself and its arguments).
OPERATORS_DEEP = MAX_NESTING - 10


# How many misspelt units the parser reports in one file; it reads past the rest at once,
# unreported, and says how many there were.
MAX_REPAIRS = 50

# The most of a file read: some 300 times the largest shipped creature; an endless device
# (/dev/zero) or a large file of another kind given by mistake was read until memory ran out.
MAX_SOURCE_BYTES = 8 * 2**20


def parse(text: str, file: str = "<string>", recover: bool = False) -> ast.SourceFile:
    """Parse .leg text; ``file`` is the name used in spans (keep it as the user wrote it).

    A misspelt unit ('10 kgg') does not stop the parse: it is reported, the unit it most
    likely meant is read in its place, and the parse goes on to the file's other mistakes.
    With ``recover`` the tree is returned with those reports in ``pending``, for the checker
    to report beside its own (``check_tree``); without, they are raised once parsing is done.

    The tree is immutable, so a text parsed again (the standard library every creature
    uses, a file a session loads twice) is the tree already built: it takes a tenth of a
    second each time.
    """
    return _parsed(text, file, recover)


@functools.lru_cache(maxsize=32)
def _parsed(text: str, file: str, recover: bool) -> ast.SourceFile:
    # what the parser reads: the text with numbers in other notations and misspelt units
    # repaired
    if hidden := hidden_line_breaks(file, text):  # what follows each is misread
        raise LegError(hidden, {file: text})
    pending, read = other_numbers(file, text)
    unshown: list[Diagnostic] = []  # a last word on the misspelt units read past unreported
    while True:
        try:
            tree = lark_parser().parse(read, start="start")
        except UnexpectedInput as err:
            error = syntax_error(file, read, err)
            repaired = repaired_unit(read, err) if not unshown else None
            if repaired is None:
                raise LegError(pending + error.diagnostics + unshown, {file: text}) from None
            if len(pending) >= MAX_REPAIRS:  # this one and the rest, at once
                line = error.diagnostics[0].span.line
                more, repaired = read_past_units(repaired, line)
                unshown.append(unshown_units(file, text, more + 1, line, MAX_REPAIRS))
            else:
                pending.extend(error.diagnostics)
            read = repaired
            continue
        _check_nesting(tree, file, text)
        built = _build(tree, file, text)
        stray = stray_key(file, read, built) or misspelt_declaration(file, built)
        if stray is not None:  # what follows it is misread: the checker's errors would mislead
            raise LegError([*pending, stray], {file: text})
        if (nan := not_a_number_name(built, text)) is not None:  # not 'declare: param inf = ...'
            raise LegError([*pending, nan], {file: text})
        # a unit the parser read as the next property ('length 0.5 meters')
        word = unit_word(file, read, built) if len(pending) < MAX_REPAIRS else None
        if word is None:
            break
        pending.append(word[0])
        if word[1] is None:
            break
        read = word[1]
    pending.extend(unshown)
    if pending and not recover:
        raise LegError(pending, {file: text})
    return replace(built, pending=tuple(pending))


def _check_nesting(tree: Tree, file: str, text: str) -> None:
    """Raise a ``LegError`` at the first place the tree nests deeper than ``MAX_NESTING``
    (walked without recursion, so that any depth is measured safely)."""
    stack: list[tuple[Tree, int, Tree | None]] = [(tree, 1, None)]
    # walked depth first, so `kind` is the top-level item (creature, controller...) of a node
    top = {id(item): str(item.data) for item in tree.children if isinstance(item, Tree)}
    kind = ""
    while stack:
        node, depth, outer = stack.pop()
        if depth == 2:
            kind = top.get(id(node), "")
        if depth > MAX_NESTING:
            where = outer if outer is not None else node
            meta = where.meta
            line = getattr(meta, "line", 0)
            span = Span(file, line, getattr(meta, "column", 0),
                        getattr(meta, "end_line", line), getattr(meta, "end_column", 0))  # fmt: skip
            raise LegError.at(
                span,
                f"this is nested too deeply (more than about {OPERATORS_DEEP} operators, or "
                f"{OPERATORS_DEEP // 2} calls, one inside another); "
                + (
                    "split it into steps with 'let' or a signal"
                    if kind in ("controller", "action_def", "shared")
                    else "write it with fewer parentheses and operators"
                ),
                {file: text},
            )
        # the outermost node that is deeper than a statement marks where the trouble starts
        mark = outer if outer is not None or depth < 8 else node
        for child in node.children:
            if isinstance(child, Tree):
                stack.append((child, depth + 1, mark if depth >= 8 else None))


def parse_value(text: str, file: str = "<string>") -> ast.Value:
    """One creature-style value, such as a path's shape written on the command line."""
    try:
        tree = lark_parser().parse(text, start="value")
    except UnexpectedInput as err:
        raise syntax_error(file, text, err) from None
    result = _ToAst(file).transform(tree)
    assert not isinstance(result, Tree)
    return result


def _build(tree: Tree, file: str, text: str) -> ast.SourceFile:
    items = _ToAst(file).transform(tree).children
    lines = text.split("\n")
    span = Span(file, 1, 1, len(lines), len(lines[-1]) + 1)
    return ast.SourceFile(
        path=file,
        creatures=tuple(i for i in items if isinstance(i, ast.CreatureDecl)),
        controllers=tuple(i for i in items if isinstance(i, ast.ControllerDecl)),
        actions=tuple(i for i in items if isinstance(i, ast.ActionDef)),
        uses=tuple(i for i in items if isinstance(i, ast.UseDecl)),
        span=span,
        shared=tuple(i for i in items if isinstance(i, ast.SharedDecl)),
        scenes=tuple(i for i in items if isinstance(i, ast.SceneDecl)),
    )


def parse_file(path: str | Path, recover: bool = False) -> tuple[ast.SourceFile, str]:
    """Read and parse a file; returns the tree and the text (for error rendering).
    ``recover`` as for ``parse``."""
    p = Path(path)
    try:
        with p.open("rb") as f:  # no further than the cap: a device or a huge file given by mistake
            data = f.read(MAX_SOURCE_BYTES + 1)
    except FileNotFoundError:
        raise LegError.at(Span(str(path), 0, 0, 0, 0), f"no such file: {path}") from None
    except OSError as e:
        raise LegError.at(
            Span(str(path), 0, 0, 0, 0), f"cannot read {path}: {e.strerror}"
        ) from None
    if len(data) > MAX_SOURCE_BYTES:
        raise LegError.at(
            Span(str(path), 0, 0, 0, 0),
            f"this holds more than {MAX_SOURCE_BYTES // 2**20} MB, far more than a .leg file "
            "(the shipped creatures' are under 30 KB): is it another kind of file, or a device? "
            "Name the .leg file",
        )
    if (refused := refusal(str(path), data)) is not None:  # its bytes never shown
        raise LegError.at(Span(str(path), 0, 0, 0, 0), refused)
    try:
        text = data.decode("utf-8-sig")  # a byte-order mark some editors write is no text
    except UnicodeDecodeError as e:
        line = data.count(b"\n", 0, e.start) + 1
        line_start = data.rfind(b"\n", 0, e.start) + 1
        col = len(data[line_start : e.start].decode("utf-8", errors="replace")) + 1
        shown = data.decode("utf-8", errors="replace").replace("\r\n", "\n").replace("\r", "\n")
        raise LegError.at(
            Span(str(path), line, col, line, col + 1),
            f"the file is not UTF-8 text ({e.reason}, byte 0x{data[e.start]:02x}); save it as "
            "UTF-8 in your editor, or replace the character under the caret",
            {str(path): shown},
        ) from None
    # Line ends as Python's text mode reads them: \r\n and a lone \r are \n.
    text = text.replace("\r\n", "\n").replace("\r", "\n")
    return parse(text, str(path), recover), text
