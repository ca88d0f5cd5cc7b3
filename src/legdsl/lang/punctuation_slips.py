"""Punctuation of another language where the parser expected legdsl's: a module's function
('np.clip('), ':' for '=' or for a block, a declaration's '=' without its name, a '{' that
opens a declaration inside an open block, ',' for ';', and a missing ',' or ')'. Each answer
is (offset, length, sentence), as ``habits``' are.
"""

from __future__ import annotations

import re

from lark import Token

from legdsl.lang.context import in_expression, innermost
from legdsl.lang.expression_slips import LAST_NAME
from legdsl.lang.spellings import mask
from legdsl.lang.value_slips import hex_color_comment

Found = tuple[int, int, str]

_PYTHON_MODULES = ("np", "numpy", "math", "torch", "jnp", "scipy")
_FUNCTION_NAMES = {"clip": "clamp", "fabs": "abs", "arctan2": "atan2", "where": "select"}


def punctuation(text: str, pos: int, token: Token | None, expected: set[str]) -> Found | None:
    """Punctuation of another language where the parser expected legdsl's (asked after the
    friendly table, whose sentences are more particular)."""
    if token is None:
        return None
    return _structure(text, mask(text), pos, token.type, expected)


_TOP = ("creature", "controller", "shared", "action", "scene", "use")


# the declarations written 'KIND NAME = ...'
_NAMED = ("param", "input", "signal", "let", "record", "instance")


def _structure(text: str, masked: str, pos: int, kind: str, expected: set[str]) -> Found | None:
    """Punctuation of another language where the parser expected legdsl's."""
    before = masked[:pos].rstrip()
    line_start = masked.rfind("\n", 0, pos) + 1
    first = masked[line_start:].split()[:1]
    word = re.match(r"[A-Za-z_]\w*", masked[pos:])
    prev = re.search(rf"{LAST_NAME}[ \t]*$", before)
    if kind == "LPAR" and re.search(
        r"(?:^|[^\w.])(" + "|".join(_PYTHON_MODULES) + r")\.(\w+)$", before
    ):
        module, name = re.search(r"(?<!\w)(\w+)\.(\w+)$", before).groups()  # type: ignore[union-attr]
        right = _FUNCTION_NAMES.get(name, name)
        start = len(before) - len(module) - len(name) - 1
        return (
            start,
            len(module) + 1 + len(name),
            (
                f"legdsl's functions are called by their own names, without a module: write "
                f"'{right}(...)', not '{module}.{name}(...)'"
            ),
        )
    if kind == "COLON" and "=" in expected:
        return (
            pos,
            1,
            "write '=' here, not ':', as in 'input speed = 1 m/s' or 'spring(k = 5000 N/m)'",
        )
    if kind == "COLON" and "{" in expected:
        return (
            pos,
            1,
            "a block opens with '{' and closes with '}', not ':', as in 'body trunk free { mass 10 kg }'",
        )
    if kind == "COLON" and "on" in expected:
        return (
            pos,
            1,
            "a table row reads 'state NAME on EVENT: action; action'; the 'on EVENT' is missing",
        )
    if kind == "EQUAL" and expected <= {"NAME"} and prev is not None and prev[1] in _NAMED:
        kind_word = prev[1]  # 'signal = select(...)': the name is missing, not the '='
        return (
            pos,
            1,
            f"the {kind_word}'s name is missing: give the {kind_word} a name, as in "
            f"'{kind_word} NAME = ...'",
        )
    if kind == "EQUAL" and expected <= {"NAME"} and prev is not None:
        after = masked[pos + 1 :].split()[:1]
        return (
            pos,
            1,
            f"'{prev.group(1)}' takes no '=': write '{prev.group(1)} {after[0] if after else 'NAME'}'",
        )
    if kind in ("QUANTITY", "NAME", "STRING") and expected == {"="} and prev is not None:
        return pos, 1, f"a '=' is missing after '{prev.group(1)}', as in 'param stroke = 2 cm'"
    if kind == "LBRACE" and expected and expected <= {"free", "fixed", "on"}:
        return (
            pos,
            1,
            (
                "say how the body hangs before its '{': 'body trunk free { ... }', 'body base "
                "fixed { ... }' or 'body shin on thigh via revolute knee { ... }'"
            ),
        )
    if (
        kind == "LBRACE"
        and first
        # a body holds no block: a '{' in one ('ground {', 'body b ... {') means it was left open
        and (first[0] in _TOP or innermost(masked, pos) == "body")
        and line_start + masked[line_start:].find(first[0]) < pos
    ):
        at = line_start + masked[line_start:].find(first[0])
        return (
            at,
            len(first[0]),
            (
                "a '}' is missing: a new declaration starts here while the block before it is still open"
            ),
        )
    if kind == "COMMA" and ";" in expected:
        return pos, 1, "actions in a table row or an action body are separated by ';', not ','"
    if kind == "NAME" and "," in expected and re.match(r"\w+[ \t]*=(?!=)", masked[pos:]) and word:
        return (
            pos,
            word.end(),
            f"a ',' is missing before '{word.group()}': separate them with commas",
        )
    if kind in ("QUANTITY", "NAME", "STRING") and {",", ")"} <= expected:
        example = (
            "'lengthen(active, 1 cm)'"
            if in_expression(masked, pos)
            else "'(0.1 m, 0 m)' or 'spring(k = 6000 N/m, b = 30 N*s/m)'"
        )
        return (
            pos,
            1,
            (
                "a ',' is missing before this: put commas between the arguments of a call and the "
                f"numbers of a vector, as in {example}"
            ),
        )
    if (
        ")" in expected
        and kind in ("RBRACE", "SEMICOLON", "$END", "STATE")
        and "(" in masked[line_start:pos]
        or (")" in expected and kind == "RBRACE")
    ):
        return pos, 1, "a ')' is missing before this: every '(' needs its ')'"
    for line in reversed(text[:pos].split("\n")[-4:]):
        found = hex_color_comment(line)
        if found is not None:
            return text.rfind(line, 0, pos) + found[0], found[1], found[2]
    return None
