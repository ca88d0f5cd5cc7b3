"""Numbers and vectors with units, checked for their dimension: the checker's smallest part,
used by the creature, the controller and the path checks alike."""

from __future__ import annotations

import contextlib
import difflib
import functools
import math
import re
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

from legdsl.ir.model import Model
from legdsl.lang import ast
from legdsl.lang.errors import Diagnostics, Span
from legdsl.lang.habits import unit_after_slash, unit_after_star
from legdsl.lang.units import (
    KINDS,
    Dim,
    UnitError,
    describe,
    other_system,
    out_of_range,
    parse_unit,
    unknown_unit,
)

STDLIB = Path(__file__).parents[1] / "stdlib"


@functools.cache
def stdlib_actions() -> dict[str, str]:
    """Each top-level action of the standard library, with the library that has it, for
    the advice on an unknown action ('use raibert')."""
    out: dict[str, str] = {}
    for path in sorted(STDLIB.glob("*.leg")):
        for name in re.findall(r"^action\s+(\w+)\s*\(", path.read_text(), re.MULTILINE):
            out.setdefault(name, path.stem)
    return out


# A creature's name names files and directories (generated/NAME/, runs/NAME/, NAME.xml), and a
# controller's too (generated/NAME/control_CONTROLLER.py): they must fit a file name.
MAX_NAME = 64


def too_long(what: str, name: str) -> str:
    return (
        f"this {what} name is {len(name)} characters long; at most {MAX_NAME} "
        f"(it names files, such as generated/NAME/), so shorten it"
    )


def stdlib_name(path: str | Path) -> str | None:
    """``stdlib/NAME`` for a file of legdsl's standard library, else None. Known by its place
    in a ``legdsl`` package, not by this process's copy of it: a compile's spawned workers (or a
    Dask cluster's) may have imported legdsl from another copy than the one that read the file."""
    path = Path(path)
    in_a_legdsl = path.parent.name == "stdlib" and path.parent.parent.name == "legdsl"
    if path.is_absolute() and in_a_legdsl and (STDLIB / path.name).is_file():
        return f"stdlib/{path.name}"
    return None


def place_of(span: Span) -> str:
    """``file:line:col`` for a note (the file as ``shown_path`` tells it)."""
    return f"{shown_path(span.file)}:{span.line}:{span.col}"


def shown_path(file: str | Path) -> str:
    """A file for a message: the standard library by its own name, another file relative to
    the working directory where it can be (never a machine's absolute path)."""
    path = Path(file)
    if path.is_absolute():
        library = stdlib_name(path)
        if library is not None:
            path = Path(library)
        else:
            with contextlib.suppress(ValueError):
                path = path.relative_to(Path.cwd())
    return path.as_posix()


def did_you_mean(word: str, choices: Iterable[str]) -> str:
    close = difflib.get_close_matches(word, list(choices), n=1)
    return f"; did you mean '{close[0]}'?" if close else ""


def owning_creature(
    decl: ast.ControllerDecl | ast.SceneDecl,
    example: str,
    tree: ast.SourceFile,
    models: list[Model],
    diag: Diagnostics,
) -> Model | None:
    """The creature a controller or scene belongs to: the one named after ``for``, or the
    file's only one; else an error and None. ``example`` starts the fix the message shows
    (``controller run``). A creature of the file that failed its own check is no unknown one."""
    by_name = {m.name: m for m in models}
    if decl.creature is not None:
        model = by_name.get(decl.creature.name)
        written = {c.name.name for c in tree.creatures}
        if model is None and tree.creatures and decl.creature.name not in written:
            advice = did_you_mean(decl.creature.name, by_name)
            if not advice and tree.uses:  # a creature of a used file is not brought in
                advice = (
                    f": a {example.split()[0]} belongs to a creature of its own file ('use' "
                    "brings in actions and shared parts, not creatures)"
                )
            diag.error(decl.creature.span, f"unknown creature '{decl.creature.name}'{advice}")
        return model
    if len(models) == 1:
        return models[0]
    if models:
        diag.error(
            decl.name.span,
            f"this file has several creatures ({', '.join(m.name for m in models)}): say which "
            f"one, as in '{example.split()[0]} {decl.name.name} for {models[0].name} {{ ... }}'",
        )
    return None


def unit_hint(kind: str) -> str:
    return KINDS[kind][1]


@dataclass
class _Num:
    """A checked scalar: its SI value and the span it came from."""

    value: float
    span: Span


class ValueChecker:
    """Numbers and vectors with units, checked for their dimension; errors go to ``diag``."""

    def __init__(self, diag: Diagnostics):
        self.diag = diag

    def err(self, span: Span, message: str) -> None:
        self.diag.error(span, message)

    def scalar(self, value: ast.Value, kind: str, what: str) -> float | None:
        """A number of dimension ``kind``; a bare number is accepted only if dimensionless or 0."""
        if doubled_minus(value, self.err):
            return None
        sign = 1.0
        node = value
        while isinstance(node, ast.Neg):
            sign, node = -sign, node.value
        if not isinstance(node, ast.Number):
            unit = (  # not "a unit of no unit"; a name or a list is no number here
                ""
                if kind == "dimensionless"
                else f" with a unit of {unit_hint(kind)}: write the one number itself, as in "
                f"'0.5 {unit_hint(kind)}'"
            )
            self.err(value.span, f"{what} must be a number{unit}")
            return None
        q = node.quantity
        trouble = out_of_range(node.text, q.value)
        if trouble is not None:
            self.err(node.span, trouble)
            return None
        want = KINDS[kind][0]
        if q.unitless:
            if kind != "dimensionless" and q.value != 0.0:
                self.err(
                    node.span,
                    f"{what} needs a unit: write e.g. "
                    f"'{'-' if sign < 0 else ''}{node.text} {unit_hint(kind)}'",
                )
                return None
            return sign * q.value
        if q.dim != want:
            self.err(node.span, wrong_dimension(what, kind, node.text, q.dim))
            return None
        return sign * q.value

    def vector(
        self,
        value: ast.Value,
        kind: str,
        n: int,
        what: str,
        axes: str | None = None,
        example: str | None = None,
        within: str = "",
    ) -> tuple[float, ...] | None:
        """A tuple of ``n`` numbers of dimension ``kind``; a unit after ')' applies to all.
        ``axes`` names the components in the error (a planar creature's (x, z) if n is 2),
        ``within`` what asks for them (' in a spatial creature'); ``example`` is the error's
        valid vector where zeros are not (a direction)."""
        if not isinstance(value, ast.Vector):
            self.err(
                value.span,
                f"{what} must be a vector of {n} numbers, as in "
                f"{example or example_vector(n, kind)}",
            )
            return None
        if len(value.items) != n:
            names = (
                f" ({axes}){within}" if axes else " (x, z) in a planar creature" if n == 2 else ""
            )
            self.err(
                value.span,
                f"{what} needs {n} components{names}, got {len(value.items)}; write {n}, as in "
                f"{example or example_vector(n, kind)}",
            )
            return None
        if value.unit is not None:
            factor, dim = parse_unit(value.unit)
            if dim != KINDS[kind][0]:
                assert value.unit_span is not None
                self.err(value.unit_span, wrong_dimension(what, kind, value.unit, dim))
                return None
            out = []
            for item in value.items:
                v = self.scalar(
                    item, "dimensionless", f"a component of {what} (the unit is after ')')"
                )
                if v is None:
                    return None
                if not math.isfinite(v * factor):
                    self.err(item.span, f"{what} is too large")
                    return None
                if v != 0 and v * factor == 0:
                    self.err(item.span, f"{what} is too small: nearer 0 than a double holds")
                    return None
                out.append(v * factor)
            return tuple(out)
        out = []
        for item in value.items:
            v = self.scalar(item, kind, f"a component of {what}")
            if v is None:
                return None
            out.append(v)
        return tuple(out)

    def one_scalar(self, prop: ast.Prop, kind: str, what: str) -> float | None:
        """The one number of a property (``mass 1.5 kg``) of dimension ``kind``."""
        if not isinstance(prop.value, ast.One):
            self.err(prop.value.span, takes_one_value(prop, unit_hint(kind)))
            return None
        return self.scalar(prop.value.value, kind, what)


def takes_one_value(prop: ast.Prop, unit: str = "") -> str:
    """A property given several values; ``mass 3 kg, shape box(...)`` is a ',' between two
    properties (the next one's name reads as a second value); ``mass value="10"``, an
    attribute as a URDF writes it. ``unit``: the unit its value takes, for the example."""
    said = f"'{prop.key.name}' takes one value"
    if isinstance(prop.value, ast.Assigns) and len(prop.value.items) == 1:
        item = prop.value.items[0]
        number = _number_text(item.value)
        if number is not None:
            unit = "" if unit == "no unit" or written_unit(number) else unit
            value = f"{number} {unit}".strip()
            shown = f'"{item.value.text}"' if isinstance(item.value, ast.String) else number
            return (
                f"{said}, written after its name without '=': '{prop.key.name} {value}', not "
                f"'{item.target.name}={shown}'"
            )
    if isinstance(prop.value, ast.Many):
        comma = _decimal_comma(*prop.value.values[:2])  # 'mass 5,5 kg', as in some locales
        if comma is not None:
            whole, fraction = comma
            return (
                f"{said}: '{whole},{fraction}' is two numbers; a decimal number is written "
                f"with a point, '{whole}.{fraction}'"
            )
        names = [v.ident.name for v in prop.value.values[1:] if isinstance(v, ast.NameValue)]
        if names:
            return (
                f"{said}, and '{names[0]}' after the ',' looks like the next property: "
                "properties are not separated by ','; leave a space between them, as in "
                "'mass 3 kg  inertia 0.1 kg*m^2'"
            )
    return said


def _number_text(value: ast.Value) -> str | None:
    """A number's text, also one written in quotes ('"10"'); None for anything else."""
    if isinstance(value, ast.Number):
        return value.text
    if isinstance(value, ast.String) and re.fullmatch(
        r"-?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?", value.text
    ):
        return value.text
    return None


# what other languages write for a truth value; legdsl has none
TRUTHS = ("True", "False", "true", "false", "TRUE", "FALSE")


def constant_advice(expr: ast.Expr) -> tuple[Span, str] | None:
    """How to write an input's or a parameter's value that is not a number with its unit,
    where it looks like one written as elsewhere: '2*cm', '1 /s' (a unit after an operator),
    'True' (legdsl has no truth values). (where, the sentence)"""
    if isinstance(expr, ast.EName) and expr.ident.name in TRUTHS:
        return (
            expr.span,
            f"legdsl has no '{expr.ident.name}': a parameter is a number with its unit (for a "
            "switch, 1 or 0, as in 'param k = 1'), and a condition is a comparison, as in "
            "'trunk.z > 2 m'",
        )
    ops: list[str] = []
    node: ast.Expr = expr
    while isinstance(node, ast.EBinary) and node.op in ("*", "/"):
        if not isinstance(node.right, ast.EName):
            return None
        ops.append(f"{node.op}{node.right.ident.name}")
        node = node.left
    if not ops or not isinstance(node, ast.EQuantity):
        return None
    number = node.text[: len(node.text) - len(written_unit(node.text))].strip()
    unit = written_unit(node.text) + "".join(reversed(ops))
    try:
        parse_unit(unit.lstrip("*/"))
    except UnitError:
        return None
    if unit.startswith("/"):
        return expr.span, unit_after_slash(number, unit[1:])
    if unit.startswith("*"):
        return expr.span, unit_after_star(number, unit[1:])
    return expr.span, f"a unit is written without spaces: write '{number} {unit}'"


def _decimal_comma(first: ast.Value, second: ast.Value) -> tuple[str, str] | None:
    """The two texts of one number written with a decimal comma (a bare whole number, a ','
    and the next number's digits with no space between them), else None."""
    if not (isinstance(first, ast.Number) and isinstance(second, ast.Number)):
        return None
    touching = first.span.end_line == second.span.line and (
        second.span.col == first.span.end_col + 1
    )
    if touching and first.text.isdigit() and second.text[:1].isdigit():
        return first.text, second.text
    return None


def written_unit(text: str) -> str:
    """The unit of a number as written ('deg' of '20 deg'), empty for a bare number."""
    match = re.match(r"\s*[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?", text)
    return text[match.end() :].strip() if match else text.strip()


def defined_by_both(what: str, files: Sequence[str], distance: int) -> str:
    """Two used files the same distance away that both define ``what`` ("action 'x'"):
    neither wins, and the message says how to choose."""
    uses = "uses" if distance > 1 else "use"
    return (
        f"{what} is defined by both {' and '.join(files)}, each {distance} '{uses}' away, so "
        "neither wins; rename it in one of them, or leave out the 'use' of the one you do not "
        "mean"
    )


def per_second(unit: str, want: Dim) -> str | None:
    """The unit to write where a rate ``want`` was written in the unit of what it is a rate
    of: the written unit per second where it scales unlike the kind's own ('20 deg' is meant
    as '20 deg/s', and '20 rad/s' would turn 57 times as fast), else the kind's own ('2 rad'
    as '2 rad/s', '2 m/s' as '2 m/s^2')."""
    if not unit:
        return None
    with contextlib.suppress(ValueError):
        factor, dim = parse_unit(f"{unit}/s")
        usual = next((u for d, u in KINDS.values() if d == want), None)
        if dim == want:
            return usual if usual is not None and factor == parse_unit(usual)[0] else f"{unit}/s"
    return None


def doubled_minus(value: ast.Value, err: Callable[[Span, str], None]) -> bool:
    """A value written with two minus signs (``--5 deg``, a key pressed twice, or a '-' typed
    before a pasted negative number): told, since it would read as +5 (a creature's value is
    one number with its unit, not arithmetic). True if told."""
    if isinstance(value, ast.Neg) and isinstance(value.value, ast.Neg):
        err(value.span, "two minus signs: '--' would read as '+'; write one '-' for a negative "
                        "value, or none")  # fmt: skip
        return True
    return False


def unit_to_write(written: str, want: Dim, declared: str) -> str | None:
    """The unit to advise for a value of dimension ``want`` written in the unit ``written``
    (perhaps none) where the file declared it in ``declared`` (perhaps none): the written unit
    per second, or over the declared unit's denominator, where that is wanted and scales
    unlike the wanted kind's unit (a turn rate given as '10deg' is '10deg/s', not '10rad/s',
    57 times as fast; a gain declared in deg/m given as '60deg' is '60deg/m'), else the
    declared unit (a bare 0.75 for 'param bend = 0.7 rad' is 0.75 rad, not deg); None if
    neither tells (the caller's kind's own unit then)."""
    if not measures(declared, want):
        declared = ""
    below = declared.partition("/")[2]
    over = f"{written}/{below}"
    per_below = over if written and below and measures(over, want) else None
    return per_second(written, want) or per_below or declared or None


def measures(unit: str, want: Dim) -> bool:
    """Whether ``unit`` is a unit of the dimension ``want``."""
    try:
        return bool(unit) and parse_unit(unit)[1] == want
    except UnitError:
        return False


def wrong_dimension(what: str, kind: str, written: str, dim: Dim) -> str:
    """'mass is a mass (kg), but '3 m' is a length (m)'; a rate written in the unit of
    what it is a rate of is told that unit per second."""
    unit = written_unit(written)
    for name, (kind_dim, example) in KINDS.items():
        if kind_dim == dim:  # its unit shown where it was written without one of its own
            found = (
                "dimensionless"
                if name == "dimensionless"
                else f"{article(name)} {name}" + ("" if unit else f" ({example})")
            )
            break
    else:
        found = f"a quantity in {describe(dim)}"
    if kind == "dimensionless":
        return f"{what} takes no unit, but '{written}' is {found}; leave the unit out"
    told = f"{what} is {article(kind)} {kind} ({unit_hint(kind)}), but '{written}' is {found}"
    rate = per_second(unit, KINDS[kind][0])
    number = written[: len(written) - len(unit)].strip()
    if rate is not None:
        told += f"; write e.g. '{number} {rate}'" if number else f"; write e.g. '{rate}'"
    else:
        told += (
            f"; give it in {unit_hint(kind)}"
            if number
            else f"; write its unit as {unit_hint(kind)}"
        )
    return told


def example_vector(n: int, kind: str) -> str:
    unit = "" if kind == "dimensionless" else " " + unit_hint(kind)
    return "(" + ", ".join(f"0{unit}" for _ in range(n)) + ")"


def article(word: str) -> str:
    return "an" if word[0] in "aeiou" else "a"


def misspelt_unit(node: ast.Expr) -> tuple[Span, str] | None:
    """In a constant written as a quantity whose unit goes on with a name that is no unit
    (``1 N*m/rdd``, read as 1 N*m over a name ``rdd``: joined without spaces, as a unit is
    written), where that name is and what to say: the whole unit's value in legdsl's units
    where it is from another system (``10 km/h``), else that the name is no unit."""
    name = _name_in_unit(node)
    if name is None:
        return None
    quantity = node
    while isinstance(quantity, ast.EBinary):
        quantity = quantity.left
    if not isinstance(quantity, ast.EQuantity):
        return name.span, unknown_unit(name.name)
    unit = written_unit(quantity.text)
    number = quantity.text.strip().removesuffix(unit).strip()
    written = unit + _unit_tail(node)
    if unit and other_system(written, number) is not None:
        start = quantity.span.end_col - len(unit)
        span = Span(node.span.file, node.span.line, start, node.span.end_line, node.span.end_col)
        return span, unknown_unit(written, number)
    return name.span, unknown_unit(name.name)


def _joined(node: ast.Expr) -> bool:
    """A quantity (or a product of one) and a name, with only ``*`` or ``/`` between them."""
    return (
        isinstance(node, ast.EBinary)
        and node.op in ("*", "/")
        and isinstance(node.left, ast.EQuantity | ast.EBinary)
        and isinstance(node.right, ast.EName)
        and node.left.span.end_line == node.right.span.line
        and node.right.span.col == node.left.span.end_col + 1
    )


def _name_in_unit(node: ast.Expr) -> ast.Ident | None:
    if not (isinstance(node, ast.EBinary) and node.op in ("*", "/")):
        return None
    if _joined(node) and isinstance(node.right, ast.EName):
        try:
            parse_unit(node.right.ident.name)
        except UnitError:
            return _name_in_unit(node.left) or node.right.ident
    return _name_in_unit(node.left)


def _unit_tail(node: ast.Expr) -> str:
    """The operators and names a quantity's unit goes on with: ``/h`` of ``10 km/h``."""
    if _joined(node) and isinstance(node, ast.EBinary) and isinstance(node.right, ast.EName):
        return _unit_tail(node.left) + node.op + node.right.ident.name
    return ""
