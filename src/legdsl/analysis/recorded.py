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
from legdsl.lang.errors import LegError, UsageError
from legdsl.sim.trajectory import Trajectory, load_run_info


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
    try:
        info = load_run_info(run)
        if run_source(run, info) is None:
            return None
        return recorded_model(run, info)[1]
    except (LegError, UsageError):
        return None


def same_run(
    directory: Path,
    info: dict[str, Any],
    trajectory: Trajectory,
    model: Model | None,
    source: Path | None,
    give: str = "",
) -> None:
    """Refuse (``UsageError``) a run directory whose trajectory.npz is not the run its
    run.json records (a file copied from another run's directory): against ``model``, the
    creature read back from ``source`` (its coordinates, their names and its contacts), and
    against the samples run.json counts. ``give`` says how the caller takes another .leg
    file ("" where it takes none)."""
    if model is not None:
        if trajectory.q.shape[1] != model.nq:
            raise UsageError(
                f"{directory}: the run has {trajectory.q.shape[1]} coordinates but {source} "
                f"describes {model.nq}; was the .leg file changed after the run, or "
                "trajectory.npz copied from another run?"
            )
        # a run without a fingerprint (an older legdsl's) may be of another creature with as
        # many coordinates: its names say so (drawn, its forces would go to the wrong contacts)
        contacts = tuple(c.name for c in model.contacts)
        other = f"give the .leg file the run was made with ({give}), or " if give else ""
        for what, recorded, described in (
            ("coordinates", trajectory.q_names, model.q_names),
            ("contacts", trajectory.contact_names, contacts),
        ):
            if tuple(recorded) != tuple(described):
                raise UsageError(
                    f"{directory}: the run's {what} ({', '.join(recorded) or 'none'}) are not "
                    f"those of {source} ({', '.join(described) or 'none'}); {other}run "
                    f"{source} again"
                )
    samples = info.get("samples")
    if isinstance(samples, int) and not isinstance(samples, bool) and samples != len(trajectory):
        raise UsageError(
            f"{directory}: its trajectory.npz holds {len(trajectory)} samples and its run.json "
            f"says the run recorded {samples}: they are not of one run (a file copied from "
            "another run's directory?); run the creature again (legdsl run FILE.leg --out DIR)"
        )


def one_run(directory: Path, trajectory: Trajectory) -> None:
    """``same_run`` for the readers that do without the creature (``plot``, ``metrics``),
    which drew and measured a trajectory.npz beside another run's run.json without a word:
    against the creature where its .leg file is at hand and run.json's fingerprint says it
    is the run's, unchanged (else the file may be another creature's), and the samples.
    Without a run.json (or with a damaged one: its readers say so) there is nothing to
    compare."""
    try:
        info = load_run_info(directory)
    except UsageError:
        return
    source, model = run_source(directory, info), None
    if source is not None and info.get("creature_fingerprint") is not None:  # else the file
        # may not be the run's creature (an older legdsl's run.json): the samples must do
        try:
            source, model = recorded_model(directory, info, source)
        except (LegError, UsageError):  # changed, or not loading: its readers say so
            model = None
    same_run(directory, info, trajectory, model, source)
