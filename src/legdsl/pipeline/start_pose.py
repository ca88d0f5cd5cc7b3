"""A contact that starts under the ground: a mistake in the initial pose, told at its line.

The ground spring would launch the body. Deeper than ``start_depth`` is refused (exit 2), or
than half a paw pad's thickness: the pad's force grows without bound as a foot sinks through
it, so a small creature's thin pad throws it up from less than 1 cm. The error is at the
root body's ``initial`` (its ``fixed at`` when welded), the line to change, when the run
starts from the file's pose (a batch copy's own start is told as a mistake of the call).
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

from legdsl.ir.model import Model, Pad
from legdsl.lang.errors import Diagnostic, LegError, Span, UsageError
from legdsl.lang.spellings import mask, offset_span
from legdsl.sim.sizes import start_depth


def check_fall_height(sim: Any) -> None:
    """A ``--fall-height`` above where the root starts (over the ground under it) would end
    the run as fallen before its first step: refused, as a negative one is. Told in the
    numbers of a ``--scale L`` run's creature."""
    limit = sim.options.fall_height
    if limit is None or isinstance(limit, str) or sim.model.welded_root is not None:  # off
        return
    root = sim.dyn.body_poses(list(sim.q))[0][0]
    above = root[2] - (sim.ground.height(root[0], root[1]) if sim.ground is not None else 0.0)
    # as the fall rule reads it (simulate.py); a root that starts at or under the ground has
    # no --fall-height to give instead (negative ones are refused): it falls at once, as said
    if 0 < above < limit:
        size = sim.size_scale
        raise UsageError(
            f"--fall-height {limit * size:.4g}m: the root starts {above * size:.4g} m above the "
            f"ground, so the run would end as fallen before its first step; give a "
            f"--fall-height below {above * size:.4g}m"
        )


def check_start(model: Model, sim: Any, source: str | Path, row: int | None = None) -> None:
    """A contact deeper under the ground than a creature of its size may start is refused: at
    the line of the file that places the root, or, for copy ``row`` of a batch (its own start,
    ``run_copies``' ``q0=``), as that row's mistake: the file gave no such start."""
    if model.ground is None:
        return
    normal = model.ground.normal
    # a --scale L run (size_scale L) allows the depth of a creature of the scaled size, in the
    # model's numbers, as the scaled file's run does (it allowed the unscaled creature's)
    scale = sim.size_scale
    allowed = start_depth(scale * sim.standing_height()) / scale
    if isinstance(normal, Pad):
        allowed = min(allowed, normal.thickness / 2)
    under = [(name, -h) for name, h in sim.contact_heights() if h < -allowed]
    if not under:
        return
    name, depth = max(under, key=lambda c: c[1])
    welded = model.welded_root
    fix = (
        _row_fix(model, sim, row, depth)
        if row is not None
        else (
            f"raise the root's initial z by at least {depth:.3g} m in the .leg file, or start "
            "with --drop H (the lowest foot H metres above the ground)"
            if welded is None
            else f"raise the point after 'fixed at' of its root body '{welded}' by at least "
            f"{depth:.3g} m in the .leg file"
        )
    )
    scaled = (f"; at --scale {scale:g} it starts {depth * scale:.3g} m under, where a creature "
              f"of that size may start {allowed * scale:.3g} m under: the file's numbers are the "
              "unscaled creature's, --drop's the scaled one's" if scale != 1.0 else "")  # fmt: skip
    message = (
        f"contact '{name}' of creature '{model.name}' starts {depth:.3g} m under the ground "
        f"(the ground would throw the body up{scaled}); {fix}"
    )
    body = next(b for b in model.bodies if b.parent is None)
    try:
        text = Path(body.span.file).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError):
        text = None
    from_file = [float(x) for x in sim.q] == list(model.q0)  # not a copy's or a scene's start
    if row is not None:
        raise UsageError(message)  # the caller names the argument and the copy
    if text is None or body.span.line <= 0 or not from_file:
        raise UsageError(f"{source}: {message}")
    span = _placed_at(text, body.span, "fixed" if welded else "initial")
    raise LegError([Diagnostic(span, message + body.span.within)], {span.file: text})


def _row_fix(model: Model, sim: Any, row: int, depth: float) -> str:
    """How to mend row ``row`` of ``q0`` (a batch copy's start): raise its root's z, the
    column named, or, for a root that has none (welded, or a planar one without a vertical
    slide), change the row's joint angles."""
    column = root_z(model)
    if column is None:
        return (f"change its joint angles in q0[{row}] so that the contact is above the "
                "ground")  # fmt: skip
    z = float(sim.q[column])
    return f"raise its root's z, q0[{row}, {column}] (now {z:.4g} m), by at least {depth:.3g} m"


def root_z(model: Model) -> int | None:
    """The column of q of the root's height (world z), None when it has none of its own."""
    root = next(j for j in model.joints if j.parent is None)
    if root.is_free_3d:
        return root.q_start + 2
    for dof in root.dofs:
        if dof.motion == "slide" and tuple(dof.axis) == (0.0, 0.0, 1.0):
            return dof.q_index
    return None


def _placed_at(text: str, body: Span, word: str) -> Span:
    """The root body's ``word`` (its 'initial' or 'fixed'), or else its declaration."""
    lines = text.split("\n")
    start = sum(len(line) + 1 for line in lines[: body.line - 1]) + body.col - 1
    masked = mask(text)
    depth, end = 0, len(masked)
    for i in range(start, len(masked)):  # the body's block: to its closing brace
        if masked[i] == "{":
            depth += 1
        elif masked[i] == "}":
            depth -= 1
            if depth == 0:
                end = i
                break
    found = re.compile(rf"\b{word}\b").search(masked, start, end)
    return offset_span(body.file, text, found.start(), len(word)) if found else body
