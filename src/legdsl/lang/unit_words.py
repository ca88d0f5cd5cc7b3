"""A unit that the parser read as the next property: '0.5 meters', '0.1 kgm2', '9.81 m s-2'.

A creature's property is a name and a value, so a word after a number that is no unit
legdsl knows starts the next property ('length 0.5 meters  com 0.2 m' reads a property
'meters'), and the file parses. ``unit_word`` finds such a word after a property's number,
on its line, where it looks plainly like a unit (a unit's case, plural, name or symbols run
together, or symbols with spaces between them as tables write them), and says how to write
it, at the word; ``parse`` reads on with the unit it suggests in its place, as it does for a
misspelt unit at a syntax error.
"""

from __future__ import annotations

import re
from collections.abc import Iterator

from legdsl.lang import ast
from legdsl.lang.errors import Diagnostic
from legdsl.lang.expression_slips import LAST_NAME, NUMBER
from legdsl.lang.spellings import mask, offset_span, unit_spelling
from legdsl.lang.units import (
    UnitError,
    looks_like_unit,
    other_system,
    parse_unit,
    stand_in_unit,
    suggest_unit,
    unit_pattern,
    unknown_unit,
)
from legdsl.lang.value_slips import bare_exponent

_CALLED = re.compile(rf"{LAST_NAME}[ \t]*$")


def called(before: str, start: int) -> str | None:
    """The function whose '(' is at ``start``: 'box' in 'shape box(0.4, 0.1)'; None for a
    vector, whose '(' follows the key ('com (0.1, 0)')."""
    found = _CALLED.search(before, 0, start)
    if found is None:
        return None
    key = before[: found.start(1)].rstrip()
    unit = re.search(rf"(?<![\w.]){NUMBER}[ \t]*{unit_pattern()}$", key)
    if not re.search(r"(?<![\w.])[A-Za-z_]\w*$", key) or unit is not None:
        return None
    return found.group(1)


# A vector of plain numbers and the word after it, '(0, 5) ft'; each of its numbers
_VECTOR_WORD = re.compile(r"\(([^()]*)\)[ \t]*([A-Za-z_°µμ][^\s,;:(){}\[\]=<>!#\"]*)")
_PLAIN_NUMBER = re.compile(r"[ \t]*(-?)[ \t]*((?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?)[ \t]*")


def vector_unit(text: str, pos: int) -> tuple[str, int, tuple[str, ...]] | None:
    """An unknown unit after a vector of plain numbers at or one word before ``pos`` (a parse
    error's), '(0,0) ft': (the unit, its offset, the vector's numbers), for the message a
    number's unknown unit gets ('0,0' is no decimal comma there, nor is a ',' missing)."""
    for m in _VECTOR_WORD.finditer(mask(text)):
        word, start, end = m.group(2), m.start(2), m.end(2)
        if start > pos:
            break
        if not re.fullmatch(r"\s*(?:[A-Za-z_]\w*\s*)?", text[end:pos]) or "," not in m.group(1):
            continue  # the error is at the word, or at most one word after it (as _bad_unit's)
        if called(mask(text), m.start()) is not None:
            continue  # 'box(0.4, 0.1) ft': a call's units, told by stray_words
        numbers = [_PLAIN_NUMBER.fullmatch(n) for n in m.group(1).split(",")]
        try:
            parse_unit(word)
        except UnitError:
            meant = looks_like_unit(word) or other_system(word, None) is not None
            if meant and all(numbers):
                return word, start, tuple(n.group(1) + n.group(2) for n in numbers if n)
    return None


def _offset(text: str, line: int, col: int) -> int:
    start = 0
    for _ in range(line - 1):
        start = text.index("\n", start) + 1
    return start + col - 1


def prop_runs(tree: ast.SourceFile) -> Iterator[list[ast.Prop]]:
    """Each list of properties written one after another: a creature's own, a body's, a
    leg's, a block's, in templates too."""
    for creature in tree.creatures:
        yield [i for i in creature.items if isinstance(i, ast.Prop)]
        parts: list[object] = list(creature.items)
        for template in (i for i in creature.items if isinstance(i, ast.TemplateDecl)):
            parts.extend(template.items)
        for part in parts:
            if isinstance(part, ast.BodyDecl | ast.LegDecl | ast.BlockDecl):
                yield list(part.props)


def _number(prop: ast.Prop) -> ast.Number | ast.Vector | None:
    if not isinstance(prop.value, ast.One):
        return None
    value = prop.value.value
    while isinstance(value, ast.Neg):
        value = value.value
    return value if isinstance(value, ast.Number | ast.Vector) else None


def _plain_numbers(vector: ast.Vector) -> tuple[str, ...] | None:
    """A vector's numbers as written, when it has no unit and they have none ('(0, -5)')."""
    numbers = []
    for item in vector.items:
        sign = ""
        while isinstance(item, ast.Neg):
            item, sign = item.value, "" if sign else "-"
        if not isinstance(item, ast.Number) or not item.quantity.unitless:
            return None
        numbers.append(sign + item.text)
    return tuple(numbers) if vector.unit is None else None


def unit_word(file: str, text: str, tree: ast.SourceFile) -> tuple[Diagnostic, str | None] | None:
    """The first unit read as a property's name in ``tree`` (parsed from ``text``): its
    diagnostic, and ``text`` with the unit it suggests in its place, every later position
    kept (None when the suggestion does not fit)."""
    for props in prop_runs(tree):
        for before, prop in zip(props, props[1:], strict=False):
            number = _number(before)
            key = prop.key
            if number is None or key.span.line != number.span.end_line:
                continue
            end = _offset(text, number.span.end_line, number.span.end_col)
            start = _offset(text, key.span.line, key.span.col)
            if text[end:start].strip(" \t"):
                continue
            found = _diagnose(file, text, number, key.name, start)
            if found is not None:
                return found
    return None


def _diagnose(
    file: str, text: str, number: ast.Number | ast.Vector, word: str, start: int
) -> tuple[Diagnostic, str | None] | None:
    if isinstance(number, ast.Vector):  # 'inertia (0.1, 0.1, 0.2) lbft2  mass ...'
        return _vector_unit(file, text, number, word, start)
    if word in ("e", "E") and text[start - 1] not in " \t":  # 'mass 10e kg', '1e -3 kg'
        return _bare_exponent(file, text, start)
    spelt = unit_spelling(text, start)
    if spelt is not None and spelt.start < start:  # '9.81 m s-2': the unit goes on past 'm'
        span = offset_span(file, text, spelt.start, len(spelt.written))
        fits = len(spelt.suggestion) <= len(spelt.written)
        end = spelt.start + len(spelt.written)
        repaired = text[: spelt.start] + spelt.suggestion.ljust(len(spelt.written)) + text[end:]
        return Diagnostic(span, spelt.message), repaired if fits else None
    if not number.quantity.unitless or not looks_like_unit(word, fuzzy=False):
        return None
    try:
        parse_unit(word)
        return None
    except UnitError:
        pass
    diagnostic = Diagnostic(
        offset_span(file, text, start, len(word)), unknown_unit(word, number.text)
    )
    suggestion = suggest_unit(word) or stand_in_unit(word)
    if suggestion is None:
        return diagnostic, None
    if len(suggestion) <= len(word):
        return diagnostic, text[:start] + suggestion.ljust(len(word)) + text[start + len(word) :]
    # '0.1 kgm2' as '1 kg*m^2': 1 passes every check of sign, and the value is reported
    first = _offset(text, number.span.line, number.span.col)
    written = start + len(word) - first
    read = f"1 {suggestion}" if len(suggestion) + 2 <= written else f"1{suggestion}"
    if len(read) > written:
        return diagnostic, None
    return diagnostic, text[:first] + read.ljust(written) + text[start + len(word) :]


def _vector_unit(
    file: str, text: str, vector: ast.Vector, word: str, start: int
) -> tuple[Diagnostic, str | None] | None:
    """A unit after a vector of plain numbers read as the next property's name: told as a
    number's, the vector converted; the parser reads on with the unit it suggests, if it fits."""
    numbers = _plain_numbers(vector)
    if numbers is None or not looks_like_unit(word, fuzzy=False):
        return None
    try:
        parse_unit(word)
        return None
    except UnitError:
        pass
    diagnostic = Diagnostic(offset_span(file, text, start, len(word)), unknown_unit(word, numbers))
    suggestion = suggest_unit(word) or stand_in_unit(word)
    if suggestion is None or len(suggestion) > len(word):
        return diagnostic, None
    return diagnostic, text[:start] + suggestion.ljust(len(word)) + text[start + len(word) :]


def _bare_exponent(file: str, text: str, start: int) -> tuple[Diagnostic, str | None] | None:
    """An 'e' after a number read as the next property's name: the parser reads on with the
    number as it is ('10  kg'), or with its power joined to it ('1e-3 kg')."""
    found = bare_exponent(mask(text), start)
    if found is None:
        return None
    at, length, message = found
    diagnostic = Diagnostic(offset_span(file, text, at, length), message)
    written = text[at : at + length]
    if written[-1:] in ("e", "E"):  # '10e kg' read as '10  kg'
        read = text[:start] + " " + text[start + 1 :]
    else:  # '1e -3 kg' read as '1e-3  kg'
        read = text[:at] + re.sub(r"[ \t]+", "", written).ljust(length) + text[at + length :]
    return diagnostic, read if read != text else None
