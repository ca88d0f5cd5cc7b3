"""Short real runs of the shipped creatures for the animation tests.

Each creature is run once per test session with ``legdsl run FILE --time 1
--drop 0.1`` (a passive drop) into a session directory; a test gets its own
copy of the run directory. Generated modules go to a session directory too,
seeded from the checked-in ``generated/`` when there is one, so that a
current module is not compiled again.
"""

from __future__ import annotations

import atexit
import shutil
import tempfile
from pathlib import Path

from conftest import CREATURES, ROOT
from runtime_helpers import legdsl_in_process

from legdsl.cli import main
from legdsl.export.motion import Motion, load_motion

_SESSION: Path | None = None
_RUNS: dict[tuple[str, float], Path] = {}


def session_dir() -> Path:
    global _SESSION
    if _SESSION is None:
        _SESSION = Path(tempfile.mkdtemp(prefix="legdsl-anim-"))
        atexit.register(shutil.rmtree, _SESSION, True)
        if (ROOT / "generated").is_dir():
            shutil.copytree(ROOT / "generated", _SESSION / "generated")
    return _SESSION


def generated_dir() -> Path:
    return session_dir() / "generated"


def creature_run(name: str, out: Path, duration: float = 1.0) -> Path:
    """A copy, at ``out``, of a real run of creatures/NAME.leg dropped from 0.1 m."""
    key = (name, duration)
    if key not in _RUNS:
        run = session_dir() / "runs" / f"{name}-{duration:g}"
        status = main(
            ["run", str(CREATURES / f"{name}.leg"), "--time", f"{duration:g}", "--drop", "0.1",
             "--out", str(run), "--generated", str(generated_dir())]
        )  # fmt: skip
        assert status in (0, 4), f"legdsl run {name} exited with {status}"  # 4: it fell
        _RUNS[key] = run
    shutil.copytree(_RUNS[key], out)
    return out


def creature_motion(name: str, out: Path, duration: float = 1.0, fps: float = 60.0) -> Motion:
    return load_motion(creature_run(name, out, duration), fps=fps, generated=generated_dir())


# The four animation files a test reads back: key -> (--format, extra options)
ANIMATION_FORMATS = {
    "glb": ("glb", []),
    "skin": ("glb", ["--skin"]),
    "usda": ("usda", []),
    "bvh": ("bvh", []),
}


def export_animations(run_dir: Path, stem: Path, fps: float, generated: Path) -> dict[str, Path]:
    """``legdsl export-motion`` of ``run_dir`` in each of ANIMATION_FORMATS, to STEM-KEY.FORMAT."""
    files = {}
    for key, (fmt, extra) in ANIMATION_FORMATS.items():
        out = stem.with_name(f"{stem.name}-{key}.{fmt}")
        argv = ["export-motion", str(run_dir), "--format", fmt, "-o", str(out), *extra]
        status, said = legdsl_in_process([*argv, "--fps", repr(fps), "--generated", str(generated)])
        assert status == 0, f"legdsl export-motion --format {fmt} {extra}: {said}"
        files[key] = out
    return files


def exported_into_a_pipe(run: Path, fmt: str, pipe: Path) -> tuple[int, bytes]:
    """``legdsl export-motion RUN --format FMT -o PIPE`` with a reader on the FIFO ``pipe``
    (made here): the exit status and what the reader got."""
    import os
    import threading

    os.mkfifo(pipe)
    got: list[bytes] = []
    reader = threading.Thread(target=lambda: got.append(pipe.read_bytes()))
    reader.start()
    args = ["export-motion", str(run), "--format", fmt, "-o", str(pipe)]
    code = main([*args, "--generated", str(generated_dir())])
    if code != 0:  # unblock the reader before failing
        with open(pipe, "wb"):
            pass
    reader.join(timeout=30)
    return code, got[0] if got else b""
