"""The creature a recorded run was made with, read back from its ``.leg`` file.

``run.json`` names the source file and records the creature's fingerprint
(``creature_fingerprint``: the tree, legs, actuators, ground and initial state; and
``motion_fingerprint``, the same without the bodies' colours and drawing shapes). The
commands that read a run with its creature (``plot``, ``metrics``, ``animate``,
``export-motion``, ``replay``) take the creature from here, and refuse a run whose
creature has changed since: drawn on the new one it would be wrong (a foot under the
floor), with nothing to say so. The animations (``animate``, ``export-motion``,
``replay``) take a creature changed only in its appearance, and draw it as it is now
(``plot`` and ``metrics`` do not: a body's drawing shape is what ``metrics`` measures
against the terrain).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from legdsl.analysis.rerun import rerun_command
from legdsl.check.source import check_file, choose
from legdsl.codegen.fingerprints import creature_fingerprint, motion_fingerprint
from legdsl.ir.model import Model
from legdsl.lang.errors import UsageError


def run_source(directory: Path, info: dict[str, Any]) -> Path | None:
    """The run's ``.leg`` file as run.json names it: from here, or beside the run."""
    named = Path(str(info.get("source", "")))
    return next((c for c in (named, directory / named, directory / named.name) if c.is_file()),
                None)  # fmt: skip


def recorded_model(
    directory: Path,
    info: dict[str, Any],
    source: Path | None = None,
    give: str = "--source FILE",
    drawn: bool = False,
) -> tuple[Path, Model]:
    """The ``.leg`` file and checked creature of the run in ``directory`` (``info`` its
    run.json): ``source``, or the file run.json names; ``UsageError`` if it is not found
    (saying to give it with ``give``: the caller's way, a flag or an argument) or its
    creature has changed since the run. ``drawn``: the caller only draws the run's motion
    (an animation), so a creature changed only in its appearance (colours, drawing shapes:
    ``motion_fingerprint``) is taken, and drawn as it is now; a run.json from before
    ``motion_fingerprint`` was recorded still needs the whole creature unchanged."""
    source = source if source is not None else run_source(directory, info)
    if source is None:
        raise UsageError(
            f"{directory}/run.json names the source {str(info.get('source', ''))!r}, which is "
            f"not found from here; pass the .leg file with {give}"
        )
    models = check_file(source)
    model = choose(models, info.get("creature"), source)
    recorded, now, only = info.get("creature_fingerprint"), creature_fingerprint, ""
    if drawn and info.get("motion_fingerprint") is not None:
        recorded, now = info["motion_fingerprint"], motion_fingerprint
        only = " (in more than its colours and drawing shapes, which an animation takes as they are now)"
    if recorded is not None and recorded != now(model):
        again = rerun_command(source, directory, info, model, len(models) > 1)
        if info.get("start"):  # a run_copies copy's own q0, v0: no legdsl run starts there
            again = (f"with run_copies(), from the start (q0, v0), controller, options and "
                     f"settings its run.json lists, and save() it to {directory}")  # fmt: skip
        raise UsageError(
            f"{source} has changed since the run in {directory} was recorded: its creature "
            f"'{model.name}' is not the one the run used{only}; run it again ({again})"
        )
    return source, model


def model_if_readable(run: Path) -> Model | None:
    """The run's creature read back from its .leg file, or None when the run does not say it
    or the file is not found or no longer reads (a figure then does without it)."""
    from legdsl.lang.errors import LegError
    from legdsl.sim.trajectory import load_run_info

    try:
        info = load_run_info(run)
        if run_source(run, info) is None:
            return None
        return recorded_model(run, info)[1]
    except (LegError, UsageError):
        return None
