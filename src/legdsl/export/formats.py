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

__all__ = ["FORMATS", "default_path", "export_text", "write_atomic"]

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
