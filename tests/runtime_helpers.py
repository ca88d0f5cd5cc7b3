"""Helpers for runtime tests: a .leg text compiled into a temporary generated tree and run through
the run session (``legdsl.pipeline.session``), as ``legdsl run`` does."""

from __future__ import annotations

from pathlib import Path

from legdsl.pipeline.session import RunSession
from legdsl.sim.simulate import RunOptions, RunResult

_CACHE: dict[str, RunSession] = {}


def compile_text(text: str, tmp: Path, name: str) -> RunSession:
    """A session on ``text`` (cached per text, so a module compiles once per test session)."""
    if text in _CACHE:
        return _CACHE[text]
    tmp.mkdir(parents=True, exist_ok=True)
    source = tmp / f"{name}.leg"
    source.write_text(text)
    _CACHE[text] = RunSession.from_file(source, generated=tmp / "generated")
    return _CACHE[text]


def run(session: RunSession, **options: object) -> RunResult:
    """A passive run (no controller) with these ``RunOptions``."""
    return session.run(options=RunOptions(**options)).result  # type: ignore[arg-type]
