"""What a scene's gait table (``gait by INPUT { CONTROLLER from LOW to HIGH; ... }``) can
never do, and the advice of its errors (``legdsl.check.scene`` checks the table).

The rule the run follows (``legdsl.ir.scene.choose_gaits``): the first command goes to the
first band that holds it (or the scene's ``controller`` line), and at each change the current
controller is kept while a band of its holds the command, else the first band that holds it
takes over. So a controller is ever chosen only for a command that no earlier band of another
controller holds: one whose bands all lie within the bands before them never runs, whatever
the commands, and nothing in the run would say so.
"""

from __future__ import annotations

from dataclasses import replace

from legdsl.ir.scene import GaitBand
from legdsl.lang import ast
from legdsl.lang.errors import Diagnostics

_EPS = 1e-12  # as GaitBand.holds


def written(value: ast.Value | None) -> str:
    """A band's end as the file wrote it ('2 m/s', '-1 m/s')."""
    sign = ""
    while isinstance(value, ast.Neg):
        sign, value = "" if sign else "-", value.value
    return sign + value.text if isinstance(value, ast.Number) else "?"


def reversed_band(band: ast.GaitBand, by: str) -> str:
    """The error of a band written from its higher end to its lower one."""
    return (
        f"a band runs from a lower {by} to a higher one: write "
        f"'{band.controller.name} from {written(band.high)} to {written(band.low)}'"
    )


def _covered(band: GaitBand, before: list[GaitBand]) -> bool:
    """Whether every command ``band`` holds is held by one of ``before``."""
    low = -float("inf") if band.low is None else band.low
    high = float("inf") if band.high is None else band.high
    spans = sorted(
        (-float("inf") if b.low is None else b.low, float("inf") if b.high is None else b.high)
        for b in before
    )
    reach = low  # every command from ``low`` up to ``reach`` is held
    for a, b in spans:
        if a > reach + _EPS:
            break
        reach = max(reach, b)
    return reach >= high - _EPS


def _cut(shadow: GaitBand, band: GaitBand) -> GaitBand | None:
    """``shadow`` ended where ``band`` begins (or begun where it ends): the band that leaves
    ``band`` its commands; None where neither end would."""
    if band.low is not None and (shadow.low is None or shadow.low < band.low):
        return replace(shadow, high=band.low)
    if band.high is not None and (shadow.high is None or shadow.high > band.high):
        return replace(shadow, low=band.high)
    return None


def tell_never_chosen(
    bands: tuple[GaitBand, ...], start: str | None, by: str, unit: str, diag: Diagnostics
) -> bool:
    """An error at the first band of each controller of the table that no command can ever
    choose (the scene's ``controller`` line starts one, so it is chosen); True if none."""
    fine = True
    for name in dict.fromkeys(b.controller for b in bands):
        if name == start:
            continue
        mine = [i for i, b in enumerate(bands) if b.controller == name]
        others = [[b for b in bands[:i] if b.controller != name] for i in mine]
        if not all(_covered(bands[i], o) for i, o in zip(mine, others, strict=True)):
            continue
        band = bands[mine[0]]
        shadows = [b for b in others[0] if _overlap(b, band)]
        cuts = [c for s in shadows for c in [_cut(s, band)] if c is not None]
        which = "; ".join(f"{s.text(unit)}, line {s.span.line}" for s in shadows)
        ends = " and ".join(f"'{c.text(unit)}'" for c in cuts)
        fix = (
            f"give the band{'s' if len(cuts) > 1 else ''} before it an end at {name}'s "
            f"({ends}; an end inside {name}'s band overlaps it, a hysteresis)"
            if cuts
            else "narrow the bands before it"
        )
        diag.error(
            band.span,
            f"no command of {by} ever chooses {name}: the bands before it ({which}) hold every "
            f"{by} its band{'s' if len(mine) > 1 else ''} hold{'' if len(mine) > 1 else 's'}, "
            f"and a command goes to the current band while it holds it, else to the first band "
            f"that holds it; {fix}",
        )
        fine = False
    return fine


def _overlap(a: GaitBand, b: GaitBand) -> bool:
    return (a.low is None or b.high is None or a.low <= b.high + _EPS) and (
        a.high is None or b.low is None or b.low <= a.high + _EPS
    )


def widen_advice(bands: tuple[GaitBand, ...], value: float, unit: str) -> str:
    """How to have a table hold a command none of its bands holds: the nearest band below
    it or above it reaching it, or a band of its own."""
    below = [b for b in bands if b.high is not None and b.high < value]
    above = [b for b in bands if b.low is not None and b.low > value]
    ways = []
    if below:
        near = max(below, key=lambda b: b.high or 0.0)
        ways.append(f"'{replace(near, high=value).text(unit)}'")
    if above:
        near = min(above, key=lambda b: b.low or 0.0)
        ways.append(f"'{replace(near, low=value).text(unit)}'")
    widen = f"widen a band to hold it ({' or '.join(ways)}), " if ways else ""
    return f"{widen}add a band that holds it, or give a command within the bands"
