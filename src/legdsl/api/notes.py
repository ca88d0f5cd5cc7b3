"""The notes ``legdsl run`` prints about a run, as Python warnings for the API's callers.

Each is a ``LegdslWarning`` (a ``UserWarning``) with the text the command line prints after
``legdsl: note:`` or ``legdsl: warning:``, reported at the caller's line: shown once by
default, silenced with ``warnings.filterwarnings("ignore", category=LegdslWarning)``, an
error under ``pytest -W error``. A session with a log (the command line's) prints them
there instead, never both.
"""

from __future__ import annotations

import contextlib
import sys
import threading
import warnings
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import Any

# legdsl's folder as its modules' code names it (as imported, and with its links resolved)
_PACKAGE = tuple({str(Path(__file__).parent.parent), str(Path(__file__).resolve().parent.parent)})


class LegdslWarning(UserWarning):
    """A note about a run that does not stop it: a switch to the controller already running,
    an actuator that chatters at its bound, a change asked for after the run's end, a drop
    whose fall outlasts the run, a passive run of a creature that has controllers..."""


def warn(text: str) -> None:
    """``text`` as a ``LegdslWarning`` at the first caller outside legdsl (its own line)."""
    frame, level = sys._getframe(0), 1
    while frame is not None and frame.f_code.co_filename.startswith(_PACKAGE):
        frame, level = frame.f_back, level + 1  # type: ignore[assignment]
    warnings.warn(text, LegdslWarning, stacklevel=level)


@contextlib.contextmanager
def from_threads(session: Any) -> Iterator[Callable[[], None]]:
    """While a batch runs in threads, their notes wait for the caller's thread (``flush``):
    warned of in a thread, they would point at the thread pool, not the caller's line."""
    hook, caller, pending = session.note, threading.get_ident(), []
    session.tells_runs = False  # the caller tells each run's notes as it comes back

    def note(text: str) -> None:
        warn(text) if threading.get_ident() == caller else pending.append(text)

    def flush() -> None:
        while pending:
            warn(pending.pop(0))

    session.note = note if hook is not None else None
    try:
        yield flush
    finally:
        session.note, session.tells_runs = hook, True


class _NotGiven:
    def __repr__(self) -> str:
        return "NOT_GIVEN"


# controller= left out: a passive run, with a warning (controller=None asks for one, without)
NOT_GIVEN: Any = _NotGiven()


def before_run(
    session: Any, plan: dict[str, Any], passive_asked: bool = False, unreached: Sequence[str] = ()
) -> None:
    """What ``legdsl run`` notes before a run, told by ``session`` (a ``RunSession``: to its
    log, else as warnings) as the command line's are (``RunSession.tell_before``; it notes the
    rest as it prepares); ``passive_asked``: the caller wrote controller=None, so a passive run
    is not news; ``unreached``: the notes of settings for gait bands the run never reaches."""
    session.tell_before(plan["controller"], plan["settings"], plan["options"], unreached,
                        plan.get("sources"))  # fmt: skip
    names = [c.name for c in session.model.controllers]
    if plan["controller"] is None and names and not passive_asked:  # legdsl run's summary says it
        session.tell("note", f"controller: none, a passive run: choose one with controller="
                     f"{names[0]!r} (the file has {', '.join(names)}), or controller=None for "
                     "a passive run")  # fmt: skip


MOST_NOTES = 5  # distinct notes on a batch's copies told one by one; the rest counted in one


def after_copies(session: Any, copies: Any) -> None:
    """The notes ``legdsl run`` prints after a run (``run_notes``: a speed off its command, a
    state held for seconds, a path far off), for a batch's ``copies`` (``Batch.run``'s): each
    distinct one told once by ``session``, with the copies it concerns (``run`` and
    ``run_many`` tell each run's; the copies said nothing, their notes only in run.json)."""
    from legdsl.pipeline.run_notes import run_notes

    concerned: dict[str, list[int]] = {}
    for k in range(len(copies)):
        if copies.status[k] == "ok":  # the notes are of a run that ended ok (and run.json's)
            for note in run_notes(copies.run(k)):
                concerned.setdefault(note, []).append(k)
    told = list(concerned.items())
    for note, which in told[:MOST_NOTES]:
        session.tell("note", f"{_which(which, len(copies))}: {note}")
    if len(told) > MOST_NOTES:
        rest = sorted({k for _, which in told[MOST_NOTES:] for k in which})
        session.tell("note", f"{len(told) - MOST_NOTES} more notes, on {_which(rest, len(copies))}"
                     ": each copy's are in copies[k].info['notes']")  # fmt: skip


def _which(copies: list[int], n: int) -> str:
    """'copy 3 of 8', 'copies 0, 1 (2 of 2)', 'copies 0, 1, 2, ... (40 of 256)'."""
    if len(copies) == 1:
        return f"copy {copies[0]} of {n}"
    shown = ", ".join(map(str, copies[:8])) + (", ..." if len(copies) > 8 else "")
    return f"copies {shown} ({len(copies)} of {n})"
