"""Export a checked model as MJCF (MuJoCo) or URDF, and write files atomically.

The formats themselves live in ``export_mjcf`` and ``export_urdf``; this
module picks one and writes its text so that a reader never sees a partial
file: the text goes to a temporary file beside the target, which is then
renamed over it.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Callable
from pathlib import Path

from legdsl.export.mjcf import model_to_mjcf
from legdsl.export.urdf import model_to_urdf
from legdsl.ir.model import Model

FORMATS: dict[str, tuple[Callable[[Model], str], str]] = {
    "mjcf": (model_to_mjcf, ".xml"),
    "urdf": (model_to_urdf, ".urdf"),
}


def export_text(model: Model, fmt: str, base: str = "world", link_mass: float = 0.0) -> str:
    """The text of ``model`` in format ``fmt`` ("mjcf" or "urdf"); URDF takes ``base`` and
    ``link_mass`` (``legdsl.export.urdf``)."""
    if fmt not in FORMATS:
        raise ValueError(f"unknown export format {fmt!r}; use one of {', '.join(FORMATS)}")
    if fmt == "urdf":
        return model_to_urdf(model, base, link_mass)
    return FORMATS[fmt][0](model)


def default_path(model: Model, fmt: str) -> Path:
    """``NAME.xml`` for MJCF, ``NAME.urdf`` for URDF, in the current directory."""
    return Path(model.name + FORMATS[fmt][1])


def write_atomic(path: str | Path, text: str) -> None:
    """Write ``text`` to ``path`` through a temporary file and a rename (parents are created)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="\n") as f:
            f.write(text)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)  # mkstemp makes it private; give it a normal file's mode
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
