"""The report ``legdsl tune`` prints: each tuned parameter's start and tuned value, each with
its unit, in the unit the file writes it in (a tilt the tuned file writes in deg was reported
in rad, and the start column had no unit), the objective, and the runs' speed, energy and
pitch at each speed, start and tuned."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

NO_STRIDE = "no whole stride"  # a run that lasted without one in its window


def report(
    result: dict[str, Any],
    units: dict[str, str],
    bounds: Sequence[Any] = (),
    factors: dict[str, float] | None = None,
) -> str:
    """Each parameter's start and tuned value with its unit (``units``, the file's: SI values
    divided by ``factors``), the objective, speeds, energy and pitch."""
    lines = ["parameter        start              tuned"]
    # the file's own values kept, no candidate beating them: no bound was met (a start within
    # 1% of the width of 20 to 1e7 said "at its lower bound: widen it")
    kept = result["best"]["values"] == result["start"]["values"]
    edges = {} if kept else {b.name: b for b in bounds}
    for name, value in result["best"]["values"].items():
        unit, factor = units.get(name, ""), (factors or {}).get(name, 1.0)
        start = f"{result['start']['values'][name] / factor:.4g} {unit}".rstrip()
        line = f"{name:<12} {start:>15}    {f'{value / factor:.4g} {unit}'.rstrip():>15}"
        lines.append(line + _at_bound(value, edges.get(name)))
    if kept and result.get("history"):
        lines.append("  (the file's own values are kept: no candidate beat them)")
    lines.append(
        f"objective    {result['start']['objective']:>15.4g}    {result['best']['objective']:>15.4g}"
    )
    lines.append("running speed (m/s)   start                tuned")
    for before, after in zip(result["start"]["runs"], result["best"]["runs"], strict=True):
        lines.append(
            f"  at {before['speed']:<6.4g}    {tune_speed(before):<20} {tune_speed(after)}"
        )
    if NO_STRIDE in "\n".join(lines[-len(result["start"]["runs"]) :]):  # why an objective of 2
        lines.append(f"  ({NO_STRIDE}: none from --from to --time, so no speed measured; "
                     "scored 2 at that speed, as a run falling at its very end)")  # fmt: skip
    lines.append("energy per metre (J/m), cost of transport (-)   start          tuned")
    for before, after in zip(result["start"]["runs"], result["best"]["runs"], strict=True):
        lines.append(f"  at {before['speed']:<6.4g}    {_energy(before):<20} {_energy(after)}")
    lines.append("pitch magnitude (deg)   start                tuned")
    for before, after in zip(result["start"]["runs"], result["best"]["runs"], strict=True):
        lines.append(
            f"  at {before['speed']:<6.4g}    {tune_pitch(before):<20} {tune_pitch(after)}"
        )
    return "\n".join(lines)


def _at_bound(value: float, bound: Any) -> str:
    """A value the search left within 1% of a bound may be better past it: say so."""
    if bound is None or bound.high <= bound.low:
        return ""
    near = 0.01 * (bound.high - bound.low)
    side = "upper" if value >= bound.high - near else "lower" if value <= bound.low + near else ""
    return f"  (at its {side} bound: widen it to search past it)" if side else ""


def _energy(row: dict[str, Any]) -> str:
    """A run's positive actuator work per metre and its cost of transport; n/a, as its speed
    is, for a run that did not last or lasted without a whole stride in its window (they were
    printed beside "no whole stride" and "n/a (fell ...)")."""
    per_metre = float(row.get("energy_per_metre", math.nan))
    cot = float(row.get("cost_of_transport", math.nan))
    measured = row["outcome"] == "ok" and math.isfinite(float(row.get("running_speed", math.nan)))
    return f"{per_metre:.4g}, {cot:.3g}" if measured and math.isfinite(per_metre) else "n/a"


def tune_speed(row: dict[str, Any]) -> str:
    """A run's measured speed and, if it did not last, how it ended; one that lasted without a
    whole stride in its window says so (it was "n/a", beside an objective of a fall)."""
    speed = float(row.get("running_speed", math.nan))
    spread = float(row.get("running_speed_std", math.nan))
    if not math.isfinite(speed) and row["outcome"] == "ok":
        return NO_STRIDE
    text = f"{speed:.4g}" if math.isfinite(speed) else "n/a"
    if math.isfinite(speed) and math.isfinite(spread):  # a mean on the command may swing about it
        text += f" ± {spread:.2g}"
    return text if row["outcome"] == "ok" else f"{text} ({row['outcome']})"


def tune_pitch(row: dict[str, Any]) -> str:
    """A run's trunk pitch magnitude: the mean of its strides' peak-to-peak pitch (degrees)."""
    pitch = float(row.get("pitch_magnitude", math.nan))
    return f"{pitch:.3g}" if math.isfinite(pitch) else "n/a"
