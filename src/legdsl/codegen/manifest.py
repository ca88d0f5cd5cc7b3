"""The files of ``generated/NAME/`` beside its modules, the same for every target: the package's
``__init__.py`` and ``SHA256SUMS``, each file's digest, which loading checks; and the path of
the ``.leg`` file their headers name.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

from legdsl.ir.model import Model

SUMS = "SHA256SUMS"  # in generated/NAME/: each file's digest, as ``sha256sum`` lists them


def source_label(path: str | Path) -> str:
    """The path to print in generated headers: relative to the working directory when it can be,
    else its last two parts (``creatures/NAME.leg``), never absolute."""
    p = Path(path)
    if p.is_absolute():
        try:
            p = p.relative_to(Path.cwd())
        except ValueError:
            p = Path(*p.parts[-2:])
    return p.as_posix()


def sha256_sums(files: tuple[tuple[str, str], ...]) -> str:
    """The listing of ``sha256sum`` for the files (name, text) as written (UTF-8): loading
    checks each file against it (``legdsl.pipeline.generated``), and so can
    ``sha256sum -c SHA256SUMS``."""
    return "".join(
        f"{hashlib.sha256(text.encode('utf-8')).hexdigest()}  {name}\n" for name, text in files
    )


def render_init(model: Model) -> str:
    """The text of ``generated/NAME/__init__.py``."""
    return (
        f'"""Generated code for the creature \'{model.name}\' (legdsl compile); do not edit."""\n'
    )
