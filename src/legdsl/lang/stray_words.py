"""A word too many among a creature's properties, which the parser reads as a property of
its own whose value is the next property's key: a unit on the line after its number
('mass 10' then 'kg'), a unit written twice ('10 kg kg'), a stray word after a value
('mass 10 kg foo'), a word cut short by a '#' ('10 k#g'), a half-typed word alone on its
line ('pa'). The parse then fails at the next property's value, or, when the key taken
is a block's ('pa' before 'leg main { ... }'), not at all.

``stray_word`` names the word at such a syntax error; ``stray_key`` finds the one the
parser read past. Each answer is (offset, length, sentence), as ``habits``' are.
"""

from __future__ import annotations

import re

from legdsl.lang import ast
from legdsl.lang.context import in_expression
from legdsl.lang.errors import Diagnostic
from legdsl.lang.expression_slips import NUMBER
from legdsl.lang.spellings import mask, offset_span
from legdsl.lang.unit_words import prop_runs
from legdsl.lang.units import UnitError, parse_unit, unit_pattern
from legdsl.lang.value_slips import hex_color_comment

Found = tuple[int, int, str]

# the tokens a value starts with: the parser met one after reading 'WORD KEY' as a property
_VALUE_START = {"QUANTITY", "STRING", "LPAR", "MINUS"}
_LAST_WORD = re.compile(r"(?<![\w.])([A-Za-z_]\w*)\s*$")
_TWO_WORDS = re.compile(r"(?<![\w.])([A-Za-z_]\w*)\s+([A-Za-z_]\w*)\s*$")


def stray_word(text: str, masked: str, pos: int, kind: str, expected: set[str]) -> Found | None:
    """The word too many before the property whose value the parse failed at, at ``pos``."""
    if in_expression(masked, pos):
        return None
    if kind == "RBRACE" and "NAME" in expected:  # 'pa' alone on the block's last line
        key = _LAST_WORD.search(masked, 0, pos)
        if key is None or masked[masked.rfind("\n", 0, key.start()) + 1 : key.start()].strip():
            return None
        return key.start(1), len(key.group(1)), alone_on_its_line(key.group(1), None)
    if kind not in _VALUE_START or "}" not in expected:
        return None
    found = _TWO_WORDS.search(masked, 0, pos)
    if found is None:
        return None
    return _why(text, masked, found.start(1), found.group(1), found.group(2))


def _is_unit(word: str) -> bool:
    try:
        parse_unit(word)
    except UnitError:
        return False
    return True


def _why(text: str, masked: str, start: int, word: str, key: str) -> Found | None:
    """Why ``word``, at ``start``, stands before ``key`` (read as its value); None when it
    is the property's own key ('initial x 0 m': the '=' is what is missing)."""
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
                if unit == word
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
    after_value = number is not None or before.endswith(")")  # not 'mass nan kg'
    if masked[line_start:start].strip() and after_value:
        return (
            start,
            len(word),
            f"'{word}' is a word too many: a property is a key and its value, as in "
            f"'mass 10 kg', and '{word}' took '{key}', the next property's key, as its value; "
            "remove it",
        )
    return None


def alone_on_its_line(word: str, key: str | None) -> str:
    """The sentence for a property's key with no value on its line; ``key``: the next line's
    first word, read as its value."""
    taken = f", and the next line's '{key}' was read as the value of '{word}'" if key else ""
    return (
        f"'{word}' stands alone on its line: a property is a key and its value on one line, "
        f"as in 'mass 10 kg'{taken}; remove it or give it its value"
    )


def stray_key(file: str, text: str, tree: ast.SourceFile) -> Diagnostic | None:
    """A property's key alone on its line whose value is the next line's first word: the
    file parsed, but that word began the next item ('pa' before 'leg main { ... }')."""
    lines, masked_lines = text.split("\n"), mask(text).split("\n")
    for props in prop_runs(tree):
        for prop in props:
            value = prop.value.value if isinstance(prop.value, ast.One) else None
            if not isinstance(value, ast.NameValue):
                continue
            key, taken = prop.key, value.ident
            line = key.span.line - 1
            if taken.span.line == key.span.line or masked_lines[line].strip() != key.name:
                continue
            if hex_color_comment(lines[line]) is not None:
                continue  # 'color #b07040': the checker tells it, at the '#'
            start = sum(len(each) + 1 for each in lines[:line]) + key.span.col - 1
            return Diagnostic(
                offset_span(file, text, start, len(key.name)),
                alone_on_its_line(key.name, taken.name),
            )
    return None
