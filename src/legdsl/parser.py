"""Parse .leg text into the syntax tree of ``legdsl.ast``.

The grammar is ``grammar/legdsl.lark``. Syntax errors become a ``LegError``
with the position, what was found and what was expected; common slips get a
friendlier sentence from ``grammar/friendly_errors.toml`` (lark's
example-matched errors).
"""

from __future__ import annotations

import difflib
import functools
import re
import tomllib
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from lark import Lark, Token, Transformer, Tree, v_args
from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken

from . import ast
from .errors import Diagnostic, LegError, Span
from .units import DIMENSIONLESS, UNITS, Quantity, UnitError, parse_unit, unit_pattern

_PACKAGE_GRAMMAR = Path(__file__).parent / "grammar"
_SOURCE_GRAMMAR = Path(__file__).resolve().parents[2] / "grammar"


def grammar_dir() -> Path:
    """Where the grammar files are: inside the installed package, or the source tree."""
    for candidate in (_PACKAGE_GRAMMAR, _SOURCE_GRAMMAR):
        if (candidate / "legdsl.lark").is_file():
            return candidate
    raise FileNotFoundError("legdsl.lark not found in the package or the source tree")


@functools.cache
def _lark() -> Lark:
    text = (grammar_dir() / "legdsl.lark").read_text(encoding="utf-8")
    return Lark(text, parser="lalr", propagate_positions=True, maybe_placeholders=True)


@functools.cache
def _friendly_entries() -> tuple[dict[str, Any], ...]:
    data = tomllib.loads((grammar_dir() / "friendly_errors.toml").read_text(encoding="utf-8"))
    return tuple(data["error"])


def friendly_errors() -> tuple[tuple[str, tuple[str, ...]], ...]:
    """(message, example inputs) pairs from grammar/friendly_errors.toml."""
    return tuple((e["message"], tuple(e["examples"])) for e in _friendly_entries())


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

    def start_state(self, meta: Any, c: list[Any]) -> ast.StartDecl:
        return ast.StartDecl(self._id(c[0]), self._s(meta))

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

    def action_def(self, meta: Any, c: list[Any]) -> ast.ActionDef:
        params = tuple(self._id(t) for t in c[1:-1] if t is not None)
        return ast.ActionDef(self._id(c[0]), params, c[-1], self._s(meta))

    def row(self, meta: Any, c: list[Any]) -> ast.Row:
        return ast.Row(self._id(c[0]), c[1], c[2], self._s(meta))

    def table(self, meta: Any, c: list[Any]) -> ast.TableDecl:
        return ast.TableDecl(tuple(c), self._s(meta))

    def controller(self, meta: Any, c: list[Any]) -> ast.ControllerDecl:
        creature = self._id(c[1]) if c[1] is not None else None
        return ast.ControllerDecl(self._id(c[0]), creature, tuple(c[2:]), self._s(meta))

    def use(self, meta: Any, c: list[Any]) -> ast.UseDecl:
        text = str(c[0])
        return ast.UseDecl(text[1:-1] if text.startswith('"') else text, self._s(meta))


# ------------------------------------------------------------- syntax errors
_TOKEN_WORDS = {
    "NAME": "a name",
    "QUANTITY": "a number",
    "UNIT": "a unit",
    "STRING": "a string",
    "$END": "the end of the file",
}


def _describe_expected(expected: set[str]) -> str:
    lark = _lark()
    words = set()
    for name in expected:
        if name in _TOKEN_WORDS:
            words.add(_TOKEN_WORDS[name])
            continue
        try:
            pattern = lark.get_terminal(name).pattern
        except KeyError:
            continue
        if pattern.type == "str":
            words.add(f"'{pattern.value}'")
    ordered = sorted(words, key=lambda w: (not w.startswith("'"), w))
    if not ordered:
        return ""
    if len(ordered) > 8:
        ordered = ordered[:8] + ["..."]
    return "expected " + ", ".join(ordered)


def _found(token: Token) -> str:
    if token.type == "$END":
        return "end of the file"
    kind = _TOKEN_WORDS.get(token.type, "").removeprefix("a ")
    return f"{kind} '{token}'" if kind else f"'{token}'"


@dataclass(frozen=True)
class _ErrorContext:
    """Where the parser stopped: its LALR state stack, the token it could not take, the next one."""

    stack: tuple[int, ...]
    token: str
    next_token: str


def _error_context(err: UnexpectedInput, text: str) -> _ErrorContext | None:
    stack = getattr(err.state, "state_stack", None)
    if not stack:
        return None
    if isinstance(err, UnexpectedToken):
        if err.token.type == "$END":
            return _ErrorContext(tuple(stack), "$END", "$END")
        end = err.token.end_pos
        token = err.token.type
    elif isinstance(err, UnexpectedCharacters):
        end = (err.pos_in_stream or 0) + 1
        token = f"char {err.char}"
    else:
        return None
    return _ErrorContext(tuple(stack), token, _token_type_at(text, end or 0))


_NEXT_TOKEN = re.compile(
    r'(?:\s|#[^\n]*)*(?:(?P<name>[A-Za-z_]\w*)|(?P<number>\.?\d)|(?P<string>")|(?P<op>[<>=!]=|\S))?'
)


@functools.cache
def _literal_terminals() -> dict[str, str]:
    """Keyword and punctuation text -> terminal name, e.g. 'on' -> 'ON', ';' -> 'SEMICOLON'."""
    return {t.pattern.value: t.name for t in _lark().terminals if t.pattern.type == "str"}


def _token_type_at(text: str, pos: int) -> str:
    """The kind of the token at ``pos`` (after blanks and comments), named as lark names it."""
    m = _NEXT_TOKEN.match(text, pos)
    if m is None or m.lastgroup is None:
        return "$END"
    if m.lastgroup == "number":
        return "QUANTITY"
    if m.lastgroup == "string":
        return "STRING"
    word = m.group(m.lastgroup)
    return _literal_terminals().get(word, "NAME" if m.lastgroup == "name" else f"char {word}")


@dataclass(frozen=True)
class _FriendlyTable:
    # (message, where its example failed, the kinds of token it also stands for)
    examples: tuple[tuple[str, _ErrorContext, frozenset[str]], ...]
    on_token: dict[str, str]  # token kind -> message, whatever the parser state
    at_end_with_open_brace: str | None


@functools.cache
def _friendly_table() -> _FriendlyTable:
    examples = []
    on_token: dict[str, str] = {}
    at_end = None
    for entry in _friendly_entries():
        message = entry["message"]
        if entry.get("at_end_with_open_brace") and at_end is None:
            at_end = message
        if "on_token" in entry:
            on_token.setdefault(_token_type_at(entry["on_token"], 0), message)
        tokens = frozenset(_token_type_at(t, 0) for t in entry.get("tokens", ()))
        for example in entry["examples"]:
            try:
                _lark().parse(example)
            except UnexpectedInput as e:
                context = _error_context(e, example)
                if context is not None:
                    examples.append((message, context, tokens | {context.token}))
    return _FriendlyTable(tuple(examples), on_token, at_end)


def _friendly(context: _ErrorContext, open_brace: bool) -> str | None:
    """The message for a syntax error, from grammar/friendly_errors.toml, if one fits.

    First the examples that failed the same way: in the same parser state on the same kind
    of token (or one of the kinds their entry lists). Among those, the ones whose parse stack
    is most like the error's, then the ones followed by the same kind of token; if they
    disagree on the message, none is given. Then the entries that apply to a kind of token
    wherever it comes, and to the end of the file inside an open '{'.
    """
    table = _friendly_table()
    best_score: tuple[int, bool] | None = None
    best: set[str] = set()
    for message, example, tokens in table.examples:
        if example.stack[-1] != context.stack[-1] or context.token not in tokens:
            continue
        # Likeness: the states of the example's stack that the error's stack also has, in
        # order, less those it lacks. A subsequence rather than a common top of stack, so
        # that an operator that differs ('<' for '>') does not hide the context around it.
        common = _common_subsequence(example.stack, context.stack)
        score = (2 * common - len(example.stack), example.next_token == context.next_token)
        if best_score is None or score > best_score:
            best, best_score = {message}, score
        elif score == best_score:
            best.add(message)
    if len(best) == 1:
        return best.pop()
    if best:  # examples of different slips fit equally well: better say nothing special
        return None
    if context.token in table.on_token:
        return table.on_token[context.token]
    if context.token == "$END" and open_brace:
        return table.at_end_with_open_brace
    return None


def _common_subsequence(a: tuple[int, ...], b: tuple[int, ...]) -> int:
    """The length of the longest common subsequence of two parse stacks."""
    row = [0] * (len(b) + 1)
    for x in a:
        prev_diag = 0
        for j, y in enumerate(b):
            prev_diag, row[j + 1] = (
                row[j + 1],
                (prev_diag + 1 if x == y else max(row[j + 1], row[j])),
            )
    return row[-1]


def _mask(text: str) -> str:
    """``text`` with comments and strings blanked out (same length, same line breaks)."""
    return re.sub(r'"[^"\n]*"|#[^\n]*', lambda m: " " * len(m.group()), text)


def _open_brace(text: str) -> bool:
    depth = 0
    for ch in _mask(text):
        if ch == "{":
            depth += 1
        elif ch == "}":
            depth = max(depth - 1, 0)
    return depth > 0


# A number and the word written after it on the same line, as '5 kgs' or '2 m/sec'.
_NUMBER_AND_WORD = re.compile(
    r"(?<![\w.])(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?[ \t]*([A-Za-z_][^\s,;:(){}\[\]=<>!#\"]*)"
)
# Units spelt out, or from elsewhere, in the singular (a final 's' is dropped before
# looking), with the symbol to suggest instead (None: no such unit in legdsl).
_UNIT_NAMES: dict[str, str | None] = {
    "sec": "s", "second": "s", "msec": "ms", "millisecond": "ms", "minute": "min",
    "meter": "m", "metre": "m", "centimeter": "cm", "centimetre": "cm", "millimeter": "mm",
    "millimetre": "mm", "kilometer": "km", "kilometre": "km", "kilogram": "kg", "kilo": "kg",
    "gram": "g", "newton": "N", "kilonewton": "kN", "joule": "J", "watt": "W", "hertz": "Hz",
    "degree": "deg", "radian": "rad", "revolution": "rev",
    "hour": None, "hr": None, "h": None, "inch": None, "in": None, "ft": None, "feet": None,
    "lb": None, "mph": None, "kph": None, "kmh": None, "mp": None, "rpm": None,
}  # fmt: skip
_UNIT_SYMBOL = "|".join(sorted(UNITS, key=len, reverse=True))
_UNIT_RUN = re.compile(rf"(?:{_UNIT_SYMBOL})+")
_UNIT_BY_LOWER = {u.lower(): u for u in UNITS}


def _plain_unit(word: str) -> str:
    return word.replace("²", "^2").replace("³", "^3").replace("·", "*").replace(".", "*")


def _looks_like_unit(word: str) -> bool:
    """Whether a word after a number was meant as a unit (and is not, say, a property name)."""
    parts = [p for p in re.split(r"[*/^]", _plain_unit(word)) if not p.lstrip("-").isdigit()]
    return bool(parts) and all(
        p.lower().removesuffix("s") in _UNIT_NAMES
        or p.lower().removesuffix("s") in _UNIT_BY_LOWER
        or re.fullmatch(rf"(?:{_UNIT_SYMBOL})+\d*", p) is not None
        or difflib.get_close_matches(p, list(UNITS), n=1, cutoff=0.8)
        for p in parts
    )


def _suggest_unit(word: str) -> str | None:
    """A unit legdsl knows for a misspelt one: 'kgs' -> 'kg', 'm/sec' -> 'm/s', 'Nm' -> 'N*m'."""
    out = []
    for part in re.split(r"([*/^])", _plain_unit(word)):
        singular = part.lower().removesuffix("s")
        if part in UNITS or part in "*/^" or part.lstrip("-").isdigit():
            out.append(part)
        elif singular in _UNIT_NAMES:
            symbol = _UNIT_NAMES[singular]
            if symbol is None:
                return None
            out.append(symbol)
        elif len(singular) > 1 and singular in _UNIT_BY_LOWER:
            out.append(_UNIT_BY_LOWER[singular])
        elif _UNIT_RUN.fullmatch(part):
            out.append("*".join(re.findall(_UNIT_SYMBOL, part)))
        else:
            close = difflib.get_close_matches(part, list(UNITS), n=1, cutoff=0.6)
            if not close:
                return None
            out.append(close[0])
    suggestion = "".join(out)
    try:
        parse_unit(suggestion)
    except UnitError:
        return None
    return suggestion if suggestion != word else None


def _bad_unit(text: str, pos: int) -> tuple[str, int] | None:
    """An unknown unit written after a number at most one word before ``pos``: (the unit, its offset)."""
    found = None
    for m in _NUMBER_AND_WORD.finditer(_mask(text)):
        if m.start(1) > pos:
            break
        found = m
    if found is None:
        return None
    word, start, end = found.group(1), found.start(1), found.end(1)
    if end < pos and not re.fullmatch(r"\s*(?:[A-Za-z_]\w*\s*)?", text[end:pos]):
        return None
    try:
        parse_unit(word)
    except UnitError:
        return (word, start) if _looks_like_unit(word) else None
    return None


def _spaced_unit(text: str, token: Token) -> bool:
    """A unit with a space inside it, as '60 N * m/rad': the error is on the '*', '/' or '^'."""
    if token.type not in ("STAR", "SLASH", "CIRCUMFLEX") or token.start_pos is None:
        return False
    before = _mask(text)[: token.start_pos]
    if not before or before[-1] not in " \t":
        return False
    return (
        re.search(
            rf"(?<![\w.])(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?[ \t]*{unit_pattern()}[ \t]+$", before
        )
        is not None
    )


def _offset_span(file: str, text: str, start: int, length: int) -> Span:
    line = text.count("\n", 0, start) + 1
    col = start - (text.rfind("\n", 0, start) + 1) + 1
    return Span(file, line, col, line, col + length)


def _syntax_error(file: str, text: str, err: UnexpectedInput) -> LegError:
    at_end = isinstance(err, UnexpectedEOF) or (
        isinstance(err, UnexpectedToken) and err.token.type == "$END"
    )
    if at_end:
        # Just after the last thing written (lark's end token borrows its position).
        token = getattr(err, "token", None)
        if token is not None and token.end_line is not None and token.end_column is not None:
            line, col = token.end_line, token.end_column
        else:
            line = text.count("\n") + 1
            col = len(text) - (text.rfind("\n") + 1) + 1
        span = Span(file, line, col, line, col + 1)
    elif isinstance(err, UnexpectedToken):
        span = _tspan(file, err.token)
    else:
        span = Span(file, err.line, err.column, err.line, err.column + 1)

    if isinstance(err, UnexpectedToken) and err.token.start_pos is not None and not at_end:
        pos = err.token.start_pos
    elif isinstance(err, UnexpectedCharacters):
        pos = err.pos_in_stream
    else:
        pos = None
    unit = _bad_unit(text, pos) if pos is not None else None
    context = _error_context(err, text)
    friendly = _friendly(context, _open_brace(text)) if context is not None else None

    if unit is not None:
        word, start = unit
        span = _offset_span(file, text, start, len(word))
        symbols = ", ".join(UNITS)
        message = (
            f"'{word}' is not a unit legdsl knows: a unit is made of the symbols {symbols} "
            f"joined by '*', '/' and '^', as in '5 m/s' or '60 N*m/rad'"
        )
        suggestion = _suggest_unit(word)
        if suggestion:
            message += f"; did you mean '{suggestion}'?"
    elif isinstance(err, UnexpectedToken) and _spaced_unit(text, err.token):
        message = "a unit is written without spaces, as in '60 N*m/rad', not '60 N * m/rad'"
    elif friendly is not None:
        message = friendly
    elif isinstance(err, UnexpectedToken):
        expected = _describe_expected(set(err.accepts or err.expected))
        message = f"unexpected {_found(err.token)}" + (f"; {expected}" if expected else "")
    elif isinstance(err, UnexpectedCharacters):
        message = f"unexpected character '{err.char}'"
    else:
        expected = _describe_expected(set(getattr(err, "expected", ()) or ()))
        message = "unexpected end of the file" + (f"; {expected}" if expected else "")
    return LegError([Diagnostic(span, message)], {file: text})


def parse(text: str, file: str = "<string>") -> ast.SourceFile:
    """Parse .leg text; ``file`` is the name used in spans (keep it as the user wrote it)."""
    try:
        tree = _lark().parse(text)
    except UnexpectedInput as err:
        raise _syntax_error(file, text, err) from None
    return _build(tree, file, text)


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
    )


def parse_file(path: str | Path) -> tuple[ast.SourceFile, str]:
    """Read and parse a file; returns the tree and the text (for error rendering)."""
    p = Path(path)
    try:
        data = p.read_bytes()
    except FileNotFoundError:
        raise LegError.at(Span(str(path), 0, 0, 0, 0), f"no such file: {path}") from None
    except OSError as e:
        raise LegError.at(
            Span(str(path), 0, 0, 0, 0), f"cannot read {path}: {e.strerror}"
        ) from None
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as e:
        line = data.count(b"\n", 0, e.start) + 1
        line_start = data.rfind(b"\n", 0, e.start) + 1
        col = len(data[line_start : e.start].decode("utf-8", errors="replace")) + 1
        raise LegError.at(
            Span(str(path), line, col, line, col + 1), f"the file is not UTF-8 text ({e.reason})"
        ) from None
    # Line ends as Python's text mode reads them: \r\n and a lone \r are \n.
    text = text.replace("\r\n", "\n").replace("\r", "\n")
    return parse(text, str(path)), text
