"""A run sent between processes (``pickle``, ``multiprocessing``): its samples, model and
run.json go as they are; the generated dynamics module, which pickle cannot carry, goes as
its file and is imported again on first use (``legdsl.api.Run._motion``), checked to be the
same creature's still."""

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


def dynamics_again(model: Model, file: str | None) -> ModuleType:
    """The generated dynamics module at ``file``, imported again for ``model``."""
    from legdsl.codegen.python.dynamics import model_fingerprint
    from legdsl.pipeline.generated import import_module_file

    if file is None or not Path(file).is_file():
        raise UsageError(f"this run came through pickle and its generated dynamics ({file}) "
                         f"are gone; {AGAIN}")  # fmt: skip
    module = import_module_file(Path(file), f"legdsl_generated_{model.name}_dynamics_again")
    if getattr(module, "MODEL_FINGERPRINT", None) != model_fingerprint(model):
        raise UsageError(f"this run came through pickle and {file} was compiled since from "
                         f"another creature; {AGAIN}")  # fmt: skip
    return module
