"""The picture of a sweep: one metric over one swept name (lines) or two (a heat map)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any


def plot_sweep(
    rows: Sequence[dict[str, Any]],
    names: Sequence[str],
    metric: str,
    out: Path,
    units: dict[str, str] | None = None,
) -> Path:
    """Draw ``metric`` of each row against the swept ``names`` (runs that fell are crosses);
    ``units`` labels the axes (name -> unit)."""
    given = units or {}

    def label(name: str) -> str:
        return f"{name} ({given[name]})" if given.get(name) else name

    import numpy as np

    from legdsl.analysis.plot import pyplot

    plt = pyplot()

    def number(value: Any) -> float:
        try:
            return float(value)
        except (TypeError, ValueError):
            return math.nan

    ok = [str(r["outcome"]) == "ok" for r in rows]
    values = np.array([number(r[metric]) for r in rows])
    fig, ax = plt.subplots(figsize=(6.4, 4.8), dpi=110)
    if len(names) == 1:
        at = np.array([number(r[names[0]]) for r in rows])
        order = np.argsort(at)
        kept = np.array(ok)[order]
        ax.plot(at[order][kept], values[order][kept], "o-", label="ran to the end")
        if (~kept).any():
            ax.plot(at[order][~kept], values[order][~kept], "rx", label="fell or diverged")
        ax.set_xlabel(label(names[0]))
        ax.set_ylabel(label(metric))
        ax.legend()
    else:
        a, b = names[:2]
        xs = sorted({number(r[a]) for r in rows})
        ys = sorted({number(r[b]) for r in rows})
        if len(xs) * len(ys) == len(rows):  # a full grid: a heat map
            grid = np.full((len(ys), len(xs)), np.nan)
            for r, v, good in zip(rows, values, ok, strict=True):
                grid[ys.index(number(r[b])), xs.index(number(r[a]))] = v if good else np.nan
            image: Any = ax.pcolormesh(_edges(xs), _edges(ys), grid, cmap="viridis", shading="flat")
            for r, good in zip(rows, ok, strict=True):
                if not good:
                    ax.plot(number(r[a]), number(r[b]), "rx")
        else:  # random or Latin-hypercube draws: a scatter
            image = ax.scatter([number(r[a]) for r in rows], [number(r[b]) for r in rows],
                               c=values, cmap="viridis")  # fmt: skip
        fig.colorbar(image, ax=ax, label=label(metric))
        ax.set_xlabel(label(a))
        ax.set_ylabel(label(b))
    ax.set_title(f"{metric} over {len(rows)} runs ({sum(ok)} ran to the end)")
    fig.tight_layout()
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out)
    plt.close(fig)
    return out


def _edges(centres: list[float]) -> list[float]:
    """Cell edges around sorted centres (one cell for a single value)."""
    if len(centres) == 1:
        return [centres[0] - 0.5, centres[0] + 0.5]
    mids = [(a + b) / 2 for a, b in zip(centres, centres[1:], strict=False)]
    return [2 * centres[0] - mids[0], *mids, 2 * centres[-1] - mids[-1]]
