"""A run of a session (``legdsl.pipeline.session.Run``, a batch copy's too) in one line, its
repr: the dataclass's own printed the whole model and every recorded array (some 290 kB)."""

from __future__ import annotations

from typing import Any


class OneLine:
    """A run's repr in one line (the session's ``Run`` takes it, with ``repr=False``)."""

    def __repr__(self) -> str:
        return run_line(self)


def run_line(run: Any) -> str:
    """``<legdsl run of 'hopper' (controller hop): ok, 0.200 s, 21 samples>``: the creature
    (and the scale it ran at), the controller (or passive), status, simulated time, samples."""
    scaled = f" scaled by {run.scale:g}" if run.scale is not None else ""
    ran = f"controller {run.controller}" if run.controller else "passive"
    n = len(run.result.trajectory)
    return (
        f"<legdsl run of '{run.model.name}'{scaled} ({ran}): {run.status}, "
        f"{run.result.sim_time:.3f} s, {n} sample{'s' if n != 1 else ''}>"
    )
