"""Syntax slips from other tools and languages, named with the way legdsl writes them.

``syntax_errors`` asks here before its friendly table: a character a keyboard or a word
processor gives (a Unicode minus, '±', '½', a non-breaking space, '×', '≥', smart quotes),
an operator of C or Python ('&&', '||', '!', '**', ':=', '=>'), a unit written
as other tools write it ('500 /s', '10*kg', '(1 + 2) cm', 'deg.'), a decimal comma ('0,5'),
arithmetic in a creature's value, a trailing comma, a misspelt keyword at a line's start
(and more of a creature's values: ``value_slips``; another language's punctuation and
'np.clip(': ``punctuation_slips``).
Each answer is (offset, length, sentence); None when no habit fits.
"""

from __future__ import annotations

import difflib
import re
import unicodedata

from lark import Token

from legdsl.lang.context import in_expression, in_parentheses, innermost, opening
from legdsl.lang.expression_slips import LAST_NAME, expression_slip
from legdsl.lang.expression_slips import NUMBER as _NUMBER
from legdsl.lang.keyword_slips import misspelt_keyword_message, stem
from legdsl.lang.lookalikes import lookalike
from legdsl.lang.spellings import mask
from legdsl.lang.stray_words import stray_word
from legdsl.lang.structure_slips import missing_value, structure_slip
from legdsl.lang.units import UnitError, looks_like_unit, parse_unit, unit_pattern
from legdsl.lang.value_slips import value_slip

Found = tuple[int, int, str]

_CHARACTERS = {
    "−": "'−' is a typographic minus sign: write the ASCII '-', as in '-0.2 m'",
    "–": "'–' is a dash, not a minus sign: write the ASCII '-', as in '-0.2 m'",
    "±": "a value has one sign: a range is written 'LOW to HIGH', as in 'limits -60 deg to 60 deg'",
    "×": "'×' is not an operator: multiply with '*', as in '3 * stroke'",
    "·": "'·' is not an operator: multiply with '*' (in a unit too: 'N*m')",
    "÷": "'÷' is not an operator: divide with '/'",
    "≥": "'≥' is written '>='",
    "≤": "'≤' is written '<='",
    "≠": "'≠' is written '!='",
    "'": "strings are written in double quotes, as in 'color \"#406080\"'",
    "[": "legdsl has no '[...]': a vector is written in parentheses, as in '(0.4 m, 0.1 m)', "
    "and a list of names with commas, as in 'joints hip, knee'",
    "]": "legdsl has no '[...]': a vector is written in parentheses, as in '(0.4 m, 0.1 m)'",
    "%": "'%' is not an operator in legdsl (and a ratio is a plain number: '0.5', not '50%')",
}
_QUOTES = "“”„‘’«»"
_LOGIC = {"&&": "and", "&": "and", "||": "or", "|": "or", "!": "not"}
_KEYWORDS = (
    "creature", "controller", "shared", "action", "scene", "use", "body", "actuator",
    "contact", "leg", "template", "instance", "planar", "spatial", "input", "param",
    "signal", "roles", "start", "path", "include", "own", "table", "state", "let",
    "record", "swap", "place", "each",
)  # fmt: skip
_OTHER_KEYWORDS = {
    "import": "use", "parameter": "param", "var": "let", "const": "let",
    "local": "let", "def": "action", "function": "action", "fn": "action",
    "model": "creature", "robot": "creature", "link": "body",
}  # fmt: skip


def habit(text: str, pos: int, token: Token | None, expected: set[str]) -> Found | None:
    """The habit from elsewhere that made the parse fail at ``pos``, if one is recognised;
    ``expected``: what could have come there (keywords and punctuation as written)."""
    masked = mask(text)
    kind = token.type if token is not None else ""
    for find in (_character, _operator):
        found = find(text, masked, pos)
        if found is not None:
            return found
    if token is None:
        return None
    for find_token in (_unit_habit, _decimal_comma, _value_habit, expression_slip):
        found = find_token(text, masked, pos, kind)
        if found is not None:
            return found
    return (
        value_slip(text, masked, pos, kind, expected)
        or stray_word(text, masked, pos, kind, expected)
        or _keyword(text, masked, pos, kind)
        or structure_slip(text, masked, pos, kind, expected)
        or missing_value(text, masked, pos, kind)
    )


def missing_semicolon(text: str, pos: int, token: Token | None, expected: set[str]) -> Found | None:
    """A statement at a line's start in an action, after one that lacks its ';'."""
    masked = mask(text)
    kind = token.type if token is not None else ""
    line_start = masked.rfind("\n", 0, pos) + 1
    at_start = not masked[line_start:pos].strip()
    if ";" in expected and kind == "NAME" and at_start and innermost(masked, pos) == "action":
        end = len(masked[:pos].rstrip())
        return (
            end - 1,
            1,
            (
                "a ';' is missing at the end of this line: the statements of a table row or an "
                "action are separated by ';'"
            ),
        )
    return None


def _character(text: str, masked: str, pos: int) -> Found | None:
    ch = text[pos : pos + 1]
    if not ch:
        return None
    if ch in _CHARACTERS:
        if ch == "%" and masked[:pos].rstrip()[-1:].isdigit() and masked[pos - 1] != " ":
            return None  # '50%': a percentage, told elsewhere
        return pos, 1, _CHARACTERS[ch]
    if ch in _QUOTES:
        return (
            pos,
            1,
            f"'{ch}' is a typographic quote: write strings in straight double quotes, '\"'",
        )
    if ch != " " and unicodedata.category(ch) == "Zs" or ch in "\u200b\ufeff":
        return (
            pos,
            1,
            (
                f"an invisible character (U+{ord(ch):04X}, a non-breaking or other special space) "
                "stands here: replace it with an ordinary space"
            ),
        )
    if ch == "@" and re.search(r"\bset\b", masked[masked.rfind("\n", 0, pos) + 1 : pos]):
        return (
            pos,
            1,
            "'@' times a command on the command line ('--set speed=2m/s@3s'); in a scene it is "
            "written 'at 3 s set speed = 2 m/s'",
        )
    if unicodedata.category(ch) == "Cc" and ch not in "\t\n\r":
        return (
            pos,
            1,
            f"a control character (U+{ord(ch):04X}) stands here: remove it (words are apart by "
            "spaces, tabs and newlines)",
        )
    if ch == '"' and '"' not in text[pos + 1 :].split("\n", 1)[0]:
        return (
            pos,
            1,
            "this string is not closed on its line: end it with '\"' before the line ends",
        )
    if unicodedata.category(ch) == "No" and unicodedata.numeric(ch, None) is not None:
        value = f"{unicodedata.numeric(ch):.6g}"
        return pos, 1, f"'{ch}' is not a number legdsl reads: write it as a decimal, '{value}'"
    found = lookalike(ch)
    return None if found is None else (pos, 1, found)


def _operator(text: str, masked: str, pos: int) -> Found | None:
    two = masked[pos : pos + 2]
    if two in ("&&", "||"):
        return pos, 2, f"'{two}' is written '{_LOGIC[two]}', as in 'a > 0 {_LOGIC[two]} b < 1 s'"
    if masked[pos : pos + 1] in ("&", "|"):
        word = _LOGIC[masked[pos]]
        return pos, 1, f"'{masked[pos]}' is written '{word}', as in 'a > 0 {word} b < 1 s'"
    if masked[pos : pos + 1] == "!" and two != "!=":
        return pos, 1, "'!' is written 'not', as in 'not (trunk.z > 2 m)'"
    start = pos - 1 if masked[pos - 1 : pos] in "=:-" and pos > 0 else pos
    pair = masked[start : start + 2]
    if pair in ("=>", "=<"):
        right = ">=" if pair == "=>" else "<="
        return start, 2, f"'{pair}' is written '{right}'"
    if pair == ":=":
        return start, 2, "':=' is written '=': 'record t_down = time'"
    if pair == "->":
        return start, 2, "a table row's event is followed by ':', not '->': 'state A on EVENT: ...'"
    if masked[pos - 1 : pos + 1] == "**" and pos > 0:
        return pos - 1, 2, "a power is written with '^': 'x^2', not 'x**2'"
    return None


_UNIT_AFTER = re.compile(rf"[ \t]*({unit_pattern()})")


def _unit_habit(text: str, masked: str, pos: int, kind: str) -> Found | None:
    unit_here = re.match(unit_pattern(), masked[pos:])
    token_text = unit_here.group() if unit_here else ""
    before = masked[:pos].rstrip(" \t")
    number = re.search(rf"(?<![\w.]){_NUMBER}$", before)
    if kind == "SLASH" and number is not None and before != masked[:pos]:
        unit = _UNIT_AFTER.match(masked, pos + 1)
        if unit is not None:  # '500 /s'
            return pos, unit.end() - pos, unit_after_slash(number.group(), unit.group(1))
    if kind == "STAR" and number is not None:
        unit = _UNIT_AFTER.match(masked, pos + 1)
        if unit is not None and before == masked[:pos]:  # '10*kg'
            return pos, unit.end() - pos, unit_after_star(number.group(), unit.group(1))
    if kind == "UNIT" and not re.match(r"[ \t]*[(=]", masked[pos + len(token_text) :]):
        written = token_text
        if before.endswith(")"):  # '(1 + 2) cm'
            opened = opening(before)
            return (
                pos,
                len(written),
                (
                    f"a unit follows a number, not a parenthesis: multiply by one of it, as in "
                    f"'{before[opened:]} * 1 {written}'"
                ),
            )
        name = re.search(rf"{LAST_NAME}$", before)
        if name is not None:  # 'thrust cm'
            return (
                pos,
                len(written),
                (
                    f"a unit follows a number, not a name: multiply by one of it, as in "
                    f"'{name.group(1)} * 1 {written}'"
                ),
            )
    dotted = re.search(rf"{_NUMBER}[ \t]*{unit_pattern()}$", before)
    if kind == "DOT" and dotted is not None:  # 'deg.'
        written = dotted.group()
        return pos, 1, f"a unit ends without '.': write '{written}', not '{written}.'"
    return None


def unit_after_slash(number: str, unit: str) -> str:
    """How to write '500 /s' (a unit opened by '/'), in a file's value or an expression."""
    inverse = _inverse_unit(unit)
    also = f" or '{number} Hz'" if inverse == "s^-1" else ""
    return f"a unit starts with a symbol, not '/': write '{number} {inverse}'{also}"


def unit_after_star(number: str, unit: str) -> str:
    """How to write '10*kg' (a unit joined to its number by '*')."""
    return f"a unit follows its number without '*': write '{number} {unit}'"


def _inverse_unit(unit: str) -> str:
    """'s' -> 's^-1 (or Hz)', 's^2' -> 's^-2'; the first symbol of ``unit`` divided into 1."""
    atom = re.match(r"([A-Za-z]+)(?:\^(-?\d+))?", unit)
    assert atom is not None
    power = -int(atom.group(2) or 1)
    rest = unit[atom.end() :]
    written = f"{atom.group(1)}^{power}" if power != 1 else atom.group(1)
    if rest.startswith("*"):
        written = f"{rest[1:]}/{atom.group(1)}" + (f"^{-power}" if power != -1 else "")
    elif rest:
        written += "*1" + rest  # '/s/m': the reader sees it whole below
        try:
            parse_unit(written)
        except UnitError:
            return f"{atom.group(1)}^{power}"
    return written


def _decimal_comma(text: str, masked: str, pos: int, kind: str) -> Found | None:
    """'0,5 m': a decimal comma, which reads as two values."""
    for m in re.finditer(r"(?<![\w.,])(\d+),(\d+)(?![\w.,(])", masked[: pos + 12]):
        near = m.start() <= pos <= m.end() + 6 and "\n" not in masked[m.end() : pos]
        if near and (kind in ("COMMA", "QUANTITY", "NAME", "EQUAL", "SLASH") or m.end() >= pos):
            written = m.group()
            return (
                m.start(),
                len(written),
                (
                    f"'{written}': a decimal number is written with a point, '{m.group(1)}."
                    f"{m.group(2)}' (a ',' separates values)"
                ),
            )
    return None


def _value_habit(text: str, masked: str, pos: int, kind: str) -> Found | None:
    before = masked[:pos].rstrip(" \t")
    after = masked[pos:]
    dots = re.search(rf"{_NUMBER}\.?$", before)
    if dots is not None and ".." in masked[pos - 1 : pos + 2]:  # '-60..60 deg'
        return (
            dots.start(),
            pos - dots.start() + 1,
            ("a range is written 'LOW to HIGH', as in 'limits -60 deg to 60 deg', not '..'"),
        )
    x10 = re.search(rf"(?<![\w.])({_NUMBER})[xX×]10$", before)
    if kind == "CIRCUMFLEX" and x10 is not None:  # '2x10^4', read as 2 and a name 'x10'
        power = re.match(r"\^(-?\d+)", masked[pos:])
        if power is not None:
            return (
                x10.start(),
                pos + power.end() - x10.start(),
                (f"a power of ten is written with 'e': '{x10.group(1)}e{power.group(1)}'"),
            )
    ten = re.match(r"(?:[xX×]|\*[ \t]*)10\^(-?\d+)", after)
    number = re.search(rf"(?<![\w.]){_NUMBER}$", before)
    if ten is not None and number is not None:  # '2x10^4', '2*10^4'
        return (
            number.start(),
            pos + ten.end() - number.start(),
            (f"a power of ten is written with 'e': '{number.group()}e{ten.group(1)}'"),
        )
    expression = in_expression(masked, pos)
    if kind == "PLUS" and after.startswith("+-"):
        return (
            pos,
            2,
            (
                "a value has one sign: a range is written 'LOW to HIGH', as in "
                "'limits -60 deg to 60 deg'"
            ),
        )
    valued = re.search(rf"{_NUMBER}(?:[ \t]*{unit_pattern()})?$", before)
    if kind in ("PLUS", "SLASH", "STAR") and valued and not expression:
        return (
            pos,
            1,
            (
                "a creature's value is one number with its unit (arithmetic is for "
                "controllers): work it out and write the result, as in '0.5 kg'"
            ),
        )
    if kind == "PLUS" and re.match(r"\+[ \t]*\.?\d", after) and not expression:
        return pos, 1, "a value takes no '+' sign: write '60 deg', not '+60 deg'"
    if kind == "MINUS" and valued and not expression and in_parentheses(masked, pos):
        return (
            pos,
            1,
            (  # '(0 m -0.05 m)'
                "put commas between the numbers of a vector, as in '(0 m, -0.05 m)'"
            ),
        )
    if kind == "RPAR" and before.endswith(","):
        return len(before) - 1, 1, "a ',' ends this list with nothing after it: remove it"
    word = re.match(r"[A-Za-z_]\w*", after)
    line = masked[masked.rfind("\n", 0, pos) + 1 : pos]
    row_head = line.split()[:1] == ["state"] and " on " not in line  # 'state A if ...'
    if (
        kind == "NAME"
        and word is not None
        and word.group() in ("if", "else", "then")
        and not row_head
    ):
        return (
            pos,
            word.end(),
            (
                f"legdsl has no '{word.group()}' in an expression: 'select(CONDITION, A, B)' is A "
                "where CONDITION holds and B elsewhere; a table row's event chooses between states"
            ),
        )
    if kind == "NAME" and word is not None and looks_like_unit(word.group()):
        return None  # '0.2 S': a misspelt unit, told as such
    called = re.match(r"[A-Za-z_]\w*[ \t]*[=.(]", after) is not None  # a new statement
    inside = in_parentheses(masked, pos)
    if kind == "NAME" and number and word and expression and inside and not called:
        return (
            pos,
            word.end(),
            (  # '3 stroke'
                f"multiplication needs '*': write '{number.group()} * {word.group()}'"
            ),
        )
    return None


def _keyword(text: str, masked: str, pos: int, kind: str) -> Found | None:
    """A misspelt or foreign keyword at the start of the error's line or the line before."""
    line_start = masked.rfind("\n", 0, pos) + 1
    starts = [line_start]
    prev_end = line_start - 1
    while prev_end > 0:
        prev_start = masked.rfind("\n", 0, prev_end) + 1
        if masked[prev_start:prev_end].strip():
            starts.append(prev_start)
            break
        prev_end = prev_start - 1
    for start in starts:
        m = re.match(r"[ \t]*([A-Za-z_]\w*)", masked[start:])
        if m is None or start + m.start(1) > pos:
            continue
        word = m.group(1)
        if word in _KEYWORDS or word in ("state", "ground"):
            continue
        if re.match(r"[ \t]*=(?!=)", masked[start + m.end(1) :]):
            continue  # 'reach = ...': a declaration without its kind, not 'each' misspelt
        if word in _OTHER_KEYWORDS:
            right = _OTHER_KEYWORDS[word]
        else:
            close = difflib.get_close_matches(word, _KEYWORDS, n=1, cutoff=0.8)
            close = close or [k for k in _KEYWORDS if k == stem(word)]  # 'Body', 'bodies'
            if not close:
                continue
            right = close[0]
        return start + m.start(1), len(word), misspelt_keyword_message(word, right)
    return None
