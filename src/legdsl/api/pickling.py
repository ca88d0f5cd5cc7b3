"""A run or a creature sent between processes (``pickle``, ``multiprocessing``).

A run's samples, model and run.json go as they are; the generated dynamics module, which
pickle cannot carry, goes as its file and is imported again on first use
(``legdsl.api.Run._motion``), checked to be the same creature's still. A creature goes as
its ``.leg`` file, checked again on arrival, and must still describe the same creature and
controllers."""

from __future__ import annotations

import os
from pathlib import Path
from types import ModuleType
from typing import Any

from legdsl.ir.model import Model
from legdsl.lang.errors import UsageError

AGAIN = "save the run with run.save(DIR) and read it back with legdsl.open_run(DIR)"


def picklable(state: dict[str, Any]) -> dict[str, Any]:
    """A Run's ``__dict__`` without the module (kept as its file, absolute: the other
    process may work elsewhere) and without the session's run (its controller's state
    machine holds modules too; ``Run.save`` writes the same files without it)."""
    state = dict(state)
    dynamics = state.pop("_dynamics", None)
    if dynamics is not None and getattr(dynamics, "__file__", None):
        state["_dynamics_file"] = os.path.abspath(dynamics.__file__)
    state["_dynamics"] = None
    state["_session_run"] = None
    return state


def creature_state(session: Any) -> tuple[str, str, str, tuple[str, ...]]:
    """What a creature is sent as: its file and generated directory (absolute: the other
    process may work elsewhere), its name, and the fingerprints of what it is."""
    return (os.path.abspath(session.source), session.model.name,
            os.path.abspath(session.generated), _fingerprints(session.model))  # fmt: skip


def creature_again(source: str, name: str, generated: str, was: tuple[str, ...]) -> Any:
    """A creature that came through pickle: its file read and checked again here, and only
    then compiled (a refused one left ``generated/`` to the creature it holds)."""
    from legdsl.api import Creature
    from legdsl.pipeline.session import RunSession, check_file

    if not Path(source).is_file():
        now = " (a folder is in its place)" if Path(source).is_dir() else ""
        raise UsageError(f"this creature came through pickle, but its file {source} is gone{now}")
    model, syntax = check_file(source, name)
    if _fingerprints(model) != was:  # the file, or one it uses (its shared parts)
        raise UsageError(f"this creature came through pickle, but {source} or a file it uses "
                         "has changed since: its creature or controllers are not the ones sent; "
                         "load it again with legdsl.load and send that")  # fmt: skip
    return Creature(RunSession.from_checked(model, source, syntax, generated))


def _fingerprints(model: Model) -> tuple[str, ...]:
    from legdsl.codegen.fingerprints import controller_fingerprint, creature_fingerprint

    controllers = (controller_fingerprint(model, c) for c in model.controllers)
    return (creature_fingerprint(model), *controllers)


def dynamics_again(model: Model, file: str | None) -> ModuleType:
    """The generated dynamics module at ``file``, imported again for ``model``."""
    from legdsl.codegen.fingerprints import model_fingerprint
    from legdsl.pipeline.generated import import_module_file

    if file is None or not Path(file).is_file():
        raise UsageError(f"this run came through pickle and its generated dynamics ({file}) "
                         f"are gone; {AGAIN}")  # fmt: skip
    module = import_module_file(Path(file), f"legdsl_generated_{model.name}_dynamics_again")
    if getattr(module, "MODEL_FINGERPRINT", None) != model_fingerprint(model):
        raise UsageError(f"this run came through pickle and {file} was compiled since from "
                         f"another creature; {AGAIN}")  # fmt: skip
    return module
