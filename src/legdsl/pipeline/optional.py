"""Libraries some commands need and legdsl does not install by default (usd-core, pygltflib,
mujoco, pandas, Dask)."""

from __future__ import annotations


def not_installed(e: ImportError, package: str) -> bool:
    """Whether ``e`` says ``package`` is not installed, the one case for "pip install it";
    an installed library that fails to load (a shared object that cannot be mapped under
    ``ulimit -v``) is not that, and goes on as an ImportError to say so."""
    name = e.name or ""
    return isinstance(e, ModuleNotFoundError) and (
        name == package or name.startswith(package + ".")
    )
