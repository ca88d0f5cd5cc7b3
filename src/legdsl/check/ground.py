"""The ground block: the contact springs of the ground (normal, tangent, torsion), the
friction coefficient and the terrain (steps, boxes, a slope)."""

from __future__ import annotations

import math

from legdsl.check.scope import CreaturePart
from legdsl.check.values import did_you_mean
from legdsl.ir.model import Ground, Pad, SpringDamper, Terrain
from legdsl.lang import ast
from legdsl.lang.errors import Span

GROUND_PROPS = ("normal", "tangent", "torsion", "friction", "terrain")


class GroundChecker(CreaturePart):
    """Checks a creature's ground block."""

    def ground(self, block: ast.BlockDecl) -> Ground | None:
        seen: dict[str, ast.Prop] = {}
        terrain: list[Terrain] = []
        normal: SpringDamper | Pad | None = None
        tangent = torsion = None
        friction: float | None = None
        for p in block.props:
            key = p.key.name
            if key not in GROUND_PROPS:
                self.err(
                    p.key.span,
                    f"unknown ground property '{key}'"
                    + (
                        did_you_mean(key, GROUND_PROPS)
                        or f"; the ground takes {', '.join(GROUND_PROPS)}"
                    ),
                )
                continue
            if key in seen and key != "terrain":
                self.err(p.key.span, f"'{key}' is given twice in the ground block")
                continue
            seen[key] = p
            value = p.value.value if isinstance(p.value, ast.One) else None
            if key == "friction":
                if isinstance(value, ast.NameValue) and value.ident.name == "none":
                    friction = None
                elif value is not None:
                    friction = self.scalar(value, "dimensionless", "the friction coefficient")
                    if friction is not None and friction <= 0:
                        self.err(
                            value.span,
                            "a friction coefficient must be positive; write 'friction none' for no slip",
                        )
                else:
                    self.err(
                        p.value.span,
                        "write 'friction none' (no slip) or a coefficient such as 'friction 0.8'",
                    )
                continue
            if not isinstance(value, ast.Call):
                self.err(p.value.span, _ground_help(key))
                continue
            if key == "terrain":
                t = self.terrain(value)
                if t is not None:
                    terrain.append(t)
                continue
            rotary = key == "torsion"
            if key == "torsion" and self.planar:
                self.err(
                    p.key.span,
                    "a planar creature has no torsional ground spring (it turns about the normal only in "
                    "3D); leave 'torsion' out",
                )
                continue
            if value.func.name == "pad" and key == "normal":
                args = self.kwargs(
                    value,
                    {"k": "force", "thickness": "length", "b": "linear damping"},
                    ("k", "thickness"),
                )
                if args is not None:
                    normal = Pad(args["k"], args["thickness"], args.get("b", 0.0))
                continue
            if value.func.name != "spring":
                self.err(value.func.span, _ground_help(key))
                continue
            args = self.kwargs(
                value,
                {
                    "k": "angular stiffness" if rotary else "linear stiffness",
                    "b": "angular damping" if rotary else "linear damping",
                },
                ("k",),
            )
            if args is None:
                continue
            sd = SpringDamper(args["k"], args.get("b", 0.0))
            if key == "normal":
                normal = sd
            elif key == "tangent":
                tangent = sd
            else:
                torsion = sd
        if any(t.kind == "slope" for t in terrain) and len(terrain) > 1:
            slope = next(t for t in terrain if t.kind == "slope")
            other = next(t for t in terrain if t is not slope)  # the line to remove
            self.err(
                other.span,
                f"a slope is the whole ground: it cannot be combined with other terrain "
                f"(the slope is on line {slope.span.line}); keep the slope alone, or remove it "
                "for steps and boxes on level ground",
            )
        for key in ("normal", "tangent"):
            if key not in seen:
                what, forms = _GROUND_HELP[key]
                self.err(block.name.span, f"the ground needs {what}: {forms}")
        if normal is None or tangent is None:
            return None
        return Ground(normal, tangent, torsion, friction, tuple(terrain), block.span)

    def kwargs(
        self, call: ast.Call, kinds: dict[str, str], required: tuple[str, ...]
    ) -> dict[str, float] | None:
        out: dict[str, float] = {}
        given: set[str] = set()
        ok = True
        for arg in call.args:
            if arg.keyword is None or arg.keyword.name not in kinds:
                word = arg.keyword.name if arg.keyword else "a positional argument"
                self.err(
                    arg.span,
                    f"{call.func.name}() takes {', '.join(k + ' = ...' for k in kinds)}, not {word}",
                )
                ok = False
                continue
            if arg.keyword.name in given:
                self.err(arg.keyword.span, f"'{arg.keyword.name}' is given twice")
                ok = False
                continue
            given.add(arg.keyword.name)
            v = self.scalar(arg.value, kinds[arg.keyword.name], f"'{arg.keyword.name}'")
            if v is None:
                ok = False
                continue
            sized = arg.keyword.name == "thickness"  # a pad's size; k and b may be 0
            if v < 0 or (v == 0 and sized):
                rule = "must be positive" if sized else "must not be negative"
                self.err(arg.value.span, f"'{arg.keyword.name}' {rule}")
                ok = False
                continue
            out[arg.keyword.name] = v
        for key in required:
            if key not in out and ok:
                self.err(call.span, f"{call.func.name}() needs '{key}'")
                ok = False
        return out if ok else None

    def terrain(self, call: ast.Call) -> Terrain | None:
        kinds = {
            "step": ({"x": "length", "height": "length"}, ("x", "height")),
            "box": (
                {
                    "x0": "length",
                    "x1": "length",
                    "y0": "length",
                    "y1": "length",
                    "height": "length",
                },
                ("x0", "x1", "height") if self.planar else ("x0", "x1", "y0", "y1", "height"),
            ),
            # The whole ground tilted about y, rising towards +x.
            "slope": ({"angle": "angle"}, ("angle",)),
        }
        if call.func.name not in kinds:
            self.err(
                call.func.span,
                f"unknown terrain '{call.func.name}'; use step(x = ..., height = ...), box(x0 = ..., x1 = ..., height = ...) or slope(angle = ...){did_you_mean(call.func.name, kinds)}",
            )
            return None
        arg_kinds, required = kinds[call.func.name]
        if self.planar and call.func.name == "box":
            for arg in call.args:  # the creature is at y = 0: a box off it would be no box
                if arg.keyword is not None and arg.keyword.name in ("y0", "y1"):
                    self.err(
                        arg.keyword.span,
                        f"a planar creature moves in the x-z plane: its box takes x0, x1 and "
                        f"height, not '{arg.keyword.name}' (remove it)",
                    )
                    return None
        args = self.kwargs_signed(call, arg_kinds, required)
        if args is None:
            return None
        if call.func.name == "slope" and not abs(args["angle"]) < math.radians(80):
            self.err(
                _arg_span(call, "angle"),
                "a slope's angle must be strictly between -80 deg and 80 deg (79.9 deg is "
                "allowed, 80 deg is not)",
            )
            return None
        if call.func.name == "box":
            for lo, hi in (("x0", "x1"), ("y0", "y1")):
                if lo in args and hi in args and args[hi] <= args[lo]:
                    self.err(
                        _arg_span(call, hi),
                        f"a box needs {lo} < {hi}: {hi} = {args[hi]:g} m is not beyond "
                        f"{lo} = {args[lo]:g} m; swap them, or give the box some extent",
                    )
                    return None
            args.setdefault("y0", -1e3)
            args.setdefault("y1", 1e3)
        return Terrain(call.func.name, tuple(sorted(args.items())), call.span)

    def kwargs_signed(
        self, call: ast.Call, kinds: dict[str, str], required: tuple[str, ...]
    ) -> dict[str, float] | None:
        out: dict[str, float] = {}
        for arg in call.args:
            if arg.keyword is None or arg.keyword.name not in kinds:
                self.err(
                    arg.span, f"{call.func.name}() takes {', '.join(k + ' = ...' for k in kinds)}"
                )
                return None
            if arg.keyword.name in out:
                self.err(arg.keyword.span, f"'{arg.keyword.name}' is given twice")
                return None
            v = self.scalar(arg.value, kinds[arg.keyword.name], f"'{arg.keyword.name}'")
            if v is None:
                return None
            out[arg.keyword.name] = v
        missing = [k for k in required if k not in out]
        if missing:
            self.err(call.span, f"{call.func.name}() needs {', '.join(missing)}")
            return None
        if out.get("height", 1.0) <= 0:
            self.err(_arg_span(call, "height"), _NOT_POSITIVE_HEIGHT[call.func.name])
            return None
        return out


def _arg_span(call: ast.Call, name: str) -> Span:
    """Where the argument ``name`` of ``call`` is written (the call's span without it)."""
    return next(
        (a.value.span for a in call.args if a.keyword and a.keyword.name == name), call.span
    )


# The floor is at 0 and a feature only raises it: how to write the ground a user had in mind.
_NOT_POSITIVE_HEIGHT = {
    "step": "a step's height must be positive (it raises the floor from x on); for a step "
    "down at x = X, raise the floor before it instead: box(x0 = ..., x1 = X, height = H), "
    "and start the creature on it",
    "box": "a box's height must be positive (a feature only raises the floor, which is at 0); "
    "for a pit, raise the floor on both sides with two boxes",
}


# What each ground property is, and how it is written.
_GROUND_HELP = {
    "normal": (
        "the vertical spring",
        "'normal spring(k = 1.2e4 N/m, b = 150 N*s/m)' or the paw pad of eq. (6), 'normal pad(k = 250 N, thickness = 1 cm, b = 100 N*s/m)'",
    ),
    "tangent": ("the tangential springs", "'tangent spring(k = 8e3 N/m, b = 120 N*s/m)'"),
    "torsion": (
        "the torsional spring about the normal",
        "'torsion spring(k = 5 N*m/rad, b = 0.5 N*m*s/rad)'",
    ),
    "terrain": (
        "a terrain feature",
        "'terrain step(x = 2 m, height = 0.1 m)', 'terrain box(x0 = 3 m, x1 = 3.3 m, height = 0.2 m)' or 'terrain slope(angle = 10 deg)'",
    ),
}


def _ground_help(key: str) -> str:
    what, forms = _GROUND_HELP[key]
    return f"write {what} as {forms}"
