"""Check a path to follow (``path route = circle(...)``, or ``legdsl run --path``) into a
``PathSpec``: its shape, its arguments and their units."""

from __future__ import annotations

from legdsl.check.values import ValueChecker, did_you_mean
from legdsl.ir.paths import (
    DEFAULT_LOOKAHEAD,
    FARTHEST,
    SAME_POINT,
    SHAPES,
    PathSpec,
    far,
    same_point,
    square_corners,
)
from legdsl.lang import ast
from legdsl.lang.errors import Diagnostics

_PATH_ARGS = {
    "circle": ("center", "radius", "turn", "lookahead"),
    "square": ("corner", "side", "turn", "lookahead"),
    "polyline": ("lookahead",),
    "polygon": ("lookahead",),
}
# a path's points are on the ground, planar creature or not (not a planar creature's (x, z))
_GROUND = "x, y on the ground"
_PATH_EXAMPLES = {
    "circle": "circle(center = (0, 5) m, radius = 5 m, turn = left)",
    "square": "square(corner = (0, 0) m, side = 8 m, turn = left)",
}
_PATH_EXAMPLE = (
    "circle(center = (0, 5) m, radius = 5 m, turn = left), polyline((0, 0) m, (10, 0) m, ...), "
    "polygon(...) or square(corner = (0, 0) m, side = 8 m, turn = left)"
)


def check_path(name: str, value: ast.Value, diag: Diagnostics) -> PathSpec | None:
    """``circle(...)``, ``polyline(...)``, ``polygon(...)`` or ``square(...)``, in metres."""
    values = ValueChecker(diag)
    if not isinstance(value, ast.Call):
        diag.error(value.span, f"a path is one of {_PATH_EXAMPLE}")
        return None
    shape = value.func.name
    if shape not in SHAPES:
        diag.error(
            value.func.span,
            f"unknown path shape '{shape}'; a path is one of {_PATH_EXAMPLE}{did_you_mean(shape, SHAPES)}",
        )
        return None
    allowed = _PATH_ARGS[shape]
    ok = True
    given: dict[str, ast.Arg] = {}
    points: list[tuple[float, float]] = []
    for arg in value.args:
        if arg.keyword is None:
            if shape not in ("polyline", "polygon"):
                diag.error(
                    arg.span,
                    f"{shape}() takes {', '.join(k + ' = ...' for k in allowed)}, not a positional argument",
                )
                ok = False
                continue
            p = values.vector(arg.value, "length", 2, "a point of the path", _GROUND)
            if p is None or not _near(p, arg.value, diag):
                ok = False
            elif points and same_point((p[0], p[1]), points[-1]):
                diag.error(
                    arg.span,
                    f"point {len(points) + 1} of the {shape} is the point before it again; "
                    "each point must differ from the one before (remove the repeat)",
                )
                ok = False
            else:
                points.append((p[0], p[1]))
            continue
        key = arg.keyword.name
        if key not in allowed:
            diag.error(
                arg.keyword.span,
                f"{shape}() takes {', '.join(k + ' = ...' for k in allowed)}, not '{key}'"
                + did_you_mean(key, allowed),
            )
            ok = False
        elif key in given:
            diag.error(arg.keyword.span, f"'{key}' is given twice")
            ok = False
        else:
            given[key] = arg
    if not ok:
        return None

    def length(key: str) -> float | None:
        v = values.scalar(given[key].value, "length", f"'{key}'")
        if v is not None and v <= 0:
            diag.error(given[key].value.span, f"'{key}' must be positive, got {v:g} m")
            return None
        # the look-ahead too: the tracker divides it by a circle's radius (1e300 m made NaN)
        if v is not None and far(v):
            diag.error(
                given[key].value.span, f"'{key}' must be at most {FARTHEST:g} m, got {v:g} m"
            )
            return None
        # a radius under a point's size is a point (5e-324 m divided a look-ahead into NaN)
        if v is not None and key != "lookahead" and v <= SAME_POINT:
            diag.error(
                given[key].value.span,
                f"'{key}' must be more than {SAME_POINT:g} m (shorter is a point), got {v:g} m",
            )
            return None
        return v

    lookahead = DEFAULT_LOOKAHEAD
    if "lookahead" in given:
        look = length("lookahead")
        if look is None:
            return None
        lookahead = look
    if shape in ("polyline", "polygon"):
        least = 2 if shape == "polyline" else 3
        if len(points) < least:
            diag.error(
                value.span,
                f"a {shape} needs at least {least} points, got {len(points)}: write {shape}((0, 0) m, (10, 0) m{', (10, 10) m' if least == 3 else ''})",
            )
            return None
        if shape == "polygon" and same_point(points[0], points[-1]):
            diag.error(
                value.span,
                "a polygon closes itself: its last point repeats the first; remove the last",
            )
            return None
        return PathSpec(name, shape, tuple(points), closed=shape == "polygon", lookahead=lookahead)
    place, size = ("center", "radius") if shape == "circle" else ("corner", "side")
    for key in (place, size):
        if key not in given:
            diag.error(value.span, f"{shape}() needs '{key} = ...', as in {_PATH_EXAMPLES[shape]}")
            return None
    where = values.vector(given[place].value, "length", 2, f"the {place}", _GROUND)
    if where is not None and not _near(where, given[place].value, diag):
        return None
    extent = length(size)
    turn = 1
    if "turn" in given:
        word = given["turn"].value
        if not isinstance(word, ast.NameValue) or word.ident.name not in ("left", "right"):
            diag.error(word.span, "'turn' is left (counter-clockwise) or right (clockwise)")
            return None
        turn = 1 if word.ident.name == "left" else -1
    if where is None or extent is None:
        return None
    center = (where[0], where[1])
    if shape == "circle":
        return PathSpec(
            name, "circle", center=center, radius=extent, turn=turn, lookahead=lookahead
        )
    corners = square_corners(center, extent, turn)
    if any(same_point(a, b) for a, b in zip(corners, corners[1:], strict=False)):
        # far from the origin a short side rounds away: the corners were one point, no segment
        diag.error(
            given["side"].value.span,
            f"'side' = {extent:g} m is lost in the rounding of a corner at ({center[0]:g}, "
            f"{center[1]:g}) m: its corners are one point; give a longer side or a nearer corner",
        )
        return None
    if any(far(c) for corner in corners for c in corner):  # as a polygon's points are held
        diag.error(
            given["side"].value.span,
            f"'side' = {extent:g} m takes a corner of the square past {FARTHEST:g} m from the "
            "origin; give a shorter side or a corner nearer the origin",
        )
        return None
    return PathSpec(name, "square", corners, closed=True, lookahead=lookahead)


def _near(point: tuple[float, ...], value: ast.Value, diag: Diagnostics) -> bool:
    """Whether a point of a path is within ``FARTHEST`` of the origin (else an error at it)."""
    if far(point[0]) or far(point[1]):
        diag.error(
            value.span,
            f"a point of a path must be within {FARTHEST:g} m of the origin in x and y, "
            f"got ({point[0]:g}, {point[1]:g}) m; give it in metres near where the creature runs",
        )
        return False
    return True
