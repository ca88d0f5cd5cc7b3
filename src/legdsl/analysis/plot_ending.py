"""How a run's pictures say it did not end ok (it fell, diverged or was interrupted).

``legdsl plot`` drew such a run as any other: its figures and standard error never said how
it ended, where ``animate`` and ``export-motion`` note it. Now ``plot`` notes it on standard
error in their words, each picture's title begins with it, and a vertical line marks the
time it ended (the time axis reaching it when the window does).
"""

from __future__ import annotations

import textwrap
import warnings
from dataclasses import dataclass
from typing import Any

ENDED_COLOR = "tab:purple"  # not the controller switches' red
TITLE_CHARS = 200  # of the cause in a title; standard error has it whole


@dataclass(frozen=True)
class Ending:
    """A run that did not end ok: its ``status``, when it ended (s) and why."""

    status: str
    at: float | None
    cause: str

    @property
    def text(self) -> str:
        """``fell at t = 0.47 s: the root ...``, as the animation exports' note says it."""
        when = f" at t = {self.at:g} s" if self.at is not None else ""
        return self.status + when + (f": {self.cause}" if self.cause else "")

    def title(self, width: int) -> str:
        """``fell at 0.4704 s: the root ...``, shortened and wrapped to ``width`` characters;
        its time as the note (and ``legdsl run``) says it."""
        when = f" at {self.at:g} s" if self.at is not None else ""
        cut = "\u00a0..."  # a no-break space: wrapped with its last word, not on a line alone
        cause = textwrap.shorten(self.cause, TITLE_CHARS, placeholder=cut) if self.cause else ""
        return textwrap.fill(self.status + when + (f": {cause}" if cause else ""), width)

    def note(self, run: Any, out: Any) -> str:
        """The note said on standard error when ``out`` is drawn from the run in ``run``."""
        return (
            f"legdsl: note: the run in {run} did not end ok ({self.text}); {out} shows its "
            "motion up to then"
        )


def run_ending(info: dict[str, Any]) -> Ending | None:
    """How the run whose run.json holds ``info`` ended, or None where it ended ok. A run told
    diverged after it ran on (an energy rise without a source) diverged at ``diverged_at``, as
    ``legdsl run`` says it, not at its ``ended_at``: every reader names that time."""
    status = str(info.get("status", "ok") or "ok")
    if status == "ok":
        return None
    ended = info.get("ended_at", info.get("sim_time"))
    if status == "diverged" and _number(info.get("diverged_at")):
        ended = info["diverged_at"]
    at = float(ended) if isinstance(ended, int | float) and _number(ended) else None
    return Ending(status, at, str(info.get("cause") or info.get("message") or ""))


def _number(x: Any) -> bool:
    return isinstance(x, int | float) and not isinstance(x, bool)


def shown_span(t: Any, ending: Ending | None, t_to: float | None) -> tuple[float, float]:
    """The time axis of a run's pictures for a window whose samples are ``t``: from its first
    to its last sample, on to the time the run ended where the window reaches it (a diverged
    run's last state is not recorded). Figure 6 and the footfall diagram share it."""
    first, last = float(t[0]), float(t[-1])
    reached = ending is not None and ending.at is not None and (t_to is None or t_to >= ending.at)
    if reached and ending is not None and ending.at is not None and last < ending.at:
        last = ending.at
    return first, last


def mark_ending(
    axes: Any, ending: Ending | None, first: float, last: float, word: bool = True
) -> list[Any]:
    """A vertical line on each of ``axes`` at the time the run ended, where it is shown, and
    (``word``) its status (``fell``) on top of the first: the texts drawn (``stack_labels``)."""
    if ending is None or ending.at is None or not first <= ending.at <= last:
        return []
    for ax in axes:
        ax.axvline(ending.at, color=ENDED_COLOR, linewidth=1.5, linestyle="-.")
    top = axes[0]
    if not word:
        return []
    return [top.text(ending.at, 1.0, f" {ending.status}", color=ENDED_COLOR, fontsize=8,
                     va="bottom", ha="right", transform=top.get_xaxis_transform())]  # fmt: skip


LINE = 1.25  # a title's line, in its font's sizes (matplotlib spaces lines 1.2 apart)


def title_room(title: str, fontsize: float) -> float:
    """The height (in) a title's lines after its first take: a picture sized for a one-line
    title grows by it (a footfall diagram of one row, 1.35 in tall, had no room for the
    lines saying how its run diverged, and its title was cut off at the top)."""
    return title.count("\n") * fontsize * LINE / 72


def lay_out(fig: Any, tries: int = 4) -> None:
    """``fig.tight_layout()``, the figure made taller where its margins could not hold what
    is around its axes (matplotlib warned "Tight layout not applied" on standard error and
    drew the title off the picture)."""
    for _ in range(tries):
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always")
            fig.tight_layout()
        if not any("Tight layout not applied" in str(w.message) for w in said):
            return
        fig.set_figheight(fig.get_figheight() * 1.5)
