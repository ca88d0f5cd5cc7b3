"""A word too many among a creature's properties, which the parser reads as a property of
its own whose value is the next property's key: a unit on the line after its number
('mass 10' then 'kg'), a unit written twice ('10 kg kg'), a stray word after a value
('mass 10 kg foo'), a word cut short by a '#' ('10 k#g'), a half-typed word alone on its
line ('pa'), a unit after a call's ')' ('box(0.4, 0.1) m', as a vector's is written). The
parse then fails at the next property's value (at its '=' or ',' when it has one, at the
block's '}' when none follows), or, when what is taken lets the file parse ('pa' before
'leg main { ... }', 'foo' before 'shape box(...)'), not at all.

``stray_word`` names the word at such a syntax error; ``stray_key`` finds the one the
parser read past. Each answer is (offset, length, sentence), as ``habits``' are.
"""

from __future__ import annotations

import re

from legdsl.lang import ast
from legdsl.lang.context import in_expression, innermost, opening
from legdsl.lang.errors import Diagnostic, Span
from legdsl.lang.expression_slips import NUMBER
from legdsl.lang.spellings import mask, offset_span
from legdsl.lang.unit_words import called, prop_runs
from legdsl.lang.units import UnitError, looks_like_unit, parse_unit, unit_pattern
from legdsl.lang.value_slips import hex_color_at, hex_color_comment

Found = tuple[int, int, str]

# the tokens a value starts with: the parser met one after reading 'WORD KEY' as a property
_VALUE_START = {"QUANTITY", "STRING", "LPAR", "MINUS"}
_LAST_WORD = re.compile(r"(?<![\w.])([A-Za-z_]\w*)\s*$")
_KEYWORDS = {
    "actuator", "at", "body", "contact", "instance", "leg", "mirror", "on", "set", "switch",
    "template", "time", "to", "use", "via", "gait", "controller", "path", "input", "param",
}  # fmt: skip
_TWO_WORDS = re.compile(r"(?<![\w.])([A-Za-z_]\w*)\s+([A-Za-z_]\w*)\s*$")


def stray_word(text: str, masked: str, pos: int, kind: str, expected: set[str]) -> Found | None:
    """The word too many before the property whose value the parse failed at, at ``pos``."""
    if in_expression(masked, pos):
        return None
    if kind == "RBRACE" and "NAME" in expected:  # 'pa' alone on the block's last line
        key = _LAST_WORD.search(masked, 0, pos)
        if (
            key is not None
            and not masked[masked.rfind("\n", 0, key.start()) + 1 : key.start()].strip()
        ):
            return key.start(1), len(key.group(1)), alone_on_its_line(key.group(1), None)
    if kind in _VALUE_START and "}" in expected:
        found = _TWO_WORDS.search(masked, 0, pos)
        if found is not None:
            told = _why(text, masked, found.start(1), found.group(1), found.group(2))
            if told is not None:
                return told
    return _last_on_its_line(text, masked, pos, kind)


def _last_on_its_line(text: str, masked: str, pos: int, kind: str) -> Found | None:
    """A word after a value, last on its line (or before the block's '}'), which took what
    follows as its value whatever the next line is: 'initial x = 0 m' (the parse fails at
    '='), 'joints hip, knee' (at ','), a block's '}'."""
    line_start = masked.rfind("\n", 0, pos) + 1
    if kind == "RBRACE" and masked[line_start:pos].strip():  # '... foo }' on one line
        found = _LAST_WORD.search(masked, 0, pos)
        if found is None or not _after_value(text, masked, found.start(1), found.group(1)):
            return None
        return _why(text, masked, found.start(1), found.group(1), None)
    words = re.findall(r"[A-Za-z_]\w*|\S", masked[line_start:pos])  # the next line's, misread
    found = _LAST_WORD.search(masked, 0, line_start)
    if found is None or not masked[masked.rfind("\n", 0, found.start(1)) : found.start(1)].strip():
        return None  # alone on its line: the parse fails at its value ('}', '-'), as above
    if not _after_value(text, masked, found.start(1), found.group(1)):
        return None
    following = masked[pos:].split()[:1]
    key = words[0] if words else (following[0] if following and kind != "RBRACE" else None)
    return _why(text, masked, found.start(1), found.group(1), key)


# a vector of numbers without units, written before a word: '(0.1, -0.2) '
_PLAIN_VECTOR = re.compile(rf"\([ \t]*-?{NUMBER}(?:[ \t]*,[ \t]*-?{NUMBER})+[ \t]*\)[ \t]*$")


def _after_value(text: str, masked: str, start: int, word: str) -> bool:
    """Whether ``word``, at ``start``, follows a whole value on its line (a number and its
    unit, a call, a vector with its unit, a string) rather than being its own part."""
    rest = text[start + len(word) : (text.find("\n", start) + 1 or len(text) + 1) - 1].strip()
    if rest and rest[0] not in "#}":
        return False  # 'color "#406080"': its value is a string, blank in ``masked``
    before = masked[:start].rstrip(" \t")
    item = re.split(r"[{};]", before[before.rfind("\n") + 1 :])[-1].split()
    if word in _KEYWORDS or (item and item[0] in _KEYWORDS):
        return False  # 'instance fl = leg(S = fl) mirror': not among properties
    if innermost(masked, start) in ("scene", "gait"):
        return False  # 'walk to 1 m/s  trot': a gait band is a name alone
    if text[:start].rstrip(" \t").endswith('"'):
        return True
    if re.search(rf"(?<![\w.]){NUMBER}[ \t]*{unit_pattern()}$", before):
        return True
    if re.search(rf"(?<![\w.]){NUMBER}$", before):
        return not _is_unit(word)  # '1 Hz' is one value
    if re.search(rf"\)[ \t]*{unit_pattern()}$", before):
        return True
    if before.endswith(")"):  # a vector's unit is its own: '(0.1, 0) m'
        return called(before, opening(before)) is not None or not _is_unit(word)
    return False


def _is_unit(word: str) -> bool:
    try:
        parse_unit(word)
    except UnitError:
        return False
    return True


def _why(text: str, masked: str, start: int, word: str, key: str | None) -> Found | None:
    """Why ``word``, at ``start``, stands before ``key`` (read as its value; None: before
    the block's '}'); None when it is the property's own key ('initial x 0 m': the '=' is
    what is missing)."""
    end = start + len(word)
    line_start = masked.rfind("\n", 0, start) + 1
    line_end = masked.find("\n", end)
    line_end = len(masked) if line_end < 0 else line_end
    before = masked[:start].rstrip()
    number = re.search(rf"(?<![\w.])({NUMBER})(?:[ \t]*({unit_pattern()}))?$", before)
    if number is not None and _is_unit(word):
        value, unit = number.group(1), number.group(2)
        if unit is not None:
            told = (
                f"'{value} {unit}' has its unit already: remove this '{word}'"
                if word in re.split(r"[*/]", re.sub(r"\^-?\d+", "", unit))
                else f"'{value} {unit}' has its unit already: a value has one, so write "
                f"'{value} {unit}' or '{value} {word}'"
            )
            return start, len(word), told
        if "\n" in masked[number.end() : start]:
            return (
                start,
                len(word),
                f"a unit follows its number on the same line: write '{value} {word}'",
            )
    called = _unit_after_call(masked, before, word)
    if called is not None:
        return start, len(word), called
    color = hex_color_at(text, start)  # 'color #ff0000 }': the '#' starts a comment
    if color is not None:
        return color
    if text[end : end + 1] == "#":
        written = re.match(r"\S*", text[start:])
        assert written is not None
        return (
            start,
            len(written.group()),
            f"'#' starts a comment, so '{written.group()}' was read as '{word}' and the rest of "
            "the line as a comment: remove the '#'",
        )
    alone = not masked[line_start:start].strip() and not masked[end:line_end].strip()
    if alone:
        return start, len(word), alone_on_its_line(word, key)
    after_value = (
        number is not None
        or before.endswith(")")
        or re.search(rf"\)[ \t]*{unit_pattern()}$", before) is not None
        or text[:start].rstrip().endswith('"')
    )  # not 'mass nan kg'
    if masked[line_start:start].strip() and after_value:
        took = (
            f"'{word}' took '{key}', the next property's key, as its value"
            if key is not None and key not in _KEYWORDS
            else f"'{word}' took the next line's '{key}' as its value"
            if key is not None
            else f"'{word}' is left a key with no value before the block's '}}'"
        )
        return (
            start,
            len(word),
            f"'{word}' is a word too many: a property is a key and its value, as in "
            f"'mass 10 kg', and {took}; remove it",
        )
    return None


def _unit_after_call(masked: str, before: str, word: str) -> str | None:
    """The sentence for a unit after a call's ')', as a vector's is written:
    'box(0.4, 0.1) m'."""
    if not before.endswith(")") or not _is_unit(word):
        return None
    start = opening(before)
    name = called(before, start)
    if name is None:
        return None
    args = [a.strip() for a in _top_level_split(before[start + 1 : -1])]
    written = ", ".join(
        re.sub(rf"^((?:[A-Za-z_]\w*[ \t]*=[ \t]*)?-?{NUMBER})$", rf"\1 {word}", a) for a in args
    )
    return (
        f"{name}(...) takes each value with its own unit, and no unit after its ')': write "
        f"'{name}({written})' (a unit after the ')' is a vector's, as in '(0.1, 0) m')"
    )


def _top_level_split(inside: str) -> list[str]:
    parts, depth, last = [], 0, 0
    for i, char in enumerate(inside):
        depth += {"(": 1, ")": -1}.get(char, 0)
        if char == "," and depth == 0:
            parts.append(inside[last:i])
            last = i + 1
    return [*parts, inside[last:]]


def alone_on_its_line(word: str, key: str | None) -> str:
    """The sentence for a property's key with no value on its line; ``key``: the next line's
    first word, read as its value."""
    taken = f", and the next line's '{key}' was read as the value of '{word}'" if key else ""
    return (
        f"'{word}' stands alone on its line: a property is a key and its value on one line, "
        f"as in 'mass 10 kg'{taken}; remove it or give it its value"
    )


def stray_key(file: str, text: str, tree: ast.SourceFile) -> Diagnostic | None:
    """A property's key whose value is the next line's first word: the file parsed, but that
    word began the next item ('pa' before 'leg main { ... }', 'mass 10 kg foo' before
    'shape box(...)'). A word after a number that looks like a unit is ``unit_word``'s."""
    lines, masked = text.split("\n"), mask(text)
    masked_lines = masked.split("\n")
    for props in prop_runs(tree):
        for prop in props:
            key, value = prop.key, prop.value
            if value.span.line == key.span.line:
                continue
            line = key.span.line - 1
            if hex_color_comment(lines[line]) is not None:
                continue  # 'color #b07040': the checker tells it, at the '#'
            start = sum(len(each) + 1 for each in lines[:line]) + key.span.col - 1
            after = re.match(r"[A-Za-z_]\w*", masked[_offset(lines, value.span) :])
            taken = after.group() if after else None
            if masked_lines[line].strip() == key.name:
                message = alone_on_its_line(key.name, taken)
            elif re.search(rf"(?<![\w.]){NUMBER}[ \t]*$", masked[:start]) and not _is_unit(
                key.name
            ):
                continue  # '0.5 meters': a unit misspelt, told by unit_word
            elif (
                (vector := _PLAIN_VECTOR.search(masked[:start])) is not None
                and called(masked, vector.start()) is None  # not 'box(0.4, 0.1) m'
                and looks_like_unit(key.name, fuzzy=False)
                and not _is_unit(key.name)
            ):
                continue  # '(0.1, 0.2) ft', likewise
            else:
                found = _why(text, masked, start, key.name, taken)
                if found is None:
                    continue
                start, length, message = found
                return Diagnostic(offset_span(file, text, start, length), message)
            return Diagnostic(offset_span(file, text, start, len(key.name)), message)
    return None


def _offset(lines: list[str], span: Span) -> int:
    return sum(len(each) + 1 for each in lines[: span.line - 1]) + span.col - 1
