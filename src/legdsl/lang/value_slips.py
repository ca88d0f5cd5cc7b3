"""More habits from other tools in a creature's values, for ``habits``: an exponent with no
digits ('9.81e m/s^2'), a range written with ':' ('-60 deg : 60 deg'), a unit in quotes
('10 "kg"'), a list ended with a ',' ('joints hip, knee,  foot toe'), a colour without
quotes ('color #b07040'). Each answer is
(offset, length, sentence); None when the slip is not there.
"""

from __future__ import annotations

import dataclasses
import re

from legdsl.lang import ast
from legdsl.lang.context import in_expression
from legdsl.lang.errors import Diagnostic, Span
from legdsl.lang.lookalikes import ascii_for, minus_sign
from legdsl.lang.units import UnitError, parse_unit, suggest_unit, unit_pattern

Found = tuple[int, int, str]

_NUMBER = r"(?<![\d.])(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?"


def value_slip(text: str, masked: str, pos: int, kind: str, expected: set[str]) -> Found | None:
    """The first of this module's slips that made the parse fail at ``pos``."""
    for find in (_bare_exponent, _range_colon, _quoted_unit, _trailing_list_comma):
        found = find(text, masked, pos, kind, expected)
        if found is not None:
            return found
    return None


def _bare_exponent(text: str, masked: str, pos: int, kind: str, expected: set[str]) -> Found | None:
    return bare_exponent(masked, pos)


def bare_exponent(masked: str, pos: int) -> Found | None:
    """'9.81e m/s^2': an 'e' with no power of ten after it (at or before ``pos``, on its
    line), read as a name; '1e -3 kg', its power apart; '3e−4', a typographic minus in it."""
    line_start = masked.rfind("\n", 0, pos) + 1
    found = None
    for m in re.finditer(
        r"(?<![\w.])(\d+(?:\.\d*)?|\.\d+)[eE](?![\w+-])", masked[line_start : pos + 1]
    ):
        found = m
    if found is None:
        return None
    start = line_start + found.start()
    after = line_start + found.end()
    power = re.match(r"([^\x00-\x7f])([0-9]+)", masked[after:])
    if power is not None and ascii_for(power.group(1)) == "-":  # '3e−4', as typeset
        number = f"{found.group()}-{power.group(2)}"
        return after, 1, minus_sign(power.group(1), number)
    unit = re.match(rf"[ \t]*({unit_pattern()})", masked[after:])
    apart = re.match(rf"[ \t]+([-+]?[0-9]+)(?![\w.])(?:[ \t]*({unit_pattern()}))?", masked[after:])
    if apart is not None:
        number = f"{found.group()}{apart.group(1)}"
        also = f" {apart.group(2)}" if apart.group(2) else ""
        return (
            start,
            apart.end(1) + found.end() - found.start(),
            f"a power of ten is written right after its 'e', without a space: write "
            f"'{number}{also}'",
        )
    value = found.group(1) + (f" {unit.group(1)}" if unit else "")
    return (
        start,
        found.end() - found.start(),
        (
            f"'{found.group()}' is no number: an 'e' takes the power of ten after it, as in "
            f"'{found.group(1)}e3'; without one, write '{value}'"
        ),
    )


_END = rf"(?:-[ \t]*)?{_NUMBER}(?:[ \t]*{unit_pattern()})?"


def _range_colon(text: str, masked: str, pos: int, kind: str, expected: set[str]) -> Found | None:
    """'limits -60 deg : 60 deg': a range written as some languages slice."""
    if kind != "COLON" or "to" not in expected:
        return None
    low = re.search(rf"(?:(?<!\w)([A-Za-z_]\w*)[ \t]+)?({_END})[ \t]*$", masked[:pos])
    high = re.match(rf"[ \t]*({_END})", masked[pos + 1 :])
    if low is None or high is None:
        return None
    key = f"{low.group(1)} " if low.group(1) else ""
    return (
        pos,
        1,
        (
            "a range is written 'LOW to HIGH', not with ':': write "
            f"'{key}{low.group(2)} to {high.group(1)}'"
        ),
    )


def _quoted_unit(text: str, masked: str, pos: int, kind: str, expected: set[str]) -> Found | None:
    """'10 "kg"': a unit in quotes, as a data file holds it."""
    if kind != "STRING":
        return None
    number = re.search(rf"(?<![\w.])({_NUMBER})[ \t]*$", masked[:pos])
    quoted = re.match(r'"([^"\n]*)"', text[pos:])
    if number is None or quoted is None:
        return None
    unit: str | None = quoted.group(1).strip()
    try:
        parse_unit(unit or "")
    except UnitError:
        unit = suggest_unit(unit or "")
    if not unit:
        return None
    return (
        pos,
        quoted.end(),
        f"a unit is written without quotes, after its number: write '{number.group(1)} {unit}'",
    )


def _trailing_list_comma(
    text: str, masked: str, pos: int, kind: str, expected: set[str]
) -> Found | None:
    """'joints hip, knee,  foot toe': the ',' after a list's last value makes the next
    property's name one more value, and the parse fails further on."""
    if in_expression(masked, pos):
        return None
    line_start = masked.rfind("\n", 0, pos) + 1
    for m in re.finditer(
        r"(\w)[ \t]*(,)[ \t]*([A-Za-z_]\w*)[ \t]+[A-Za-z_]\w*(?!\w)(?![ \t]*[=(,.)])",
        masked[line_start:pos],
    ):
        comma = line_start + m.start(2)
        if "=" in masked[comma:pos]:
            # A trailing ',' fails the parse by the next '=' at the latest: one read well
            # before it ('joints hip, slide  ...  alias a = x b = y') ended its list fine.
            continue
        # from after the line's last '{', '}' or '=', where a list can start: searched from
        # its start, a long line would be tried from each of its words
        head = masked[line_start:comma]
        head = head[max(head.rfind(c) for c in "{}=") + 1 :]
        listed = re.search(
            r"(?<![A-Za-z_])([A-Za-z_]\w*)[ \t]+(\S[^,{}=\n]*(?:,[^,{}=\n]+)*)$", head
        )
        shown = f" ('{listed.group(1)} {listed.group(2).strip()}')" if listed else ""
        return (
            comma,
            1,
            (
                f"a list ends without a ','{shown}: the ',' before '{m.group(3)}' makes it one "
                "more value of the list; remove it"
            ),
        )
    return None


_HEX_COLOR = re.compile(r"^[ \t]*(\w+)[ \t]+(#[0-9A-Fa-f]{3,8})[ \t]*$")


def hex_color_comment(line: str) -> Found | None:
    """'color #b07040' (``line`` from the key on): '#' starts a comment, so the key takes the
    next line's first word as its value. (offset in ``line``, length, sentence)"""
    found = _HEX_COLOR.search(line)
    if found is None:
        return None
    return found.start(2), len(found.group(2)), _quote_it(found.group(1), found.group(2))


def _quote_it(key: str, color: str) -> str:
    """``key``'s '#' colour read as a comment, and how to write it."""
    return (
        f"'#' starts a comment, so the {key} was read as one: write it in quotes, "
        f"'{key} \"{color}\"'"
    )


# a '#' colour and the word before it, on one line: 'color #b07040 }', 'kg*m^2 #ff0000 }'
_COLOR_AFTER = re.compile(r"(?<![\w\"])(\w+)?[ \t]+(#[0-9A-Fa-f]{3,8})(?![\w#])")


def hex_color_at(text: str, start: int) -> Found | None:
    """A '#' colour written after the word at ``start`` (from the whitespace before it, when
    no word): '#' starts a comment. The word is named as the colour's key when it is one
    ('color #b07040'), not when it ends a value ('2' of 'kg*m^2', 'kg' of '1 kg', ')'). When
    a '}' follows on the line, the comment took it and its block stayed open. (offset in
    ``text``, length, sentence)"""
    line_end = text.find("\n", start)
    line_end = len(text) if line_end < 0 else line_end
    found = _COLOR_AFTER.match(text, start, line_end)
    if found is None:
        return None
    key, color, at = found.group(1), found.group(2), found.start(2)
    before = text[text.rfind("\n", 0, start) + 1 : start].rstrip(" \t")
    ends_value = False  # the word is the unit of the value before it: '1 kg', '(0, 1) m'
    if key is not None and re.search(r"(?:(?<![\w.^*/])[\d.]+(?:[eE][-+]?\d+)?|\))$", before):
        try:
            parse_unit(key)
            ends_value = True
        except UnitError:
            pass
    if key is not None and re.fullmatch(r"[A-Za-z_]\w*", key) and not ends_value:
        told = _quote_it(key, color)
    else:
        told = (
            f"'#' starts a comment, so '{color}' was read as one: a color is a property of "
            f"its own, written in quotes, as in 'color \"{color}\"'"
        )
    if "}" in text[at:line_end]:
        told += "; the '}' after it was read as part of the comment, so its block stayed open"
    return at, len(color), told


def hex_color_line_before(text: str, pos: int) -> Found | None:
    """A 'color #b07040' line right before ``pos``'s line (blank lines aside), whose key took
    the first word of ``pos``'s line: the parse failed because of it."""
    end = text.rfind("\n", 0, pos)
    while end > 0:
        start = text.rfind("\n", 0, end) + 1
        if text[start:end].strip():
            found = hex_color_comment(text[start:end])
            return None if found is None else (start + found[0], found[1], found[2])
        end = start - 1
    return None


NOT_NUMBERS = ("nan", "inf", "infinity")


def not_a_number(word: str) -> str:
    """What 'nan' or 'inf' written as a value is told, wherever it is."""
    return (
        f"'{word}' is not a number legdsl reads: every quantity is a finite number with its "
        "unit, as in '10 kg'"
    )


def not_a_number_name(tree: object, text: str) -> Diagnostic | None:
    """The first 'nan' or 'inf' in ``tree`` (parsed from ``text``) that parsed as a name in an
    expression ('inf * stroke') and is declared nowhere in it: it is no name to declare, but a
    number legdsl does not read. A file that declares one ('param NAN = 2', as C names go)
    uses its own."""
    if re.search(r"(?<![\w.])(?:nan|inf)", text, re.IGNORECASE) is None:
        return None  # the tree is not walked for nothing
    declared: set[str] = set()
    used: list[ast.EName] = []
    _names(tree, declared, used)
    return next((Diagnostic(e.span, not_a_number(e.ident.name)) for e in used
                 if e.ident.name not in declared), None)  # fmt: skip


def _names(tree: object, declared: set[str], used: list[ast.EName]) -> None:
    """The names ``tree`` declares (every name outside an expression's) and the expressions'
    names that read as a number legdsl does not read."""
    if isinstance(tree, ast.EName):
        if tree.ident.name.lower() in NOT_NUMBERS:
            used.append(tree)
        return
    if isinstance(tree, ast.Ident):
        declared.add(tree.name)
        return
    if isinstance(tree, Span | str):
        return
    if isinstance(tree, tuple | list):
        parts: list[object] = list(tree)
    elif dataclasses.is_dataclass(tree) and not isinstance(tree, type):
        parts = [getattr(tree, f.name) for f in dataclasses.fields(tree)]
    else:
        return
    for part in parts:
        _names(part, declared, used)
