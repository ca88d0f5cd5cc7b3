"""A failing check of a randomly drawn input names the draw, the environment that reruns it
alone and the input itself, in place of a bare assertion."""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Iterator

import pytest


@contextlib.contextmanager
def told_with_seed(what: str, rerun: str, shown: Callable[[], str]) -> Iterator[None]:
    """``what`` (the draw and its seed), ``rerun`` (the variables that repeat it) and the input
    ``shown`` (made only on failure) added to any failure inside; a skip or Ctrl-C passes."""
    try:
        yield
    except BaseException as e:
        if isinstance(e, KeyboardInterrupt | pytest.skip.Exception):
            raise
        raise AssertionError(f"{what} ({rerun}): {type(e).__name__}: {e}\n{shown()}") from e
