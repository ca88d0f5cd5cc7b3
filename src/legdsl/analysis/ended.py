"""The metrics of a run that did not end ok (it fell, diverged or was interrupted).

``legdsl metrics`` measured such a run as any other, without a word: a run diverged at 0.285 s
printed "3 strides" and a foot clearance at the apex of -0.336 m, its metrics.json held no
status. Now the window of a run that fell or diverged ends at the last touchdown of the
reference before it did (``measured_until``): the strides before then are measured, the one
it fell or diverged in is not (nor its stances, flights, forces or work), so that no value of
the fall or of the blown-up state is averaged in. An interrupted run's motion is real up to
its end and is measured as recorded. Either way a note says how the run ended
(``ending_note``, in the words ``plot`` and ``animate`` use) and metrics.json records it.
"""

from __future__ import annotations

import numpy as np

from legdsl.analysis.plot_ending import Ending

CUT = {"fell": "fall", "diverged": "divergence"}  # the endings whose last stride is left out
EPS_T = 1e-9


def measured_until(
    t: np.ndarray, ref_on: np.ndarray, reference: str | None, t_from: float, t_to: float,
    ending: Ending | None,
) -> tuple[float, str]:  # fmt: skip
    """The window's end for a run that ended so (``ref_on``: where the reference touches;
    ``reference``: its name, None for a creature without contacts) and, where it was cut,
    the note's words on where: the reference's last touchdown before the run fell or diverged
    (a creature without contacts: the time it did), ``t_from`` where there was none after it."""
    if ending is None or ending.status not in CUT or ending.at is None:
        return t_to, ""
    cut, where = ending.at, "when it did"
    if reference is not None:
        rises = np.flatnonzero(np.diff(ref_on.astype(np.int8)) == 1) + 1
        before = t[rises][(t[rises] < ending.at - EPS_T) & (t[rises] >= t_from - EPS_T)]
        cut = float(before[-1]) if before.size else t_from
        where = (f"the last touchdown of {reference} before then" if before.size else
                 f"the window's start, as {reference} did not touch down in it before then")  # fmt: skip
    if cut >= t_to:
        return t_to, ""
    return cut, f"its metrics are measured up to {cut:.3f} s, {where}"


def ending_note(ending: Ending, where: str, cut: str) -> str:
    """What is said of the metrics of ``where`` (``the run in runs/b``), which ended so,
    measured up to ``cut`` (``measured_until``'s words; empty: the window ended before)."""
    said = f"{where} did not end ok ({ending.text})"
    if ending.status not in CUT:
        return f"{said}; its metrics are of its motion up to then"
    if not cut:
        return f"{said}; the window ends before the stride it {ending.status} in"
    return f"{said}; {cut}, so that no stride through the {CUT[ending.status]} is averaged in"
