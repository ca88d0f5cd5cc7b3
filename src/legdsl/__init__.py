"""legdsl: a compiler and runner for .leg files describing legged creatures and their control.

    import legdsl
    creature = legdsl.load("creatures/kangaroo.leg")
    run = creature.run(controller="hop", set={"speed": "3 m/s"}, time=5)

``load`` and ``open_run`` are the public API (``legdsl.api``, docs/api.md); they are imported
when first used, so that the stages below, which read ``__version__`` from here, never
import the API.
"""

from __future__ import annotations

import os
import sys
from typing import Any

__version__ = "0.1.0"

# sympy keeps the expressions it built in a cache of 1000 by default, which a creature's
# lowering overflows: with 50000 the quadruped compiles 13% faster and a 10-DOF random rig 30%,
# byte for byte the same code, for some 15 MB more (docs/compiler.md). sympy reads it once, as
# it is first imported; a user's own setting wins.
if "sympy" not in sys.modules:
    os.environ.setdefault("SYMPY_CACHE_SIZE", "50000")
__all__ = ["__version__", "load", "open_run"]
# the API's names, read from legdsl.api when first used (docs/api.md writes legdsl.Run and
# legdsl.api.Quantity, legdsl.api.LegdslWarning: 'legdsl.api' after 'import legdsl' alone was
# an AttributeError, the API not yet imported)
_API_NAMES = ("load", "open_run", "Creature", "Run", "Copies", "Quantity", "LegdslWarning")


def __getattr__(name: str) -> Any:
    if name == "api" or name in _API_NAMES:
        from legdsl.signals import import_held

        # a Ctrl-C in the 0.6 s import comes once it is whole
        api = import_held("legdsl.api")
        return api if name == "api" else getattr(api, name)
    raise AttributeError(f"module 'legdsl' has no attribute {name!r}")


def __dir__() -> list[str]:
    """The public names and the module's own (not os, sys, Any: its imports)."""
    return sorted({*(n for n in globals() if n.startswith("__")), "api", *_API_NAMES})
