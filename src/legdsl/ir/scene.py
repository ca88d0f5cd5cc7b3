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
class GaitBand:
    """``gait by speed { CONTROLLER from LOW to HIGH }``: the commands (SI) it is chosen for."""

    controller: str
    low: float | None
    high: float | None
    span: Span

    def holds(self, speed: float) -> bool:
        eps = 1e-12
        return (self.low is None or speed >= self.low - eps) and (
            self.high is None or speed <= self.high + eps
        )

    def text(self, unit: str = "") -> str:
        low = f" from {self.low:g} {unit}" if self.low is not None else ""
        high = f" to {self.high:g} {unit}" if self.high is not None else ""
        return f"{self.controller}{low.rstrip()}{high.rstrip()}"


def choose_gaits(
    bands: tuple[GaitBand, ...], start: str | None, speed: float, changes: list[tuple[float, float]]
) -> tuple[str, list[tuple[float, str]], list[tuple[float, float]]]:
    """The controller a run starts with (``start``, else the first band holding ``speed``) and
    its switches ``(t, controller)`` as the speed command changes (``changes``: (t, speed)):
    the current controller is kept while its band holds the command (the hysteresis of
    overlapping bands), else the first band that holds it is taken. The third value lists the
    (t, speed) commands that no band holds (t = 0: the first)."""
    lost: list[tuple[float, float]] = []

    def pick(v: float, t: float) -> str | None:
        found = next((b.controller for b in bands if b.holds(v)), None)
        if found is None:
            lost.append((t, v))
        return found

    # a command at 0 s is the one the run starts with: it chooses the first band, as the
    # untimed one would (a switch at 0 s cannot be made)
    speed = first_command(speed, changes)
    changes = [c for c in changes if c[0] > 0.0]
    band = pick(speed, 0.0)  # with a controller line too: a first command no band holds is lost
    current = start if start is not None else band
    current = current if current is not None else bands[0].controller
    first = current
    switches: list[tuple[float, str]] = []
    for t, v in sorted(changes):
        mine = [b for b in bands if b.controller == current]
        if any(b.holds(v) for b in mine):
            continue
        new = pick(v, t)
        if new is not None and new != current:
            switches.append((t, new))
            current = new
    return first, switches, lost


def first_command(speed: float, changes: list[tuple[float, float]]) -> float:
    """The command a run starts with: the last of ``changes`` (t, speed) at 0 s, which
    replaces the value ``speed`` before it is used, else ``speed``."""
    at_start = [v for t, v in sorted(changes) if t <= 0.0]
    return at_start[-1] if at_start else speed


def starts_in_band(bands: tuple[GaitBand, ...], start: str, speed: float) -> bool:
    """Whether a band of controller ``start`` (a scene's ``controller`` line) holds the first
    command ``speed``: else it would run outside its band, against its gait table."""
    return any(b.controller == start and b.holds(speed) for b in bands)


@dataclass(frozen=True)
class Scene:
    name: str
    controller: str  # the first band's choice when the scene has bands and no controller line
    values: tuple[SceneValue, ...]
    switches: tuple[SceneSwitch, ...]
    duration: float | None
    span: Span
    bands: tuple[GaitBand, ...] = ()  # gait by INPUT { ... }
    band_input: str = ""  # the input whose command chooses among the bands
    starts_by_band: bool = False  # no 'controller' line: the first command's band starts it
