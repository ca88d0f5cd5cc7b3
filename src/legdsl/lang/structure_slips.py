"""Slips in a file's structure that the parser meets later than they were made: one '}' too
many (the block it closes early makes the next, correct line misplaced), a colour without
quotes whose comment took a one-line block's '}', a file to 'use' named without quotes, and
a line of a controller that starts with no kind of declaration ('kp2 = 1 N*m/rad', 'let',
a half-typed 'pa'). Each answer is (offset, length, sentence), as ``habits``' are.
"""

from __future__ import annotations

import difflib
import re

from lark.exceptions import UnexpectedEOF, UnexpectedInput, UnexpectedToken

from legdsl.lang.context import innermost
from legdsl.lang.lalr import lark_parser
from legdsl.lang.stray_words import alone_on_its_line
from legdsl.lang.value_slips import hex_color_at

Found = tuple[int, int, str]

# what a line of a controller or shared part starts with, as the grammar lists them
_CONTROLLER_LINES = (
    "input", "param", "signal", "roles", "start", "path", "own", "include", "action", "table",
)  # fmt: skip
_OWNER = {"controller": "a controller", "shared": "a shared part"}


def structure_slip(text: str, masked: str, pos: int, kind: str, expected: set[str]) -> Found | None:
    """The first of this module's slips that made the parse fail at ``pos``."""
    return (
        _color_took_brace(text, masked, pos)
        or _extra_brace(text, masked, pos, kind)
        or _unquoted_use(text, masked, pos)
        or _controller_line(masked, pos, kind, expected)
    )


def _open_brace_before(masked: str, pos: int) -> int | None:
    """Where the innermost '{' still open at ``pos`` is."""
    depth = 0
    for i in range(pos - 1, -1, -1):
        if masked[i] == "}":
            depth += 1
        elif masked[i] == "{":
            if not depth:
                return i
            depth -= 1
    return None


_COLOR_THEN_BRACE = re.compile(r"(?<![\w\"])(?:\w+)?[ \t]+#[0-9A-Fa-f]{3,8}(?![\w#])[^\n]*\}")


def _color_took_brace(text: str, masked: str, pos: int) -> Found | None:
    """'body b ... { mass 1 kg  color #a0a0a0 }': the '#' comments out the '}', so the block
    is still open where the parse fails, a line or more later (the last such before ``pos``)."""
    for found in reversed(list(_COLOR_THEN_BRACE.finditer(text, 0, pos))):
        hash_at = text.index("#", found.start())
        first = len(text[:hash_at].rstrip(" \t")) - 1  # the key's last letter, or the value's
        if masked[hash_at] != " " or first < 0 or not masked[first].strip():
            continue  # the '#' in a string, or the whole of it in a comment
        told = hex_color_at(text, found.start())
        if told is not None:
            return told
    return None


def _indent(masked: str, at: int) -> int:
    line_start = masked.rfind("\n", 0, at) + 1
    return len(masked[line_start:at]) - len(masked[line_start:at].lstrip(" \t"))


def _misplaced(masked: str, close: int, opener: int | None) -> bool:
    """Whether the '}' at ``close`` looks out of place for the block it closes: on a line of
    its own but not under its block's first line, or after other text though its block
    opened on another line. (Every '}' closes something in a file written tidily: this is
    how one too many shows.)"""
    if opener is None:
        return True
    first_on_line = not masked[masked.rfind("\n", 0, close) + 1 : close].strip()
    if first_on_line:
        return _indent(masked, close) != _indent(masked, opener)
    return "\n" in masked[opener:close]


def _passes(text: str, pos: int) -> bool:
    """Whether ``text`` parses, or parses on from the line of ``pos`` to a mistake two lines
    or more further (one just after may be the same slip read another way, and a block left
    open at the end is what taking away a '}' it needs gives)."""
    try:
        lark_parser().parse(text, start="start")
    except UnexpectedInput as err:
        at_end = isinstance(err, UnexpectedToken) and err.token.type == "$END"
        if at_end or isinstance(err, UnexpectedEOF) or err.pos_in_stream is None:
            return False
        return text.count("\n", pos, err.pos_in_stream) >= 2
    return True


def _under_indented(masked: str, pos: int) -> list[int]:
    """The '}'s before ``pos``, last first, that are alone on their line (but for what a
    line may end with) and followed by a line indented deeper than they are."""
    found = []
    for m in re.finditer(r"(?m)^([ \t]*)\}[ \t;]*\n((?:[ \t]*\n)*)([ \t]*)\S", masked[:pos]):
        if len(m.group(3).expandtabs()) > len(m.group(1).expandtabs()):
            found.append(m.start() + len(m.group(1)))
    return found[::-1]


def _block_name(masked: str, opener: int) -> str:
    line_start = masked.rfind("\n", 0, opener) + 1
    words = re.findall(r"[A-Za-z_]\w*", masked[line_start:opener])
    line = masked.count("\n", 0, opener) + 1
    if not words:
        return f"the block of line {line}"
    if words[0] in ("creature", "controller", "shared", "body", "leg", "template", "action",
                    "scene") and len(words) > 1:  # fmt: skip
        return f"{words[0]} '{words[1]}' (line {line})"
    return f"the {words[0]}" + ("" if words[0] == "table" else " block") + f" (line {line})"


def _extra_brace(text: str, masked: str, pos: int, kind: str) -> Found | None:
    """One '}' too many just before ``pos``: a misplaced '}' without which the file parses
    past the line the parse failed on."""
    closes = [i for i in range(pos - 1, -1, -1) if masked[i] == "}"][:3]
    if kind == "RBRACE":  # the '}' the parse failed at, after those, which may have closed early
        closes.append(pos)
    # further back, a '}' on its own line whose next line is indented deeper: the file read on
    # outside its block ('action' is at home there too) until something was not
    under = _under_indented(masked, pos)[:10]
    for close in closes + [i for i in under if i not in closes]:
        opener = _open_brace_before(masked, close)
        if close not in under and not _misplaced(masked, close, opener):
            continue
        if not _passes(text[:close] + " " + text[close + 1 :], pos):
            continue
        closed = (
            "closes nothing: every block before it is closed already"
            if opener is None
            else f"closes {_block_name(masked, opener)}, and what follows is read outside it"
        )
        return close, 1, f"one '}}' too many: this one {closed}; remove it"
    return None


def _unquoted_use(text: str, masked: str, pos: int) -> Found | None:
    """'use raibert.leg', 'use lib/gaits.leg': a file's path, which is written in quotes."""
    line_start = masked.rfind("\n", 0, pos) + 1
    used = re.match(r"[ \t]*use[ \t]+([^\s\"#]+)", masked[line_start:])
    if used is None or line_start + used.start(1) > pos:
        return None
    path = used.group(1)
    return (
        line_start + used.start(1),
        len(path),
        f"a file to use is named in quotes: write 'use \"{path}\"' (a bare name, as "
        "'use raibert', is a file of the standard library)",
    )


def _controller_line(masked: str, pos: int, kind: str, expected: set[str]) -> Found | None:
    """A line of a controller or shared part that starts with none of the kinds of its
    declarations: a name given a value ('kp2 = 1 N*m/rad'), 'let', a half-typed word."""
    kinds = [k for k in _CONTROLLER_LINES if k in expected]
    owner = _OWNER.get(innermost(masked, pos))
    line_start = masked.rfind("\n", 0, pos) + 1
    word = re.match(r"[A-Za-z_]\w*", masked[pos:])
    if "param" not in kinds or owner is None or word is None or masked[line_start:pos].strip():
        return None
    written = word.group()
    if written == "let":
        return (
            pos,
            len(written),
            "'let' names a value within a table row or an action; at a controller's level "
            "declare it with 'signal NAME = ...' (an expression) or 'param NAME = ...' (a "
            "number with its unit)",
        )
    if re.match(r"[ \t]*=(?!=)", masked[pos + len(written) :]):
        return (
            pos,
            len(written),
            f"a declaration starts with its kind: write 'param {written} = ...' for a number "
            f"with its unit, 'signal {written} = ...' for an expression, or 'input "
            f"{written} = ...' for a command",
        )
    if written == "state":
        return pos, len(written), "a table row goes inside the controller's 'table { ... }'"
    meant = [k for k in kinds if k.startswith(written)] or difflib.get_close_matches(
        written, kinds, n=1, cutoff=0.6
    )
    listed = ", ".join(f"'{k}'" for k in kinds)
    return (
        pos,
        len(written),
        f"'{written}' cannot start a line of {owner}: its lines start with {listed}"
        + (f"; did you mean '{meant[0]}'?" if len(meant) == 1 else ""),
    )


_ALONE_ALLOWED = ("planar", "spatial")  # the lines that are one word


def missing_value(text: str, masked: str, pos: int, kind: str) -> Found | None:
    """A line without the value it needs ('gravity' alone, 'param kv ='): the parser took the
    next line's first word as that value and failed on that next line (at ``pos``), where
    what it says would be beside the point."""
    line_start = masked.rfind("\n", 0, pos) + 1
    before = masked[:line_start].rstrip()
    last_start = before.rfind("\n") + 1
    last = before[last_start:]
    if masked.count("\n", last_start, pos) == 0 or not last.strip():
        return None
    nxt = re.match(r"\s*([A-Za-z_]\w*)", masked[line_start:])
    taken = nxt.group(1) if nxt is not None else None
    alone = re.fullmatch(r"[ \t]*([A-Za-z_]\w*)[ \t]*", last)
    if alone is not None and alone.group(1) not in _ALONE_ALLOWED:
        word = alone.group(1)
        return last_start + alone.start(1), len(word), alone_on_its_line(word, taken)
    assigned = re.fullmatch(r"[ \t]*(?:([A-Za-z_]\w*)[ \t]+)?([A-Za-z_]\w*)[ \t]*(=)[ \t]*", last)
    if assigned is not None:
        kind_word, name = assigned.group(1), assigned.group(2)
        written = f"{kind_word} {name}" if kind_word else name
        return (
            last_start + assigned.start(3),
            1,
            f"the value of '{name}' is missing: write it after the '=' on the same line, "
            f"'{written} = VALUE'"
            + (f"; the next line's '{taken}' was read as its value" if taken else ""),
        )
    return None
