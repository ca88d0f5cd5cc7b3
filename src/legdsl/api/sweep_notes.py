"""What ``legdsl sweep`` says of its rows once they are all in: a heat map its values cannot
be drawn on, and swept values that changed nothing."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

from legdsl.analysis.sweep_plot import as_number

# beyond this, a plot axis's ticks overflow (matplotlib: 'arange: cannot compute length' for
# 1e308 to 1.7e308, an internal error after the rows were whole)
DRAWABLE = 1e300
# the columns a run's outcome is read from, beside the swept values and the run's number
OUTCOME = ("outcome", "simulated", "strides")


def beyond_a_plot(rows: Sequence[dict[str, Any]], names: Sequence[str], metric: str) -> str | None:
    """Why the heat map of ``metric`` over ``names`` cannot be drawn, or None: a swept value or
    a measured one too large for a plot's axis."""
    for name in [*names, metric]:
        values = [as_number(r.get(name)) for r in rows]
        huge = [v for v in values if math.isfinite(v) and abs(v) > DRAWABLE]
        if huge:
            what = "swept" if name in names else "measured"
            return (
                f"its {what} {name} reaches {max(huge, key=abs):g}, beyond what a plot's axis "
                f"can span ({DRAWABLE:g} at most)"
            )
    return None


def changed_nothing(
    rows: Sequence[dict[str, Any]], names: Sequence[str], measured: Sequence[str]
) -> list[str]:
    """The swept names whose values changed nothing: every row alike in its outcome and in
    every measured column to the bit, among rows that differ only in that name (a name with
    fewer than two values is left out). ``legdsl tune`` says as much of tuned parameters."""
    columns = [*OUTCOME, *measured]
    said = []
    for name in names:
        others = [n for n in names if n != name]
        groups: dict[tuple[Any, ...], list[dict[str, Any]]] = {}
        for r in rows:
            groups.setdefault(tuple(_key(r.get(n)) for n in others), []).append(r)
        varied = [g for g in groups.values() if len({_key(r.get(name)) for r in g}) > 1]
        ran = any(r.get("outcome") == "ok" for g in varied for r in g)  # not all fell alike
        if ran and all(
            len({tuple(_key(r.get(c)) for c in columns) for r in g}) == 1 for g in varied
        ):
            said.append(name)
    return said


def _key(value: Any) -> Any:
    """A cell as a key of its own value (NaN equal to NaN)."""
    if isinstance(value, float) and math.isnan(value):
        return "nan"
    return value


def step_of(options: Any, model: Any) -> str:
    """The step a sweep's runs take, and where it is from (a sweep has no --dt)."""
    given = model.simulation.dt is not None
    where = "the file's simulation block" if given else "the default: the file's gives none"
    return f"dt {options.dt:g}s, {where}"
