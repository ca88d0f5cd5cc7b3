"""Export a checked model as MJCF (MuJoCo) or URDF, and write files atomically.

The formats themselves live in ``export_mjcf`` and ``export_urdf``; this
module picks one and writes its text so that a reader never sees a partial
file: the text goes to a temporary file beside the target, which is then
renamed over it.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from legdsl.export.mjcf import model_to_mjcf
from legdsl.export.urdf import model_to_urdf
from legdsl.files import write_atomic
from legdsl.ir.model import Model

__all__ = ["FORMATS", "default_path", "export_notes", "export_text", "write_atomic"]

FORMATS: dict[str, tuple[Callable[[Model], str], str]] = {
    "mjcf": (model_to_mjcf, ".xml"),
    "urdf": (model_to_urdf, ".urdf"),
}


def export_text(
    model: Model, fmt: str, base: str = "world", link_mass: float = 0.0, pads: bool = True
) -> str:
    """The text of ``model`` in format ``fmt`` ("mjcf" or "urdf"); URDF takes ``base`` and
    ``link_mass`` (``legdsl.export.urdf``), MJCF ``pads`` (``legdsl.export.mjpads``)."""
    if fmt not in FORMATS:
        raise ValueError(f"unknown export format {fmt!r}; use one of {', '.join(FORMATS)}")
    if fmt == "urdf":
        return model_to_urdf(model, base, link_mass)
    return model_to_mjcf(model, pads)


def default_path(model: Model, fmt: str) -> Path:
    """``NAME.xml`` for MJCF, ``NAME.urdf`` for URDF, in the current directory."""
    return Path(model.name + FORMATS[fmt][1])


def export_notes(model: Model, fmt: str, source: str, pads: bool = True) -> list[str]:
    """What of ``model``'s ground the ``fmt`` file leaves out, one note each (said, not
    silently dropped): URDF has no ground, MuJoCo no torsion spring at a contact."""
    ground = model.ground
    if ground is None:
        return []
    notes = []
    if fmt == "urdf" and ground.terrain:
        kinds = ", ".join(sorted({t.kind for t in ground.terrain}))
        notes.append(
            f"URDF describes no ground, so the terrain of {source} ({kinds}) "
            "is not in it; --format mjcf writes the ground and its terrain"
        )
    if fmt == "mjcf" and ground.torsion is not None:
        notes.append(
            f"MuJoCo has no torsion spring at a contact: the ground's torsion spring of {source} "
            "is not in the MJCF (a foot on one contact point turns about the ground's normal freely)"
        )
    if fmt == "mjcf" and not pads:
        notes.append(
            "--no-anchor-pads: the ground's tangent spring is not in the MJCF, only its damper "
            "(as friction's solreffriction); leave the option out to keep it"
        )
    return notes
