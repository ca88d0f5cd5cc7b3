"""Where a position is in a .leg text, for the messages of ``legdsl.lang.habits``: the block
around it, whether its values are expressions (a controller's) or plain values (a
creature's), inside parentheses."""

from __future__ import annotations

from collections.abc import Iterator


def opening(before: str) -> int:
    """Where the '(' is that the ')' ending ``before`` closes."""
    depth = 0
    for i in range(len(before) - 1, -1, -1):
        depth += {")": 1, "(": -1}.get(before[i], 0)
        if depth == 0:
            return i
    return 0


def _enclosing(masked: str, pos: int) -> Iterator[str]:
    """The first word of the line opening each block still open at ``pos``, innermost first."""
    depth = 0
    for i in range(pos - 1, -1, -1):
        if masked[i] == "}":
            depth += 1
        elif masked[i] == "{" and depth:
            depth -= 1
        elif masked[i] == "{":
            header = masked[masked.rfind("\n", 0, i) + 1 : i].split()
            yield header[0] if header else ""


def innermost(masked: str, pos: int) -> str:
    """The first word of the line that opens the innermost block still open at ``pos``."""
    return next(_enclosing(masked, pos), "")


def in_expression(masked: str, pos: int) -> bool:
    """Whether ``pos`` is inside a controller, shared part or action (where values are
    expressions), rather than a creature or a scene."""
    for word in _enclosing(masked, pos):
        if word in ("controller", "shared", "action", "table", "each"):
            return True
        if word in ("creature", "scene", "template"):
            return False
    return False


def in_parentheses(masked: str, pos: int) -> bool:
    line_start = masked.rfind("\n", 0, pos) + 1
    segment = masked[line_start:pos]
    return segment.count("(") > segment.count(")")
