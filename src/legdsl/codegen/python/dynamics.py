"""Lay out the generated dynamics module: jinja2 for the skeleton, ``printer`` for the math."""

from __future__ import annotations

from pathlib import Path

import jinja2
import sympy

from legdsl import __version__
from legdsl.codegen.fingerprints import model_fingerprint
from legdsl.codegen.python.printer import LegPrinter
from legdsl.ir.model import Model
from legdsl.lower.straightline import Assign, Comment, Unpack
from legdsl.lower.symbolic import Call, Function, Nested, SymbolicSystem

TEMPLATES = Path(__file__).parent / "templates"
LINE_LENGTH = 100
INDENT = "    "


def _environment() -> jinja2.Environment:
    return jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(TEMPLATES)),
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=True,
        autoescape=False,
    )


def format_result(value: Nested, indent: str, printer: LegPrinter | None = None) -> str:
    """A returned value on one line if it fits, else one item per line."""
    printer = printer or LegPrinter()
    flat = _one_line(value, printer)
    if len(indent) + len("return ") + len(flat) <= LINE_LENGTH or not isinstance(
        value, list | tuple
    ):
        return flat
    open_, close = ("[", "]") if isinstance(value, list) else ("(", ")")
    inner = indent + INDENT
    items = [f"{inner}{format_result(item, inner, printer)}," for item in value]
    return "\n".join([open_, *items, f"{indent}{close}"])


def _one_line(value: Nested, printer: LegPrinter) -> str:
    if isinstance(value, Call):
        return value.text
    if isinstance(value, list):
        return "[" + ", ".join(_one_line(v, printer) for v in value) + "]"
    if isinstance(value, tuple):
        inner = ", ".join(_one_line(v, printer) for v in value)
        return f"({inner},)" if len(value) == 1 else f"({inner})"
    return printer.print(value)


def function_body(function: Function) -> str:
    """The indented statements and return of one generated function."""
    printer = LegPrinter(function.names, function.bases)
    lines: list[str] = []
    for st in function.statements:
        if isinstance(st, Unpack):
            lines.append(f"{INDENT}{st.target.name} = {st.array}[{st.index}]")
        elif isinstance(st, Assign):
            lines.append(f"{INDENT}{function.name_of(st.target)} = {printer.print(st.value)}")
        elif isinstance(st, Comment):
            lines.append(f"{INDENT}# {st.text}")
    lines.append(f"{INDENT}return {format_result(function.result, INDENT, printer)}")
    return "\n".join(lines)


def _layout(model: Model) -> list[tuple[str, str, str, str]]:
    """(array index, name, unit, meaning) of every entry of q and v."""
    rows: list[tuple[str, str, str, str]] = []
    for joint in model.joints:
        if joint.is_free_3d:
            for k, axis in enumerate("xyz"):
                rows.append((f"q[{joint.q_start + k}]", axis, "m", "root origin, world"))
            for k, part in enumerate(("w", "x", "y", "z")):
                rows.append(
                    (f"q[{joint.q_start + 3 + k}]", f"q{part}", "", "root orientation quaternion")
                )
            continue
        for dof in joint.dofs:
            unit, how = ("rad", "hinge about") if dof.motion == "hinge" else ("m", "slide along")
            axis = ", ".join(_short(c) for c in dof.axis)
            rows.append((f"q[{dof.q_index}]", dof.name, unit, f"{joint.name}: {how} ({axis})"))
    for joint in model.joints:
        if joint.is_free_3d:
            for k, name in enumerate(("vx", "vy", "vz")):
                rows.append(
                    (f"v[{joint.v_start + k}]", name, "m/s", "root origin velocity, world axes")
                )
            for k, name in enumerate(("wx", "wy", "wz")):
                rows.append(
                    (
                        f"v[{joint.v_start + 3 + k}]",
                        name,
                        "rad/s",
                        "root angular velocity, body axes",
                    )
                )
            continue
        for dof in joint.dofs:
            unit = "rad/s" if dof.motion == "hinge" else "m/s"
            rows.append((f"v[{dof.v_index}]", dof.name, unit, f"rate of {dof.name}"))
    return rows


def _short(x: float) -> str:
    """``repr(float)`` (the shortest text that reads back to ``x``) without a trailing ``.0``."""
    text = repr(float(x))
    return text[:-2] if text.endswith(".0") else text


def _table(rows: list[tuple[str, str, str, str]]) -> list[str]:
    widths = [max((len(r[k]) for r in rows), default=0) for k in range(3)]
    return [
        f"{r[0]:<{widths[0]}}  {r[1]:<{widths[1]}}  {r[2]:<{widths[2]}}  {r[3]}".rstrip()
        for r in rows
    ]


def _floats(values: tuple[float, ...]) -> str:
    return "(" + ", ".join(repr(float(v)) for v in values) + ")"


def _names(values: tuple[str, ...]) -> str:
    if len(values) == 1:
        return f"({values[0]!r},)"
    return "(" + ", ".join(repr(v) for v in values) + ")"


def render_dynamics(system: SymbolicSystem, source: str) -> str:
    """The text of ``generated/NAME/dynamics.py``."""
    model = system.model
    template = _environment().get_template("dynamics.py.j2")
    return template.render(
        version=__version__,
        sympy_version=sympy.__version__,
        source=source,
        model=model,
        kind="planar" if model.planar else "spatial",
        free3d=any(j.is_free_3d for j in model.joints),
        layout=_table(_layout(model)),
        fingerprint=model_fingerprint(model),
        q_names=_names(model.q_names),
        v_names=_names(model.v_names),
        body_names=_names(tuple(b.name for b in model.bodies)),
        contact_names=_names(tuple(c.name for c in model.contacts)),
        gravity=_floats(model.gravity),
        total_mass=repr(float(model.total_mass)),
        body={f.name: function_body(f) for f in system.functions},
    )
