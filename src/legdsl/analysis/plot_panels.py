"""Figure 6's joint-angle panels and its note for a root welded to the world.

A leg's joint curves were black in four line styles, so a fifth joint was drawn as the first
(the odd creature's sh_x and tw, both solid black, crossed and could not be told apart). Each
curve of a panel now has its own colour and line style: 7 colours and 4 styles, stepped
together (7 and 4 have no common factor), make 28 distinct pairs, and two curves after one
another differ in both. A panel holds at most ``MOST_CURVES`` of them (a longer legend runs
off the panel); a leg with more joints is split over several panels of even size, each
saying which of the leg's joints it draws.

A creature whose root is welded to the world (``fixed at``) cannot pitch or roll: its pitch
panel was a flat line at zero with no word why; it now says so instead of drawing it.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from legdsl.sim.trajectory import Trajectory

LINE_STYLES = ("-", "--", "-.", ":")
# no red (controller switches), purple (the end of a run) or grey (stances): those are marks
COLOURS = ("k", "tab:blue", "tab:orange", "tab:green", "tab:brown", "tab:cyan", "tab:olive")
MOST_CURVES = 8  # joint curves in one panel: its legend beside it fits its height


def legend(ax: Any) -> None:
    """A panel's legend beside it, on the right, where it hides none of the curves (inside,
    at the lower right, it hid a kangaroo's third speed dip and its hip's trough)."""
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False,
              borderaxespad=0.0, handlelength=2.5)  # fmt: skip


def curve_style(k: int) -> dict[str, str]:
    """The colour and line style of a panel's ``k``-th curve: no two alike for k under 28."""
    return {"color": COLOURS[k % len(COLOURS)], "linestyle": LINE_STYLES[k % len(LINE_STYLES)]}


def joint_groups(names: list[str]) -> list[list[str]]:
    """``names`` split over as few panels as hold ``MOST_CURVES`` each, as evenly as can be
    (one empty panel for none)."""
    panels = max(1, math.ceil(len(names) / MOST_CURVES))
    size = math.ceil(len(names) / panels) if names else 0
    return [names[i * size : (i + 1) * size] for i in range(panels)]


def draw_joints(
    panels: list[Any], groups: list[list[str]], tr: Trajectory, window: np.ndarray, leg: str
) -> None:
    """Each group of joint angles (deg) in its panel, with its legend; more than one panel
    says which share of the leg's joints each draws."""
    for n, (ax, names) in enumerate(zip(panels, groups, strict=True)):
        for k, name in enumerate(names):
            column = tr.q_names.index(name)
            ax.plot(tr.t[window], np.degrees(tr.q[window, column]), label=name, **curve_style(k))
        if names:
            legend(ax)
        part = f", {n + 1} of {len(groups)}" if len(groups) > 1 else ""
        ax.set_ylabel(f"leg '{leg}'{part}\njoint angles (deg)" if leg else "joint angles (deg)")


def welded_note(ax: Any, root: str) -> None:
    """The pitch panel of a creature welded to the world: a sentence in place of zeros."""
    ax.text(0.5, 0.5, f"root body '{root}' is welded to the world ('fixed at' in its .leg "
            "file):\nit cannot move, pitch or roll", transform=ax.transAxes, ha="center",
            va="center", fontsize=9, color="0.3", zorder=5,
            bbox={"facecolor": "white", "edgecolor": "none"})  # fmt: skip
    ax.set_yticks([])
    ax.set_ylabel("body pitch (deg)")
