"""The scene IR: a whole run written in a ``.leg`` file (``scene NAME { ... }``), checked.

``legdsl run FILE --scene NAME`` runs it as the options it stands for would: ``controller``
is ``--controller``, each ``set`` a ``--set`` (``at T set`` one at time T), each
``at T switch`` a ``--switch``, ``time`` the ``--time``. Values are in SI units, each with the
dimension its name was checked against (``legdsl.check.scene``).
"""

from __future__ import annotations

from dataclasses import dataclass

from legdsl.lang.errors import Span
from legdsl.lang.units import Dim


@dataclass(frozen=True)
class SceneValue:
    """``set NAME = VALUE`` (``at`` None) or ``at T set NAME = VALUE``; NAME may be
    ``ACTUATOR.KEY``."""

    name: str
    value: float
    dim: Dim
    at: float | None
    span: Span


@dataclass(frozen=True)
class SceneSwitch:
    t: float
    controller: str
    span: Span


@dataclass(frozen=True)
class Scene:
    name: str
    controller: str
    values: tuple[SceneValue, ...]
    switches: tuple[SceneSwitch, ...]
    duration: float | None
    span: Span
