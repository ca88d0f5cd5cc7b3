"""The picture of a sweep: one metric over one swept name (lines) or two (a heat map).

A third swept name and more make one panel per combination of their values (up to
``MOST_PANELS``), all on one colour scale: drawn over the first two alone, the runs at the
other values fell on the same cells, and only one of each showed. Random or Latin-hypercube
draws are never cells or panels (each value is its own: six draws of a third name made six
one-cell heat maps): they are the axes of a scatter, or vary among its dots. Runs that fell
or diverged are red crosses everywhere (in the lines at the foot of the axes, where a metric
they never measured cannot place them).
"""

from __future__ import annotations

import itertools
import math
import textwrap
from collections.abc import Sequence
from pathlib import Path
from typing import Any

MOST_PANELS = 12  # more combinations of the other swept names: one panel, the others told


def plot_sweep(
    rows: Sequence[dict[str, Any]],
    names: Sequence[str],
    metric: str,
    out: Path,
    units: dict[str, str] | None = None,
    random_names: Sequence[str] = (),
) -> Path:
    """Draw ``metric`` of each row against the swept ``names`` (runs that fell are crosses);
    ``units`` labels the axes (name -> unit); ``random_names`` are the names drawn at random
    or by Latin hypercube (``--random``, ``--lhs``)."""
    given = units or {}

    def label(name: str) -> str:
        return f"{name} ({given[name]})" if given.get(name) else name

    from legdsl.analysis.plot import pyplot

    plt = pyplot()
    ok = [str(r.get("outcome")) == "ok" for r in rows]
    title = f"{metric} over {len(rows)} runs ({sum(ok)} ran to the end)"
    if len(names) == 1:
        fig, ax = plt.subplots(figsize=(6.4, 4.8), dpi=110, layout="constrained")
        _lines(ax, rows, names[0], metric)
        ax.set_xlabel(label(names[0]))
        ax.set_ylabel(label(metric))
    else:
        if len(names) > 2:  # the draws as the axes, the grid's names as the panels
            names = sorted(names, key=lambda n: n not in random_names)
        others = [n for n in names[2:] if n not in random_names]
        varying = [n for n in names[2:] if n in random_names]
        groups = sorted({tuple(as_number(r.get(n)) for n in others) for r in rows})
        if len(groups) > MOST_PANELS:
            groups, others, varying = [()], [], list(names[2:])
        if varying:  # the title says what varies among the dots
            title += (
                f"; {', '.join(varying)} var{'y' if len(varying) > 1 else 'ies'} among the dots"
            )
        heat = not varying and not set(names[:2]) & set(random_names)
        cols = min(3, len(groups))
        rows_of = math.ceil(len(groups) / cols)
        fig, axes = plt.subplots(rows_of, cols, figsize=(4.2 * cols + 1.2, 3.6 * rows_of + 0.6),
                                 dpi=110, squeeze=False, layout="constrained")  # fmt: skip
        values = [as_number(r.get(metric)) for r, good in zip(rows, ok, strict=True) if good]
        finite = [v for v in values if math.isfinite(v)] or [0.0]
        scale = colour_scale(metric, finite)
        image = None
        for ax, group in zip(axes.flat, groups, strict=False):
            inside = [r for r in rows if tuple(as_number(r.get(n)) for n in others) == group]
            image = _map(ax, inside, names[0], names[1], metric, scale, heat)
            ax.set_xlabel(label(names[0]))
            ax.set_ylabel(label(names[1]))
            if others:
                ax.set_title(", ".join(f"{n} = {v:g} {given.get(n, '')}".rstrip()
                                       for n, v in zip(others, group, strict=True)))  # fmt: skip
        for ax in itertools.islice(axes.flat, len(groups), None):
            ax.set_axis_off()
        fig.colorbar(image, ax=axes.ravel().tolist(), label=label(metric))
    # wrapped to the figure's width (a long one ran off both edges)
    fig.suptitle("\n".join(textwrap.wrap(title, int(fig.get_figwidth() * CHARACTERS_PER_INCH))))
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out)
    plt.close(fig)
    return out


# Metrics whose sign says something (over or under the command): drawn on a diverging colour
# map centred on zero. Any metric with values of both signs is drawn so too.
SIGNED_METRICS = frozenset({"speed_error"})


def colour_scale(metric: str, finite: Sequence[float]) -> dict[str, Any]:
    """The heat map's colours for ``metric``'s ``finite`` values: a signed one (or one with
    values both sides of zero) on a diverging map (PuOr: not the red of the falls' crosses)
    whose white is zero, its limits as far either side; a magnitude on viridis over its
    range. (viridis drew a signed speed_error's most negative value darkest, read as best.)"""
    from matplotlib import colormaps

    low, high = min(finite), max(finite)
    # a cell with no value (its run fell) grey: PuOr's white is zero
    if metric in SIGNED_METRICS or (low < 0.0 < high):
        most = max(abs(low), abs(high)) or 1.0
        return {"vmin": -most, "vmax": most, "cmap": colormaps["PuOr"].with_extremes(bad="0.8")}
    return {"vmin": low, "vmax": high, "cmap": colormaps["viridis"].with_extremes(bad="0.8")}


def _lines(ax: Any, rows: Sequence[dict[str, Any]], name: str, metric: str) -> None:
    """The metric along one swept name; a run that fell as a cross at the foot of the axes."""
    import numpy as np

    at = np.array([as_number(r.get(name)) for r in rows])
    values = np.array([as_number(r.get(metric)) for r in rows])
    order = np.argsort(at)
    kept = np.array([str(r.get("outcome")) == "ok" for r in rows])[order]
    ax.plot(at[order][kept], values[order][kept], "o-", label="ran to the end")
    if (~kept).any():  # x in data, y in the axes: a fall has no metric to stand at
        ax.plot(at[order][~kept], [0.03] * int((~kept).sum()), "rx", clip_on=False,
                transform=ax.get_xaxis_transform(), label="fell or diverged")  # fmt: skip
    if not np.isfinite(values[order][kept]).any():
        ax.set_yticks([])  # nothing measured: no scale to read
    ax.legend()


def _map(
    ax: Any,
    rows: Sequence[dict[str, Any]],
    a: str,
    b: str,
    metric: str,
    scale: dict[str, Any],
    heat: bool = True,
) -> Any:
    """A heat map over a full grid of ``a`` and ``b``, else a scatter; falls are crosses.
    Not ``heat``: a scatter always (other names vary among the runs of a cell: a grid name
    beside drawn ones made a full grid of stripes, one draw each)."""
    import numpy as np

    ok = [str(r.get("outcome")) == "ok" for r in rows]
    xs = sorted({as_number(r.get(a)) for r in rows})
    ys = sorted({as_number(r.get(b)) for r in rows})
    at_x, at_y = as_number, as_number  # where a row's value is drawn
    if heat and len(xs) * len(ys) == len(rows):  # a full grid: a heat map
        grid = np.full((len(ys), len(xs)), np.nan)
        for r, good in zip(rows, ok, strict=True):
            grid[ys.index(as_number(r.get(b))), xs.index(as_number(r.get(a)))] = (
                as_number(r.get(metric)) if good else np.nan
            )
        # an axis of unevenly spaced values has equal cells, one per value, each ticked at
        # its centre (cells between midpoints of 50, 100 and 1000 put 100's from 75 to 550,
        # its tick at the foot)
        at_x, xs_drawn = _placed(xs)
        at_y, ys_drawn = _placed(ys)
        image = ax.pcolormesh(_edges(xs_drawn), _edges(ys_drawn), grid, shading="flat", **scale)
        # each cell labelled with its swept value (matplotlib's own ticks, 0.06 and 0.08
        # between cells of 0.04, 0.07 and 0.1, named values no run had)
        ax.set_xticks(*_cell_ticks(xs_drawn, labels=xs))
        ax.set_yticks(*_cell_ticks(ys_drawn, MOST_Y_TICKS, labels=ys))
    else:  # random or Latin-hypercube draws: a scatter of the runs that lasted
        lasted = [r for r, good in zip(rows, ok, strict=True) if good]
        image = ax.scatter([as_number(r.get(a)) for r in lasted], [as_number(r.get(b)) for r in lasted],
                           c=[as_number(r.get(metric)) for r in lasted], **scale)  # fmt: skip
    fell = [r for r, good in zip(rows, ok, strict=True) if not good]
    ax.plot([at_x(r.get(a)) for r in fell], [at_y(r.get(b)) for r in fell], "rx")
    return image


def _placed(values: list[float]) -> tuple[Any, list[float]]:
    """Where a heat map draws sorted ``values``: as they are where they are evenly spaced,
    else one equal cell each (0, 1, 2, ...); (a cell's value to where it is drawn, the
    places)."""
    steps = [b - a for a, b in zip(values, values[1:], strict=False)]
    span = values[-1] - values[0] if values else 0.0
    if not steps or max(steps) - min(steps) <= 1e-6 * abs(span):
        return as_number, values
    index = {v: float(k) for k, v in enumerate(values)}
    return (lambda value: index.get(as_number(value), math.nan)), list(index.values())


CHARACTERS_PER_INCH = 9  # of the title's font, for wrapping it
X_ROOM, MOST_Y_TICKS = 50, 12  # a panel's width in characters of its labels; rows of labels


def _cell_ticks(
    centres: list[float], most: int | None = None, labels: list[float] | None = None
) -> tuple[list[float], list[str]]:
    """Ticks at the cells' centres, labelled with their swept values (``labels``, where the
    centres are not the values): every ``k``-th from the first, at most ``most`` of them, else
    as many as fit a panel's width (``X_ROOM``) side by side."""
    texts = [f"{v:.4g}" for v in (centres if labels is None else labels)]
    fit = most or max(2, X_ROOM // (max(map(len, texts)) + 2))
    step = math.ceil(len(centres) / fit)
    return centres[::step], texts[::step]


def as_number(value: Any) -> float:
    """A table cell as a float; NaN for one that holds none."""
    try:
        return float(value)
    except (TypeError, ValueError):
        return math.nan


def _edges(centres: list[float]) -> list[float]:
    """Cell edges around sorted centres (one cell for a single value)."""
    if len(centres) == 1:
        return [centres[0] - 0.5, centres[0] + 0.5]
    mids = [(a + b) / 2 for a, b in zip(centres, centres[1:], strict=False)]
    return [2 * centres[0] - mids[0], *mids, 2 * centres[-1] - mids[-1]]
