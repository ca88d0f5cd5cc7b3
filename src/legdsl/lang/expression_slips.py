"""Slips in a controller's expressions that the parser meets as a wrong token: a chained
comparison ('1 s < time < 2 s') and a function read as a unit ('2 min(...)': minutes).
The answer is (offset, length, sentence), as ``habits``' are; None when none fits.
"""

from __future__ import annotations

import re

Found = tuple[int, int, str]
NUMBER = r"(?<![\d.])(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?"  # a number as written

# The name that ends a run of word characters (its group 1: 'x' of '2x'), in linear time: the
# run is tried only from its start, and only the run that reaches the end (what follows it
# in a pattern is '[ \t]*$' or '$')
LAST_NAME = r"(?<!\w)(?=\w*+[ \t]*+$)\w*?([A-Za-z_]\w*)"

_COMPARISON = r"<=|>=|==|!=|<|>"


def expression_slip(text: str, masked: str, pos: int, kind: str) -> Found | None:
    """The slip that made the parse fail at ``pos`` (``masked``: ``text`` with strings and
    comments blanked; ``kind``: the token's type there), if one of these."""
    before = masked[:pos].rstrip(" \t")
    minutes = re.search(rf"({NUMBER})[ \t]*min$", before)
    if kind == "LPAR" and minutes is not None:
        return (
            before.rfind("min"),
            3,
            f"'min' right after a number is the unit minutes: to call the function, multiply, "
            f"as in '{minutes.group(1)} * min(...)'",
        )
    line_start = masked.rfind("\n", 0, pos) + 1
    here = re.match(_COMPARISON, masked[pos:])
    if here is not None:
        clause = re.split(r"[:;(]|\b(?:on|and|or|not)\b", masked[line_start:pos])[-1]
        first = re.search(rf"^(.*?)(?<!\s)\s*({_COMPARISON})\s*(.*?)$", clause.strip())
        rest = re.match(r"[^:;)\n]*", masked[pos + here.end() :])
        if first is not None and rest is not None and first.group(1) and first.group(3):
            a, op, b = first.groups()
            c = re.split(r"\b(?:and|or)\b", rest.group())[0].strip()
            return (
                pos,
                here.end(),
                f"comparisons do not chain: join two with 'and', as in "
                f"'{a} {op} {b} and {b} {here.group()} {c}'",
            )
    return None
