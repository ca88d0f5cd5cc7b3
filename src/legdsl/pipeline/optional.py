"""Libraries some commands need and legdsl does not install by default (usd-core, pygltflib,
mujoco, pandas, Dask)."""

from __future__ import annotations

import importlib
import sys
from typing import Any


def not_installed(e: ImportError, package: str) -> bool:
    """Whether ``e`` says ``package`` is not installed, the one case for "pip install it";
    an installed library that fails to load (a shared object that cannot be mapped under
    ``ulimit -v``) is not that, and goes on as an ImportError to say so."""
    name = e.name or ""
    return isinstance(e, ModuleNotFoundError) and (
        name == package or name.startswith(package + ".")
    )


def import_whole(name: str) -> Any:
    """``import name``, leaving nothing half-imported behind when it is cut short: a Ctrl-C
    caught in a notebook during ``import cma`` (which imports matplotlib) left matplotlib's
    submodules holding the half-made package, and every later import failed
    (``module 'matplotlib' has no attribute 'get_data_path'``) until the kernel restarted."""
    before = set(sys.modules)
    try:
        return importlib.import_module(name)
    except BaseException:  # only the packages this import brought (numpy's stay: imported twice,
        known = {n.partition(".")[0] for n in before}  # a module would have two states)
        for added in set(sys.modules) - before:
            if added.partition(".")[0] not in known:
                sys.modules.pop(added, None)
        raise
