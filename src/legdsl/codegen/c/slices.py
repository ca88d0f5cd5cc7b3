"""The ``NAME_some`` twins of the kinematic functions: the outputs of chosen parts, same doubles.

The C runtime often needs part of a kinematic function's result: the Jacobians of the feet on
the ground, the velocities of the feet at or under it, one foot and one hip for the foot placer.
``NAME_some(..., want, out, err)`` writes the outputs of part ``p`` only where ``want[p]`` is set
and leaves the rest of ``out`` as it was. A part is one contact of the contact functions, the
position or the rotation of one body of the body functions (``SLICED``).

Its statements are ``NAME``'s, printed the same way and in the same order, each run where a
wanted output depends on it, so every double it writes is the one ``NAME`` writes there (the
same operations on the same inputs). It flags in ``*err`` the first error ``NAME`` flags: a
statement that may fail runs always (with what it depends on), except a sine or cosine of a
coordinate, which where skipped flags Python's domain error where the coordinate is infinite,
as the call would (``leg_math1``: the sine of anything else finite or NaN never fails).
"""

from __future__ import annotations

import re
from collections.abc import Iterator

from legdsl.codegen.c.printer import INDENT, CPrinter, flatten
from legdsl.lower.straightline import Assign, Comment, Unpack
from legdsl.lower.symbolic import Function, Nested

# The functions with a ``_some`` twin, and the depth in their nested result of one part.
SLICED = {
    "contact_positions": 1,  # per contact: (x, y, z)
    "contact_velocities": 1,
    "contact_jacobians": 1,  # per contact: its three rows
    "contact_angular_jacobians": 1,
    "body_poses": 2,  # per body: position, then rotation
    "body_velocities": 2,  # per body: linear, then angular velocity
}

_CALL = re.compile(r"(?<!\w)(leg_\w+)\(")
_NAME = re.compile(r"[A-Za-z_]\w*")
_TRIG = re.compile(r"^leg_(sin|cos)\((\w+)\)$")


def parts(function: Function) -> list[list[int]]:
    """The indices in ``out`` of each part's outputs, part by part."""
    return parts_of(function.result, SLICED[function.name])


def parts_of(result: Nested, depth: int) -> list[list[int]]:
    """The flat indices of the items ``depth`` levels down in a nested result, item by item."""

    def at_depth(value: Nested, level: int) -> Iterator[Nested]:
        if level == depth or not isinstance(value, list | tuple):
            yield value
        else:
            for item in value:
                yield from at_depth(item, level + 1)

    found, start = [], 0
    for part in at_depth(result, 0):
        size = len(flatten(part))
        found.append(list(range(start, start + size)))
        start += size
    return found


def signature(function: Function) -> str:
    params = ", ".join(f"const double *{p}" for p in function.params)
    return f"void {function.name}_some({params}, const unsigned char *want, double *out, int *err)"


def _may_fail(text: str, coordinates: set[str]) -> bool:
    """Whether a statement's C text may flag an error, unless it is a sine or cosine of a
    coordinate (whose failing, where skipped, is checked on the coordinate)."""
    trig = _TRIG.match(text)
    return bool(_CALL.search(text)) and (trig is None or trig.group(2) not in coordinates)


def function_text(function: Function) -> str:
    """``NAME_some``: ``NAME``'s statements, each guarded by the parts that need it."""
    printer = CPrinter.for_function(function)
    by_part = parts(function)
    everyone = frozenset(range(len(by_part)))
    leaves = [printer.print(leaf) for leaf in flatten(function.result)]
    part_of = {k: p for p, ks in enumerate(by_part) for k in ks}
    coordinates = {
        printer.c_name(st.target.name) for st in function.statements if isinstance(st, Unpack)
    }
    # each assignment's C name and text, and the parts that need it (all parts for one that
    # may fail, so that it fails where NAME does), found from the outputs backwards
    names, texts = {}, {}
    for i, st in enumerate(function.statements):
        if isinstance(st, Assign):
            names[i] = printer.c_name(function.name_of(st.target))
            texts[i] = printer.print(st.value)
    where = {name: i for i, name in names.items()}
    needs: dict[int, frozenset[int]] = {
        i: everyone if _may_fail(text, coordinates) else frozenset() for i, text in texts.items()
    }
    for k, text in enumerate(leaves):
        for name in _NAME.findall(text):
            if name in where:
                i = where[name]
                needs[i] = needs[i] | (everyone if _CALL.search(text) else {part_of[k]})
    for i in sorted(needs, reverse=True):
        for name in _NAME.findall(texts[i]):
            if name in where and where[name] != i:
                needs[where[name]] = needs[where[name]] | needs[i]

    lines = [signature(function), "{"]
    if any("leg_sin(" in t or "leg_cos(" in t for t in texts.values()):
        lines.append(f"{INDENT}leg_trig_entry *const leg_trig_here = leg_trig_table();")
    guarded = [names[i] for i in names if needs[i] != everyone]
    if guarded:
        lines.append(f"{INDENT}double {', '.join(guarded)};")
    run: list[int] = []

    def close() -> None:
        if not run:
            return
        group = needs[run[0]]
        if group == everyone:
            lines.extend(f"{INDENT}const double {names[i]} = {texts[i]};" for i in run)
        else:
            lines.append(f"{INDENT}if ({_wanted(group)}) {{")
            lines.extend(f"{INDENT * 2}{names[i]} = {texts[i]};" for i in run)
            trig = [_TRIG.match(texts[i]) for i in run]
            skipped = list(dict.fromkeys(m.group(2) for m in trig if m is not None))
            if skipped:  # the sines and cosines skipped, failing where their calls would
                infinite = " || ".join(f"isinf({x})" for x in skipped)
                lines.append(f"{INDENT}}} else if ({infinite}) {{")
                lines.append(f"{INDENT * 2}leg_flag(err, LEG_EDOM);")
            lines.append(f"{INDENT}}}")
        run.clear()

    for i, st in enumerate(function.statements):
        if isinstance(st, Unpack):
            close()
            lines.append(
                f"{INDENT}const double {printer.c_name(st.target.name)} = {st.array}[{st.index}];"
            )
        elif isinstance(st, Comment):
            close()
            lines.append(f"{INDENT}/* {st.text} */")
        elif isinstance(st, Assign):
            if run and needs[run[0]] != needs[i]:
                close()
            run.append(i)
    close()
    for p, ks in enumerate(by_part):
        failing = [k for k in ks if _CALL.search(leaves[k])]
        for k in failing:  # computed whether wanted or not, in NAME's order
            lines.append(
                f"{INDENT}{{ const double o = {leaves[k]}; if (want[{p}]) out[{k}] = o; }}"
            )
        rest = [k for k in ks if k not in failing]
        if rest:
            lines.append(f"{INDENT}if (want[{p}]) {{")
            lines.extend(f"{INDENT * 2}out[{k}] = {leaves[k]};" for k in rest)
            lines.append(f"{INDENT}}}")
    lines.append(f"{INDENT}(void)err;")
    lines.append("}")
    return "\n".join(lines)


def _wanted(group: frozenset[int]) -> str:
    return " || ".join(f"want[{p}]" for p in sorted(group)) if group else "0"
