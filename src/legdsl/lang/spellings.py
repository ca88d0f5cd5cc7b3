"""Units and numbers written as other languages and books write them, which legdsl does not
read: a unit with spaces, parentheses or '**' between its symbols ('9.81 m s^-2',
'200 N s/m', 'm/(s^2)', 'm/s**2') and a number in hexadecimal, binary or octal or with
'_' between its digits ('0x10', '1_000'). Each is named with the way legdsl writes it
(``legdsl.lang.syntax_errors`` says so at a syntax error; ``parse`` reads past them)."""

from __future__ import annotations

import re
from dataclasses import dataclass

from legdsl.lang.errors import Diagnostic, Span
from legdsl.lang.lookalikes import lookalike
from legdsl.lang.units import UNITS, UnitError, looks_like_unit, parse_unit, suggest_unit

_UNIT_SYMBOL = "|".join(sorted(UNITS, key=len, reverse=True))


def mask(text: str) -> str:
    """``text`` with comments and strings blanked out (same length, same line breaks)."""
    return re.sub(r'"[^"\n]*"|#[^\n]*', lambda m: " " * len(m.group()), text)


def offset_span(file: str, text: str, start: int, length: int) -> Span:
    line = text.count("\n", 0, start) + 1
    col = start - (text.rfind("\n", 0, start) + 1) + 1
    return Span(file, line, col, line, col + length)


# The unit written after a number, loosely: symbols with spaces, parentheses or '**'
# between them ('9.81 m s^-2', '200 N s/m', 'm/(s^2)', 'm/s**2'), which legdsl does not read.
_LOOSE_ATOM = rf"(?:{_UNIT_SYMBOL})(?:(?:\^|\*\*)?-?\d+|\^\(-?\d+\))?(?![A-Za-z0-9_])"
# No two runs of blanks meet without a symbol between them ('[ \t]+\(?[ \t]*' would try
# every way of splitting a long run of blanks between them: minutes on a line that ends in
# 100 000 spaces), so each is read in linear time.
_LOOSE_SEP = r"(?:[ \t]*[*/][ \t]*(?:\([ \t]*)?|[ \t]+(?:\([ \t]*)?|[ \t]*\([ \t]*)"
_LOOSE_UNIT = re.compile(
    r"(?<![\w.])(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?[ \t]*"
    rf"({_LOOSE_ATOM}(?:[ \t]*\)|{_LOOSE_SEP}{_LOOSE_ATOM})*)"
)


@dataclass(frozen=True)
class UnitSpelling:
    written: str
    start: int
    suggestion: str
    message: str


def _tidy_unit(written: str) -> str | None:
    """``written`` in legdsl's spelling: '*' between symbols, '^' for powers, no
    parentheses ('/' divides by the one symbol after it), a lone trailing negative power
    as a division ('m*s^-2' is 'm/s^2'); None if that is no unit legdsl reads."""
    unbracketed = re.sub(r"\^\((-?\d+)\)", r"^\1", written)  # 'm*s^(-1)': its power's
    text = re.sub(r"(?<=[A-Za-z])(-?\d)", r"^\1", unbracketed.replace("**", "^"))
    parts = re.findall(r"[A-Za-z]+(?:\^-?\d+)?|[*/()]|[ \t]+", text)
    out: list[str] = []
    group: str | None = None  # the operator before an open parenthesis
    op = ""
    for part in parts:
        if part.isspace():
            op = op or "*"
        elif part in "*/":
            op = part
        elif part == "(":
            if group is not None:
                return None  # nested: leave it to the person
            group, op = op or "*", ""
        elif part == ")":
            group = None
        else:
            if out:
                sign = op or "*"
                if group == "/" and op:  # inside '/(...)' every factor divides
                    sign = "/" if op == "*" else "*"
                elif group == "/":
                    sign = "/"
                out.append(sign)
            out.append(part)
            op = ""
    tidy = "".join(out)
    negative = re.findall(r"\^-\d+", tidy)
    if "/" not in tidy and len(negative) == 1 and tidy.endswith(negative[0]):
        tidy = re.sub(r"\*([A-Za-z]+)\^-(\d+)$", r"/\1^\2", tidy)
        tidy = re.sub(r"\^1(?!\d)", "", tidy)
    try:
        parse_unit(tidy)
    except UnitError:
        return None
    return tidy


def unit_spelling(text: str, pos: int) -> UnitSpelling | None:
    """A unit spelt as elsewhere (spaces, parentheses, '**') around ``pos``, with how to
    write it."""
    masked = mask(text)
    line_start = masked.rfind("\n", 0, pos) + 1
    line_end = masked.find("\n", pos)
    line = masked[: line_end if line_end >= 0 else len(masked)]
    for m in _LOOSE_UNIT.finditer(line, line_start):
        written = m.group(1).rstrip()
        start = m.start(1)
        while written.endswith(")") and written.count(")") > written.count("("):
            written = written[:-1].rstrip()  # a call's or a vector's own ')'
        if not start <= pos <= start + len(written):
            continue
        tidy = _tidy_unit(written)
        if tidy is None or tidy == written:
            continue
        also = ""
        if re.search(r"\^\(-?\d+\)", written):
            why = "a unit takes no parentheses, around a power neither"
        elif "(" in written or ")" in written:
            why = "a unit takes no parentheses ('/' divides by the one symbol after it)"
        elif "**" in written:
            why = "a power in a unit is written with '^'"
        elif re.search(r"[A-Za-z]-?\d", written):  # 'm s-2', as SI tables write it
            why = "a unit's symbols are joined by '*' or '/', and a power is written with '^'"
            last = re.search(r"/([A-Za-z]+)(?:\^(\d+))?$", tidy)
            if last is not None and "/" not in written:  # as written, with its power
                also = f" (or '{tidy[: last.start()]}*{last[1]}^-{last[2] or 1}')"
        else:
            why = "a unit is written without spaces, its symbols joined by '*' or '/'"
        return UnitSpelling(written, start, tidy, f"{why}: write '{tidy}'{also}, not '{written}'")
    return None


# Numbers as other languages write them: 0x10, 0b101, 0o17, 1_000, 2_500.5.
_OTHER_NUMBER = re.compile(
    r"(?<![\w.])(?:0[xX][0-9a-fA-F_]+|0[bB][01_]+|0[oO][0-7_]+"
    r"|\d+(?:_\d+)+(?:\.\d+(?:_\d+)*)?|\d+\.\d+(?:_\d+)+)"
)


def other_numbers(file: str, text: str) -> tuple[list[Diagnostic], str]:
    """The numbers written as in other languages (hexadecimal, binary, octal, with '_'
    between digits), each reported, and ``text`` with each read as a plain number of the
    same length so the parse goes on to the file's other mistakes."""
    found: list[Diagnostic] = []
    read = text
    for m in _OTHER_NUMBER.finditer(mask(text)):
        written = m.group()
        plain = written.replace("_", "")
        if written[:2].lower() in ("0x", "0b", "0o"):
            value = int(plain, 0) if 2 < len(plain) <= 20 else None
            message = f"'{written}' is not a number legdsl reads: numbers are plain decimals" + (
                f", so write '{value}'" if value is not None else ", as in '16'"
            )
        else:
            message = (
                f"'{written}' is not a number legdsl reads: digits are written without '_', "
                f"as in '{plain}'"
            )
        found.append(Diagnostic(offset_span(file, text, m.start(), len(written)), message))
        # 1 stands in for it: its value is reported already, and 1 passes every check of sign
        read = read[: m.start()] + "1".ljust(len(written)) + read[m.end() :]
    return found, read


# A number and the word written after it on the same line, where its unit is ('10 kgg',
# '2 m/sec').
NUMBER_AND_WORD = re.compile(
    r"(?<![\w.])(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?[ \t]*([A-Za-z_°µμ][^\s,;:(){}\[\]=<>!#\"]*)"
)


def read_past_units(text: str, line: int) -> tuple[int, str]:
    """Each unknown unit after a number from ``line`` on with a likely meaning no longer than
    itself ('kgg' for 'kg'), replaced by it: (how many, the text so read). The parser reads
    past a file's misspelt units beyond the first it reports this way, unreported, at once
    (one by one, each costs a parse of the whole file)."""
    start = 0
    for _ in range(line - 1):
        start = text.index("\n", start) + 1
    count, read = 0, text
    for m in NUMBER_AND_WORD.finditer(mask(text), start):
        word = m.group(1)
        try:
            parse_unit(word)
            continue
        except UnitError:
            suggestion = suggest_unit(word) if looks_like_unit(word) else None
        if suggestion is not None and len(suggestion) <= len(word):
            count += 1
            read = read[: m.start(1)] + suggestion.ljust(len(word)) + read[m.end(1) :]
    return count, read


def unshown_units(file: str, text: str, count: int, line: int, shown: int) -> Diagnostic:
    """The last word on a file whose misspelt units from ``line`` on, ``count`` of them, were
    read past unreported (the first ``shown`` mistakes are), at the end of its last line."""
    lines = text.rstrip().split("\n")
    end = Span(file, len(lines), len(lines[-1]) + 1, len(lines), len(lines[-1]) + 2)
    units, them = ("unit is", "it") if count == 1 else ("units are", "them")
    return Diagnostic(
        end,
        f"{count} more misspelt {units} not shown, from line {line} on (legdsl names the "
        f"first {shown} of a file): fix those shown and check again to see {them}",
    )


_LINE_BREAKS = "\u2028\u2029"  # that editors draw as a line break: not one to the parser


def hidden_line_breaks(file: str, text: str) -> list[Diagnostic]:
    """Each line or paragraph separator in a comment or a string, named: the rest of its line
    is still the comment ('# ...<U+2028>use raibert' uses nothing), though it shows as a line
    of its own. (Elsewhere the parser stops at one, and names it.)"""
    if "\u2028" not in text and "\u2029" not in text:
        return []
    masked = mask(text)
    found = []
    for i in (i for i, ch in enumerate(text) if ch in _LINE_BREAKS and masked[i] != ch):
        named = lookalike(text[i]) or f"U+{ord(text[i]):04X} stands here"
        found.append(
            Diagnostic(
                offset_span(file, text, i, 1),
                f"{named}; in a comment or a string, what follows it on its line is part of "
                "it, though it shows as a line of its own",
            )
        )
    return found
