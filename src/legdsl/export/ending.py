"""How a run that did not end ``ok`` is told by its animation exports.

A run that fell, diverged or was interrupted is kept and can be exported as any other; the
HTML player's panel and a video's caption say how it ended, and so does each animation file
where its format has a place for it: the glTF scene's ``extras`` (``status``,
``ended_at``, ``cause``), the USD layer's ``customLayerData`` and documentation. BVH has no
comment or metadata syntax (its readers take every word as part of the hierarchy), so a
BVH file cannot say it: ``legdsl export-motion`` and ``legdsl animate`` say it on standard
error for every format, where the run did not end ok.
"""

from __future__ import annotations

from typing import Any


def ending(motion: Any) -> dict[str, Any]:
    """``status``, ``ended_at`` (s, the run's own time) and ``cause`` of a run that did not
    end ok, as its run.json has them; empty for one that did."""
    if motion.status == "ok":
        return {}
    out: dict[str, Any] = {"status": motion.status}
    if motion.ended_at is not None:
        out["ended_at"] = motion.ended_at
    if motion.cause or motion.message:
        out["cause"] = motion.cause or motion.message
    return out


def ending_text(motion: Any) -> str:
    """``fell at t = 0.176 s: the root fell to ...``: how the run ended, in a sentence's
    words; empty for a run that ended ok."""
    told = ending(motion)
    if not told:
        return ""
    when = f" at t = {told['ended_at']:g} s" if "ended_at" in told else ""
    cause = f": {told['cause']}" if "cause" in told else ""
    return f"{told['status']}{when}{cause}"


def ending_note(motion: Any, run: str, out: str) -> str:
    """The note said on standard error when ``out`` is written from a run that did not end
    ok; empty for one that did."""
    text = ending_text(motion)
    if not text:
        return ""
    return (
        f"legdsl: note: the run in {run} did not end ok ({text}); {out} shows its motion up to then"
    )
