"""A body's own properties: its mass, mass centre, link length and direction, inertia,
shape and colour (the properties of the joint above it are read in ``joints``)."""

from __future__ import annotations

import math

import numpy as np

from legdsl.check.scope import CreaturePart
from legdsl.check.values import did_you_mean, takes_one_value
from legdsl.ir.model import Body, Mat3, Shape, Vec3
from legdsl.lang import ast
from legdsl.lang.errors import Span
from legdsl.lang.value_slips import hex_color_comment

BODY_PROPS = (
    "mass", "inertia", "com", "length", "direction", "shape", "color",
    "axis", "axes", "initial", "velocity", "limits", "stop",
)  # fmt: skip
SHAPES = {
    "box": ("x", "y", "z"),
    "frustum": ("r0", "r1"),
    "capsule": ("r",),
    "cylinder": ("r",),
    "sphere": ("r",),
}


class BodyChecker(CreaturePart):
    """Checks a body's properties into a ``Body``."""

    def body_props(self, decl: ast.BodyDecl) -> dict[str, ast.Prop]:
        props: dict[str, ast.Prop] = {}
        misread_line = None  # the line whose first word a 'color #b07040' took as its value
        for p in decl.props:
            key = p.key.name
            if p.key.span.line == misread_line:
                continue  # the rest of that line, read as a property: told at the colour
            misread_line = None
            commented = self._commented_color(p)
            if commented is not None:
                self.err(*commented)
                misread_line = p.value.span.line
            elif key not in BODY_PROPS:
                self.err(
                    p.key.span,
                    f"unknown body property '{key}'"
                    + (did_you_mean(key, BODY_PROPS) or "; a body takes " + ", ".join(BODY_PROPS)),
                )
            elif key in props:
                self.err(p.key.span, f"'{key}' is given twice for body '{decl.name.name}'")
            else:
                props[key] = p
        return props

    def _commented_color(self, p: ast.Prop) -> tuple[Span, str] | None:
        """'color #b07040' without quotes: the '#' began a comment, and the key took the next
        line's first word. (where the '#' is, the sentence)"""
        key = p.key.span
        if (
            p.value.span.line == key.line
            or isinstance(p.value, ast.One)
            and isinstance(p.value.value, ast.String)
        ):
            return None
        source = self.diag.sources.get(key.file, "")
        line = source.split("\n")[key.line - 1] if key.line <= source.count("\n") + 1 else ""
        found = hex_color_comment(line[key.col - 1 :])
        if found is None:
            return None
        col = key.col + found[0]
        return Span(key.file, key.line, col, key.line, col + found[1]), found[2]

    def body(
        self, decl: ast.BodyDecl, props: dict[str, ast.Prop], parents: dict[str, Body]
    ) -> Body:
        name = decl.name.name
        self.declare(decl.name, "body")
        mass = 1.0
        if "mass" not in props:
            self.err(decl.name.span, f"body '{name}' needs a mass, e.g. 'mass 1.5 kg'")
        else:
            m = self.one_scalar(props["mass"], "mass", "the mass")
            if m is not None and m <= 0:
                self.err(
                    props["mass"].value.span,
                    f"the mass of body '{name}' must be positive: give it one above 0, as in "
                    "'mass 0.5 kg' (a part too light to matter still has some, as 'mass 10 g')",
                )
            elif m is not None:
                mass = m

        length = None
        if "length" in props:
            length = self.one_scalar(props["length"], "length", "the link length")
            if length is not None and length <= 0:
                self.err(
                    props["length"].value.span,
                    "a link length must be positive: give it one above 0, as in 'length 0.3 m', "
                    "or leave 'length' out of a body without a tip",
                )
                length = None
            if length is None:  # written, with a mistake told here: not missing elsewhere
                self.diag.unknown.add(f"{name}.length")

        direction: Vec3 = (0.0, 0.0, -1.0)
        if "direction" in props:
            p = props["direction"]
            if isinstance(p.value, ast.One):
                direction = self.unit_vector(p.value.value, "the link direction") or direction

        com: Vec3 = (0.0, 0.0, 0.0)
        if "com" in props:
            p = props["com"]
            if isinstance(p.value, ast.One) and isinstance(p.value.value, ast.Vector):
                com = self.point(p.value.value, "the mass centre") or com
            else:
                along = self.one_scalar(p, "length", "the mass centre (distance along the link)")
                if along is not None:
                    com = (along * direction[0], along * direction[1], along * direction[2])

        inertia = self.inertia(decl, props.get("inertia"), mass)
        shape = self.shape(props.get("shape"), length, mass)
        color = None
        if "color" in props:
            p = props["color"]
            if isinstance(p.value, ast.One) and isinstance(p.value.value, ast.String):
                color = p.value.value.text
                if not (len(color) == 7 and color[0] == "#" and _is_hex(color[1:])):
                    self.err(p.value.span, 'a colour is written as "#rrggbb", e.g. "#c08040"')
                    color = None
            else:
                self.err(p.value.span, 'a colour is a string such as "#c08040"')
        parent = decl.attach.parent.name if isinstance(decl.attach, ast.AttachJoint) else None
        joint_name = decl.attach.joint.name if isinstance(decl.attach, ast.AttachJoint) else "root"
        return Body(
            name, parent, joint_name, mass, com, inertia, length, direction, shape, color, decl.span
        )

    def inertia(self, decl: ast.BodyDecl, prop: ast.Prop | None, mass: float) -> Mat3:
        name = decl.name.name
        fallback: Mat3 = ((1e-3, 0.0, 0.0), (0.0, 1e-3, 0.0), (0.0, 0.0, 1e-3))
        if prop is None:
            self.err(
                decl.name.span,
                f"body '{name}' needs an inertia about its mass centre, e.g. "
                + ("'inertia 0.01 kg*m^2'" if self.planar else "'inertia (0.1, 0.1, 0.05) kg*m^2'"),
            )
            return fallback
        if not isinstance(prop.value, ast.One):
            self.err(prop.value.span, takes_one_value(prop))
            return fallback
        value = prop.value.value
        if self.planar:
            i = self.scalar(value, "moment of inertia", "the inertia of a planar body (about y)")
            if i is None:
                return fallback
            if i <= 0:
                self.err(
                    value.span,
                    f"the inertia of body '{name}' must be positive: give its moment about y "
                    "above 0, as in 'inertia 0.01 kg*m^2'",
                )
                return fallback
            # Only the moment about y acts in a planar model; the others are set equal so
            # that exports (MJCF, URDF) carry a valid tensor.
            return ((i, 0.0, 0.0), (0.0, i, 0.0), (0.0, 0.0, i))
        if isinstance(value, ast.Vector) and value.items and isinstance(value.items[0], ast.Vector):
            rows = []
            for row in value.items:
                r = (
                    self.vector(row, "moment of inertia", 3, "a row of the inertia matrix")
                    if not value.unit
                    else None
                )
                if value.unit:
                    self.err(
                        value.unit_span or value.span,
                        "put the unit on each number of a 3x3 inertia",
                    )
                    return fallback
                if r is None:
                    return fallback
                rows.append(r)
            if len(rows) != 3:
                self.err(
                    value.span, "a full inertia is a 3x3 matrix ((Ixx, Ixy, Ixz), (...), (...))"
                )
                return fallback
            mat = np.array(rows)
            if not np.allclose(mat / _scale(mat), mat.T / _scale(mat), rtol=1e-9, atol=1e-12):
                self.err(value.span, _not_symmetric(name, mat))
                return fallback
        else:
            diag = self.vector(value, "moment of inertia", 3, "the inertia (Ixx, Iyy, Izz)")
            if diag is None:
                return fallback
            mat = np.diag(diag)
        with np.errstate(over="ignore"):
            eig = np.linalg.eigvalsh(mat / _scale(mat)) * _scale(mat)
        if not np.isfinite(eig).all():
            self.err(value.span, f"the inertia of body '{name}' is too large")
            return fallback
        if eig.min() <= 0:
            self.err(
                value.span,
                f"the inertia of body '{name}' is not positive definite (principal moments "
                f"{', '.join(f'{e:.3g}' for e in eig)}); every principal moment must be > 0",
            )
            return fallback
        a, b, c = sorted(eig)
        if a / c + b / c < 1 - 1e-9:
            self.err(
                value.span,
                f"the inertia of body '{name}' breaks the triangle inequality: principal moments "
                f"{_apart(a, b, c)}, which no rigid body has; make the largest at most the "
                "sum of the other two",
            )
            return fallback
        return (
            (float(mat[0, 0]), float(mat[0, 1]), float(mat[0, 2])),
            (float(mat[1, 0]), float(mat[1, 1]), float(mat[1, 2])),
            (float(mat[2, 0]), float(mat[2, 1]), float(mat[2, 2])),
        )

    def shape(self, prop: ast.Prop | None, length: float | None, mass: float) -> Shape:
        if prop is None:
            if length:
                return Shape("capsule", (("r", 0.1 * length),))
            # A sphere of water of the body's mass.
            return Shape("sphere", (("r", (3 * mass / (4 * math.pi * 1000.0)) ** (1 / 3)),))
        default = Shape("sphere", (("r", 0.05),))
        value = prop.value.value if isinstance(prop.value, ast.One) else None
        if not isinstance(value, ast.Call):
            self.err(
                prop.value.span,
                "a shape is written as a call: " + ", ".join(f"{k}(...)" for k in SHAPES),
            )
            return default
        kind = value.func.name
        if kind not in SHAPES:
            self.err(
                value.func.span,
                f"unknown shape '{kind}'; use one of {', '.join(SHAPES)}{did_you_mean(kind, SHAPES)}",
            )
            return default
        keys = SHAPES[kind]
        if kind == "box" and self.planar:
            keys = ("x", "z")
        params: dict[str, float] = {}
        center: Vec3 = (0.0, 0.0, 0.0)
        positional = [a for a in value.args if a.keyword is None]
        if len(positional) > len(keys):
            self.err(value.span, f"{kind}() takes {len(keys)} sizes ({', '.join(keys)})")
            return default
        given: set[str] = set()  # written, even if wrong (then reported on its own)
        for key, arg in zip(keys, positional, strict=False):
            given.add(key)
            v = self.scalar(arg.value, "length", f"{kind} size '{key}'")
            if v is not None:
                params[key] = v
        for arg in value.args:
            if arg.keyword is None:
                continue
            name = arg.keyword.name
            if name not in (*keys, "center"):
                self.err(
                    arg.keyword.span,
                    f"{kind}() has no argument '{name}'; it takes {', '.join(keys)} and center",
                )
                continue
            if name in given:
                self.err(arg.keyword.span, f"'{name}' is given twice")
                continue
            given.add(name)
            if name == "center":
                center = self.point(arg.value, "the shape centre") or center
            else:
                v = self.scalar(arg.value, "length", f"{kind} size '{name}'")
                if v is not None:
                    params[name] = v
        for key, v in params.items():
            if v <= 0:
                self.err(value.span, f"{kind} size '{key}' must be positive")
        missing = [k for k in keys if k not in given]
        if missing:
            self.err(value.span, f"{kind}() needs {', '.join(missing)}")
        if missing or any(k not in params or params[k] <= 0 for k in keys):
            return default
        if kind == "box" and self.planar:
            params["y"] = min(params["x"], params["z"])
        return Shape(kind, tuple((k, params[k]) for k in SHAPES[kind]), center)


def _scale(mat: np.ndarray) -> float:
    """The largest magnitude in a matrix (1 if all zero): divide by it to compute safely."""
    return float(np.abs(mat).max()) or 1.0


def _is_hex(text: str) -> bool:
    return all(c in "0123456789abcdefABCDEF" for c in text)


def _apart(a: float, b: float, c: float) -> str:
    """'a + b < c' with as many digits as show it (1 + 1 < 2.0000001, not 1 + 1 < 2)."""
    for digits in range(3, 17):
        x, y, z = (float(f"{v:.{digits}g}") for v in (a, b, c))
        if x + y < z:
            return f"{a:.{digits}g} + {b:.{digits}g} < {c:.{digits}g}"
    return f"{a!r} + {b!r} < {c!r}"


def _not_symmetric(name: str, mat: np.ndarray) -> str:
    """The mistake of an inertia matrix that is not symmetric, naming the first pair of
    entries that differ, and the way out."""
    scale = _scale(mat)
    pairs = [(i, j) for i in range(3) for j in range(i + 1, 3)]
    row, col = next(
        (p for p in pairs
         if not np.isclose(mat[p] / scale, mat[p[::-1]] / scale, rtol=1e-9, atol=1e-12)),
        (0, 1),
    )  # fmt: skip
    axes = "xyz"
    return (
        f"the inertia matrix of body '{name}' must be symmetric, but row {row + 1}, column "
        f"{col + 1} is {mat[row, col]:.4g} and row {col + 1}, column {row + 1} is "
        f"{mat[col, row]:.4g}: both are the product of inertia I{axes[row]}{axes[col]}; write "
        "the same number in both places"
    )
