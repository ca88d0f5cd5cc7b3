"""Syntax errors in words a person can act on.

A lark ``UnexpectedInput`` becomes a ``LegError`` at the right place with, in
order of preference: an unknown unit written after a number ('5 kgs'), a unit
with spaces inside it, a unit spelt as elsewhere ('m s^-2', 'm/(s^2)': ``spellings``),
a friendly sentence from ``grammar/friendly_errors.toml``
(matched by example: the same parser state on the same kind of token), or what
was found and what was expected.
"""

from __future__ import annotations

import functools
import re
import unicodedata
from dataclasses import dataclass

from lark import Token
from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken

from legdsl.lang.errors import Diagnostic, LegError, Span
from legdsl.lang.habits import habit, missing_semicolon
from legdsl.lang.lalr import friendly_entries, lark_parser
from legdsl.lang.lookalikes import letter_of_name, odd_letter_in_word
from legdsl.lang.punctuation_slips import punctuation
from legdsl.lang.spellings import NUMBER_AND_WORD, mask, offset_span, unit_spelling
from legdsl.lang.unit_words import vector_unit
from legdsl.lang.units import (
    UnitError,
    looks_like_unit,
    parse_unit,
    percentage,
    suggest_unit,
    unit_pattern,
    unknown_unit,
)
from legdsl.lang.value_slips import hex_color_line_before
from legdsl.lang.value_slips import not_a_number as not_a_number_message


def friendly_errors() -> tuple[tuple[str, tuple[str, ...]], ...]:
    """(message, example inputs) pairs from grammar/friendly_errors.toml."""
    return tuple((e["message"], tuple(e["examples"])) for e in friendly_entries())


def _token_span(file: str, tok: Token) -> Span:
    assert tok.line is not None and tok.column is not None
    return Span(file, tok.line, tok.column, tok.end_line or tok.line, tok.end_column or tok.column)


_TOKEN_WORDS = {
    "NAME": "a name",
    "QUANTITY": "a number",
    "UNIT": "a unit",
    "STRING": "a string",
    "$END": "the end of the file",
}


def _describe_expected(expected: set[str]) -> str:
    lark = lark_parser()
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


def _expected_words(err: UnexpectedInput) -> set[str]:
    """What the parser could have taken where it stopped: keywords and punctuation as
    written ('=', 'on'), other kinds of token by their names ('NAME')."""
    words = set()
    for name in set(getattr(err, "accepts", None) or getattr(err, "expected", None) or ()):
        try:
            pattern = lark_parser().get_terminal(name).pattern
        except KeyError:
            words.add(name)
            continue
        words.add(pattern.value if pattern.type == "str" else name)
    return words


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
    return {t.pattern.value: t.name for t in lark_parser().terminals if t.pattern.type == "str"}


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
    for entry in friendly_entries():
        message = entry["message"]
        if entry.get("at_end_with_open_brace") and at_end is None:
            at_end = message
        if "on_token" in entry:
            on_token.setdefault(_token_type_at(entry["on_token"], 0), message)
        tokens = frozenset(_token_type_at(t, 0) for t in entry.get("tokens", ()))
        for example in entry["examples"]:
            try:
                lark_parser().parse(example, start="start")
            except UnexpectedInput as e:
                context = _error_context(e, example)
                if context is not None:
                    examples.append((message, context, tokens | {context.token}))
    return _FriendlyTable(tuple(examples), on_token, at_end)


def _friendly(context: _ErrorContext, open_brace: bool) -> str | None:
    """The message for a syntax error, from grammar/friendly_errors.toml, if one fits.

    First the examples that failed the same way: in the same parser state on the same kind
    of token (or one of the kinds their entry lists). Among those whose parse stack has more
    than half its states in the error's, the ones whose stack is most like the error's, then
    the ones followed by the same kind of token; if they disagree on the message, none is
    given. Then the entries that apply to a kind of token wherever it comes, and to the end
    of the file inside an open '{'.
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
        if 2 * common <= len(example.stack):
            continue  # the same last state in another construct (a row's event, a param's value)
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


def _open_brace(text: str) -> bool:
    depth = 0
    for ch in mask(text):
        if ch == "{":
            depth += 1
        elif ch == "}":
            depth = max(depth - 1, 0)
    return depth > 0


# the start of a controller's input or parameter, whose number a unit must follow
_CONSTANT_DECL = re.compile(r"\s*(?:param|input)\s+[A-Za-z_]\w*\s*=\s*-?\s*")


def _bad_unit(text: str, pos: int) -> tuple[str, int] | None:
    """An unknown unit written after a number (a vector) at most one word before ``pos``: (the
    unit, its offset)."""
    if (vector := vector_unit(text, pos)) is not None:
        return vector[:2]
    found = None
    for m in NUMBER_AND_WORD.finditer(mask(text)):
        if m.start(1) > pos:
            break
        found = m
    if found is None:
        return None
    word, start, end = found.group(1), found.start(1), found.end(1)
    if re.match(r"[eE](?![A-Za-z_])", word) and text[start - 1] not in " \t":
        return None  # '3e cm', '3e−4': an exponent, told by value_slips
    if end < pos and not re.fullmatch(r"\s*(?:[A-Za-z_]\w*\s*)?", text[end:pos]):
        return None
    try:
        parse_unit(word)
    except UnitError:
        line = text[text.rfind("\n", 0, found.start()) + 1 : found.start()]
        declared = (
            _CONSTANT_DECL.fullmatch(line) is not None
        )  # its value's unit, whatever it looks like
        return (word, start) if declared or looks_like_unit(word) else None
    return None


def _error_pos(err: UnexpectedInput) -> int | None:
    if isinstance(err, UnexpectedToken):
        at_end = err.token.type == "$END"
        return None if at_end or err.token.start_pos is None else err.token.start_pos
    if isinstance(err, UnexpectedCharacters):
        return err.pos_in_stream
    return None


def repaired_unit(text: str, err: UnexpectedInput) -> str | None:
    """``text`` with the misspelt unit that caused ``err`` replaced by the unit it suggests,
    padded to the same length so that every later position stays where it was; None when
    the error is not a misspelt unit, or the suggestion is longer than what was written.
    The parser reads on with it to find the file's other mistakes, the misspelling itself
    still reported."""
    pos = _error_pos(err)
    unit = _bad_unit(text, pos) if pos is not None else None
    suggestion: str | None
    if unit is None:
        spelt = unit_spelling(text, pos) if pos is not None else None
        if spelt is None:
            return None
        unit, suggestion = (spelt.written, spelt.start), spelt.suggestion
    else:
        suggestion = suggest_unit(unit[0])
    word, start = unit
    if suggestion is None or len(suggestion) > len(word):
        return None
    return text[:start] + suggestion.ljust(len(word)) + text[start + len(word) :]


_NOT_A_NUMBER = re.compile(r"(?<![\w.])(?:nan|inf|infinity)(?![\w.])", re.IGNORECASE)


def _not_a_number(text: str, pos: int) -> tuple[str, int] | None:
    """'nan' or 'inf' written as a value on the line of ``pos`` (or the line before) and
    before it: the mistake a parse error there comes from. (word, its offset)"""
    line_start = text.rfind("\n", 0, text.rfind("\n", 0, pos)) + 1
    found = list(_NOT_A_NUMBER.finditer(mask(text), line_start, pos + 1))
    return (found[-1].group(0), found[-1].start()) if found else None


def _just_before(text: str, word: tuple[str, int] | None, pos: int | None) -> bool:
    """Whether ``word`` (as ``_not_a_number`` gives it) is the last thing before ``pos``: 'nan'
    in 'cylinder(nan m)' is the mistake, not a name a unit follows."""
    if word is None or pos is None:
        return False
    return not text[word[1] + len(word[0]) : pos].strip(" \t")


def _slip(text: str, pos: int) -> str | None:
    """A sentence for a habit from other languages at ``pos``: a C comment, a percentage,
    a name with a letter outside ASCII."""
    if text.startswith(("//", "/*"), pos):
        return (
            f"'{text[pos : pos + 2]}' does not start a comment in a .leg file: a comment "
            "starts with '#' and runs to the end of the line"
        )
    if text.startswith("%", pos) and text[:pos][-1:].isdigit():  # not '5 % 2', a remainder
        return percentage(re.findall(r"[\d.]+$", text[:pos])[0])
    if pos < len(text) and not text[pos].isascii() and text[pos].isalpha():
        return letter_of_name(text[pos])
    return None


def _spaced_unit(text: str, token: Token) -> bool:
    """A unit with a space inside it, as '60 N * m/rad': the error is on the '*', '/' or '^'."""
    if token.type not in ("STAR", "SLASH", "CIRCUMFLEX") or token.start_pos is None:
        return False
    before = mask(text)[: token.start_pos]
    if not before or before[-1] not in " \t":
        return False
    return (
        re.search(
            rf"(?<![\w.])(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?[ \t]*{unit_pattern()}[ \t]+$",
            before,
        )
        is not None
    )


# 'x = 0 m z': an assignment, then a name with no comma between (the '=' after it is the error)
_ASSIGNED_THEN_NAME = re.compile(r"\b\w+[ \t]*=[ \t]*[^,=\s{}()][^,={}()\n]*?[ \t]+(\w+)[ \t]*$")


def _missing_comma(text: str, token: Token) -> tuple[str, int, str] | None:
    """A property's assignments with a comma left out, as 'initial x = 0 m z = 0.9 m': the
    parser reads 'z' as the next property, and '=' is the error. (the name, its offset, the
    assignment before it)"""
    if token.type != "EQUAL" or token.start_pos is None:
        return None
    before = mask(text)[: token.start_pos]
    line = before[before.rfind("\n") + 1 :]
    found = _ASSIGNED_THEN_NAME.search(line)
    if found is None:
        return None
    before_name = text[token.start_pos - len(line) + found.start() :][
        : found.start(1) - found.start()
    ]
    return found.group(1), token.start_pos - len(line) + found.start(1), before_name.strip()


# 'mirror' at a line's end: the parser takes the next line's first word as its plane
_MIRROR_THEN_LINE = re.compile(r"\bmirror[ \t]*\n\s*(\w+)[ \t]*$")


def _planeless_mirror(text: str, token: Token) -> tuple[int, str] | None:
    """'mirror' with no plane before a line such as 'ground {': (its offset, the word read)."""
    found = _MIRROR_THEN_LINE.search(mask(text)[: token.start_pos or 0])
    return (found.start(), found.group(1)) if found and token.type == "LBRACE" else None


_BRACELESS = re.compile(
    r"^[ \t]*(ground|simulation)(?=[ \t]*(?:#[^\n]*)?\n|[ \t]+[A-Za-z_])(?!\s*\{)", re.M
)
_BLOCK_EXAMPLE = {
    "ground": "ground { normal spring(k = 3e4 N/m, b = 300 N*s/m) }",
    "simulation": "simulation { dt 0.4 ms }",
}


def _braceless_block(text: str, pos: int) -> tuple[int, str] | None:
    """A 'ground' or 'simulation' block opened without its '{' before ``pos``: the parser
    reads its settings as a property's words and fails a line or two later. (start, word)"""
    masked = mask(text)
    found = next(reversed(list(_BRACELESS.finditer(masked, 0, pos + 1))), None)
    if found is None or any(c in masked[found.end() : pos] for c in "{};"):
        return None
    return found.start(1), found.group(1)


def syntax_error(file: str, text: str, err: UnexpectedInput) -> LegError:
    """The user's syntax error as a ``LegError``: where, and in the friendliest words we have."""
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
        span = _token_span(file, err.token)
    else:
        span = Span(file, err.line, err.column, err.line, err.column + 1)

    pos = _error_pos(err)
    unit = _bad_unit(text, pos) if pos is not None else None
    context = _error_context(err, text)
    friendly = _friendly(context, _open_brace(text)) if context is not None else None

    not_a_number = _not_a_number(text, pos) if pos is not None else None
    odd = odd_letter_in_word(text, pos) if pos is not None else None  # 'bοdy', in a template
    slip = _slip(text, pos if odd is None else odd) if pos is not None else None
    spelt = unit_spelling(text, pos) if pos is not None else None
    # the parser sees 'x = 0 m z = 1 m' as a property 'z' written with '=': say the comma
    comma = (
        _missing_comma(text, err.token)
        if friendly is not None
        and friendly.startswith("properties take no '='")
        and isinstance(err, UnexpectedToken)
        else None
    )
    mirror = _planeless_mirror(text, err.token) if isinstance(err, UnexpectedToken) else None
    token = err.token if isinstance(err, UnexpectedToken) else None
    expected_words = _expected_words(err)
    other = habit(text, pos, token, expected_words) if pos is not None else None
    punct = punctuation(text, pos, token, expected_words) if pos is not None else None
    semi = missing_semicolon(text, pos, token, expected_words) if pos is not None else None
    if semi is not None and friendly is not None and "table row reads" not in friendly:
        semi = None  # the table's own sentence; it said a row's ':' was missing in an action
    block = _braceless_block(text, pos) if pos is not None and unit is None else None
    if block is not None:
        span = offset_span(file, text, block[0], len(block[1]))
        message = (f"a '{{' is missing after '{block[1]}': its settings go in braces, as in "
                   f"'{_BLOCK_EXAMPLE[block[1]]}'")  # fmt: skip
    elif mirror is not None:
        span = offset_span(file, text, mirror[0], len("mirror"))
        message = (f"'mirror' needs its plane on its line: 'mirror sagittal' (y to -y, left to "
                   f"right) or 'mirror frontal' (x to -x, front to back); the next line's "
                   f"'{mirror[1]}' was read as the plane")  # fmt: skip
    elif pos is not None and (color := hex_color_line_before(text, pos)) is not None:
        span = offset_span(file, text, color[0], color[1])  # it misread the line after it
        message = color[2]
    elif slip is not None and unit is None:  # 'µm' is a unit before it is a name's letter
        span = span if odd is None else offset_span(file, text, odd, 1)
        message = slip
    elif (
        other is not None
        and unit is None
        and spelt is None
        and not _just_before(text, not_a_number, pos)
    ):
        span = offset_span(file, text, other[0], other[1])
        message = other[2]
    elif not_a_number is not None:
        word, start = not_a_number
        span = offset_span(file, text, start, len(word))
        message = not_a_number_message(word)
    elif unit is not None:
        word, start = unit
        span = offset_span(file, text, start, len(word))
        number = re.search(
            r"(?<![\d.])(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?[ \t]*$", text[:start]
        )
        vector = vector_unit(text, start)  # '(0, 5) ft': the vector to write
        message = unknown_unit(word, vector[2] if vector else number and number.group().strip())
    elif isinstance(err, UnexpectedToken) and _spaced_unit(text, err.token):
        message = "a unit is written without spaces, as in '60 N*m/rad', not '60 N * m/rad'"
    elif spelt is not None:
        span = offset_span(file, text, spelt.start, len(spelt.written))
        message = spelt.message
    elif comma is not None:
        name, start, previous = comma
        span = offset_span(file, text, start, len(name))
        message = (
            f"a ',' is missing before '{name}': separate the assignments with commas, "
            f"as in '{previous}, {name} = ...'"
        )
    elif semi is not None:
        span = offset_span(file, text, semi[0], semi[1])
        message = semi[2]
    elif friendly is not None:
        message = friendly
    elif punct is not None:
        span = offset_span(file, text, punct[0], punct[1])
        message = punct[2]
    elif isinstance(err, UnexpectedToken):
        expected = _describe_expected(set(err.accepts or err.expected))
        message = f"unexpected {_found(err.token)}" + (f"; {expected}" if expected else "")
    elif isinstance(err, UnexpectedCharacters):
        char = err.char if err.char.isprintable() else f"U+{ord(err.char):04X}"
        message = f"unexpected character '{char}'"
        if err.char.isdigit():  # Python's float() would read it: never as a number here
            message += (f", a digit of another script ({unicodedata.digit(err.char, '?')}): "
                        "numbers are written with the digits 0-9")  # fmt: skip
    else:
        expected = _describe_expected(set(getattr(err, "expected", ()) or ()))
        message = "unexpected end of the file" + (f"; {expected}" if expected else "")
    return LegError([Diagnostic(span, message)], {file: text})
