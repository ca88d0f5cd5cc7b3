"""The creature a recorded run was made with, read back from its ``.leg`` file.

``run.json`` names the source file and records the creature's fingerprint
(``creature_fingerprint``: the tree, legs, actuators, ground and initial state). The
commands that read a run with its creature (``plot``, ``metrics``, ``animate``,
``export-motion``, ``replay``) take the creature from here, and refuse a run whose
creature has changed since: drawn on the new one it would be wrong (a foot under the
floor), with nothing to say so.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from legdsl.analysis.rerun import rerun_command
from legdsl.check.source import check_file, choose
from legdsl.codegen.fingerprints import creature_fingerprint
from legdsl.ir.model import Model
from legdsl.lang.errors import UsageError


def run_source(directory: Path, info: dict[str, Any]) -> Path | None:
    """The run's ``.leg`` file as run.json names it: from here, or beside the run."""
    named = Path(str(info.get("source", "")))
    return next((c for c in (named, directory / named, directory / named.name) if c.is_file()),
                None)  # fmt: skip


def recorded_model(
    directory: Path, info: dict[str, Any], source: Path | None = None, give: str = "--source FILE"
) -> tuple[Path, Model]:
    """The ``.leg`` file and checked creature of the run in ``directory`` (``info`` its
    run.json): ``source``, or the file run.json names; ``UsageError`` if it is not found
    (saying to give it with ``give``: the caller's way, a flag or an argument) or its
    creature has changed since the run."""
    source = source if source is not None else run_source(directory, info)
    if source is None:
        raise UsageError(
            f"{directory}/run.json names the source {str(info.get('source', ''))!r}, which is "
            f"not found from here; pass the .leg file with {give}"
        )
    models = check_file(source)
    model = choose(models, info.get("creature"), source)
    recorded = info.get("creature_fingerprint")
    if recorded is not None and recorded != creature_fingerprint(model):
        again = rerun_command(source, directory, info, model, len(models) > 1)
        if info.get("start"):  # a run_copies copy's own q0, v0: no legdsl run starts there
            again = (f"with run_copies(), from the start (q0, v0), controller, options and "
                     f"settings its run.json lists, and save() it to {directory}")  # fmt: skip
        raise UsageError(
            f"{source} has changed since the run in {directory} was recorded: its creature "
            f"'{model.name}' is not the one the run used; run it again ({again})"
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
