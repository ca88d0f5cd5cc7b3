"""The files of ``generated/NAME/`` beside its modules, the same for every target: the package's
``__init__.py`` and ``SHA256SUMS``, each file's digest, which loading checks; and the path of
the ``.leg`` file their headers name.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

from legdsl.ir.model import Model

SUMS = "SHA256SUMS"  # in generated/NAME/: each file's digest, as ``sha256sum`` lists them


def source_label(path: str | Path) -> str:
    """The path to print in generated headers: the ``.leg`` file as the compile was given it,
    relative to the working directory (``creatures/NAME.leg``), which a path given absolute is
    made too (``../../tmp/v/hopper2.leg`` from ``/usr/share``): true from there, and no
    machine's absolute path in the code. Its last parts alone (``v/hopper2.leg``) were
    relative to nothing."""
    p = Path(path)
    if p.is_absolute():
        try:
            return Path(os.path.relpath(p, Path.cwd())).as_posix()
        except ValueError:  # another drive (Windows): no relative path leads there
            return p.as_posix()
    return p.as_posix()


def shown_used(path: str | Path, source: str) -> str:
    """A used ``.leg`` file (absolute ``path``) as the generated code names it, beside the
    compiled file shown as ``source`` (``source_label``'s): from that file's folder when it
    lies under it (``creatures/lib/gaits.leg``), else relative to the working directory as
    the header's is (``../shared/gaits.leg``). Its bare name was shown for the latter, which
    named no folder."""
    file = Path(path)
    home = Path(source).resolve().parent
    if file.is_relative_to(home):
        return (Path(source).parent / file.relative_to(home)).as_posix()
    return source_label(file.resolve())


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
