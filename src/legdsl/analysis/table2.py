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

from legdsl.analysis.results import GaitMetrics, num_text


def _load(path: Path) -> dict[str, dict[str, tuple[float, float]]]:
    with path.open("rb") as f:
        data = tomllib.load(f)
    return {
        gait: {label: (refs[0], refs[1]) for label, refs in rows.items()}
        for gait, rows in data.items()
    }


TABLE2: dict[str, dict[str, tuple[float, float]]] = _load(Path(__file__).with_name("table2.toml"))


def compare_table(
    metrics: GaitMetrics,
    reference_rows: Mapping[str, Sequence[float | None]],
    headers: Sequence[str] = ("robot/animal", "paper animation"),
) -> str:
    """The run's values beside reference columns (e.g. ``TABLE2["kangaroo hop"]``), as text.

    Rows are matched by label (``"stride duration (s)"``) or key
    (``"stride_duration"``); a row the run did not measure shows ``n/a``.
    """
    by_name = {s.label: s for s in metrics.summaries} | {s.key: s for s in metrics.summaries}
    width = max([len(name) for name in reference_rows] + [8])
    cols = [f"{h:>15}" for h in headers]
    lines = [f"{'quantity':<{width}}  {'this run':>17}  " + "  ".join(cols)]
    for name, refs in reference_rows.items():
        s = by_name.get(name)
        run = "n/a" if s is None else num_text(s.value)
        if s is not None and math.isfinite(s.std):
            run += f" +/- {num_text(s.std)}"
        ref = "  ".join(f"{'n/a' if r is None else f'{r:g}':>15}" for r in refs)
        lines.append(f"{name:<{width}}  {run:>17}  {ref}")
    return "\n".join(lines) + "\n"
