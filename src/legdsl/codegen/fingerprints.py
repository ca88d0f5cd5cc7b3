"""What generated code depends on, hashed: a generated module carries the hash of the model it
was printed from, and a run or a file that hashes differently now is stale.

Both targets print these hashes, and the runtime checks them before it loads a module, so they
live apart from the printers (no sympy: loading a fresh module must not import it).
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import fields, is_dataclass, replace
from typing import Any

from legdsl import __version__
from legdsl.ir.model import Controller, Model, Shape


def _clean(obj: Any) -> Any:
    """A dataclass tree as plain data, without source spans or other spelling (so comments,
    layout and the unit a value was written in don't count)."""
    if is_dataclass(obj) and not isinstance(obj, type):
        return {
            f.name: _clean(getattr(obj, f.name))
            for f in fields(obj)
            if f.name != "span"
            and not f.metadata.get("spelling")
            and (getattr(obj, f.name) or not f.metadata.get("omit_empty"))
        }
    if isinstance(obj, tuple | list):
        return [_clean(x) for x in obj]
    return obj


def _digest(payload: Any) -> str:
    return hashlib.sha256(json.dumps(payload, sort_keys=True).encode()).hexdigest()[:16]


def model_fingerprint(model: Model) -> str:
    """A hash of what the dynamics depend on (not spans or comments): the runtime's staleness check."""
    return _digest(
        {
            "legdsl": __version__,
            "planar": model.planar,
            "gravity": model.gravity,
            "bodies": _clean(model.bodies),
            "joints": _clean(model.joints),
            "contacts": _clean(model.contacts),
        }
    )


def creature_fingerprint(model: Model) -> str:
    """A hash of the creature a recorded run shows (the tree, its legs, actuators, ground and
    initial state; not the controllers, spans or comments): a run whose creature hashes
    differently now was made with another creature, and is not drawn on this one."""
    return _digest(
        {
            "model": model_fingerprint(model),
            "legs": _clean(model.legs),
            "actuators": _clean(model.actuators),
            "ground": _clean(model.ground) if model.ground is not None else None,
            "stops": _clean(model.stops),
            "start": [model.q0, model.v0],
        }
    )


def motion_fingerprint(model: Model) -> str:
    """``creature_fingerprint`` without the creature's appearance: each body's colour and
    drawing shape (which no simulation reads: the inertia, contacts and names are their own,
    and are kept). A recorded run is drawn on a creature whose fingerprint this is (its
    recolouring or reshaping changes no motion); a change of anything else refuses it."""
    plain = Shape("none", ())
    return creature_fingerprint(
        replace(model, bodies=tuple(replace(b, shape=plain, color=None) for b in model.bodies))
    )


def controller_fingerprint(model: Model, controller: Controller) -> str:
    """A hash of what a control module depends on: the controller, the legs and actuators it drives."""
    return _digest(
        {
            "model": model_fingerprint(model),
            "legs": _clean(model.legs),
            "actuators": _clean(model.actuators),
            "controller": {
                k: v for k, v in _clean(controller).items() if k not in ("paths", "own")
            },
        }
    )
