"""Table 2 of Raibert & Hodgins (1991) and a run's values beside it.

The paper's numbers are data, in ``table2.toml`` beside this module (shipped in the wheel
with the package); ``TABLE2`` holds them as ``{gait: {row label: (robot or animal, paper
animation)}}``.
"""

from __future__ import annotations

import math
import tomllib
from collections.abc import Mapping, Sequence
from pathlib import Path

from legdsl.analysis.pairs import hip_positions, pair_groups
from legdsl.analysis.results import GaitMetrics
from legdsl.figures import figure
from legdsl.ir.model import Model


def _load(
    path: Path,
) -> tuple[dict[str, dict[str, tuple[float, float]]], dict[str, dict[str, str]]]:
    with path.open("rb") as f:
        data = tomllib.load(f)
    rows = {
        gait: {label: (refs[0], refs[1]) for label, refs in table.items() if isinstance(refs, list)}
        for gait, table in data.items()
    }
    measure = {gait: dict(table.get("measure", {})) for gait, table in data.items()}
    return rows, measure


TABLE2, MEASURE = _load(Path(__file__).with_name("table2.toml"))
# TIME_UNIT[gait]: the natural time (run.json's ``time_unit``) of the creature the gait's
# numbers are for, the shipped file's (its standing height: legdsl.sim.switching.natural_scale)
TIME_UNIT = {
    gait: float(how.pop("time_unit")) for gait, how in MEASURE.items() if "time_unit" in how
}
# MEASURE[gait]: "pairs" (its virtual legs, legdsl.analysis.pairs, or "steps": one of every
# leg, so a stride is a step), "reference" (the stride's virtual leg, or "first"), and paper
# labels measured as legdsl rows (label -> row key)


def virtual_legs(gait: str, model: Model) -> tuple[dict[str, list[str]], str | None]:
    """The virtual legs ``gait``'s rows are measured with (none for most gaits), found from
    ``model``'s hips, and the one whose touchdowns start a stride."""
    how = MEASURE.get(gait, {})
    if "pairs" not in how:
        return {}, None
    if how["pairs"] == "steps":
        return step_legs(gait, [leg.name for leg in model.legs])
    groups = pair_groups(hip_positions(model), how["pairs"])
    reference = how.get("reference", "first")
    return groups, next(iter(groups)) if reference == "first" else reference


def step_legs(gait: str, legs: Sequence[str]) -> tuple[dict[str, list[str]], str | None]:
    """For a gait measured a step a stride (the paper's biped): one virtual leg of all
    ``legs``, whose touchdowns (either foot's) start the strides; none for fewer than two legs,
    whose strides are steps already."""
    name = str(MEASURE[gait].get("reference", "steps"))
    return ({name: list(legs)}, name) if len(legs) > 1 else ({}, None)


def compare_table(
    metrics: GaitMetrics,
    reference_rows: Mapping[str, Sequence[float | None]],
    headers: Sequence[str] = ("robot/animal", "paper animation"),
    measured_as: Mapping[str, str] | None = None,
) -> str:
    """The run's values beside reference columns (e.g. ``TABLE2["kangaroo hop"]``), as text.

    Rows are matched by label (``"stride duration (s)"``) or key
    (``"stride_duration"``), or through ``measured_as`` (label -> key, ``MEASURE[gait]``); a
    row the run did not measure shows ``n/a``.
    """
    alias = dict(measured_as or {})
    by_name = {s.label: s for s in metrics.summaries} | {s.key: s for s in metrics.summaries}
    width = max([len(name) for name in reference_rows] + [8])
    cols = [f"{h:>15}" for h in headers]
    lines = [f"{'quantity':<{width}}  {'this run':>17}  " + "  ".join(cols)]
    for name, refs in reference_rows.items():
        s = by_name.get(name, by_name.get(alias.get(name, "")))
        run = "n/a" if s is None else figure(s.value)
        if s is not None and math.isfinite(s.std):
            run += f" +/- {figure(s.std, s.value)}"
        ref = "  ".join(f"{'n/a' if r is None else f'{r:g}':>15}" for r in refs)
        lines.append(f"{name:<{width}}  {run:>17}  {ref}")
    return "\n".join(lines) + "\n"


def size_note(gait: str, time_unit: float) -> str | None:
    """What ``legdsl metrics --table2 GAIT`` says of a run of a creature of another size than
    the one Table 2's ``gait`` is for (``time_unit``, the run's, L = (its / the gait's)^2 times
    as large, as ``legdsl scale`` or ``--scale`` make it); None within 5% of that size. Table
    2's numbers are not scaled: Table 1 says how they would be."""
    ref = TIME_UNIT.get(gait)
    if ref is None or not math.isfinite(time_unit) or time_unit <= 0:
        return None
    size = (time_unit / ref) ** 2
    if abs(math.log(size)) < math.log(1.05):
        return None
    return (
        f"this creature is {size:.3g} times the size of the one Table 2's {gait} is for (by "
        f"its standing height: run.json's time_unit {time_unit:.4g}, Table 2's {ref:.4g}); "
        f"Table 2's numbers are for that size and are not scaled: at this size, by Table 1, "
        f"its durations and speeds would be {math.sqrt(size):.3g} times as large, its lengths "
        f"{size:.3g} times, its angles and accelerations the same; compare by those factors, "
        "or run the creature at Table 2's size"
    )
