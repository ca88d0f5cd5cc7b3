"""A LegError renders every mistake with its line and caret, and travels between processes."""

from __future__ import annotations

import pickle
import time

from legdsl.lang.errors import Diagnostic, LegError, Span


def test_a_leg_error_pickles_as_its_diagnostics() -> None:
    """A compile lowers controllers in worker processes; an error there comes back pickled
    (it was rebuilt from its text, and failed: 'str' object has no attribute 'span')."""
    error = LegError(
        [
            Diagnostic(Span("f.leg", 2, 3, 2, 5), "second"),
            Diagnostic(Span("f.leg", 1, 1, 1, 2), "first"),
        ],
        {"f.leg": "ab\ncdef\n"},
    )
    back = pickle.loads(pickle.dumps(error))
    assert back.diagnostics == error.diagnostics
    assert back.render() == error.render()


def test_rendering_many_mistakes_takes_time_in_proportion() -> None:
    """Each diagnostic split the whole file into lines again: 20 000 mistakes in a file of
    20 000 lines took minutes to print (about 30 s here, rendered twice); now well under 5 s."""
    text = "".join(f'  body b{i} {{ colour "#000000" }}\n' for i in range(20_000))
    error = LegError(
        [
            Diagnostic(Span("f.leg", i + 1, 15, i + 1, 21), "unknown body property")
            for i in range(20_000)
        ],
        {"f.leg": text},
    )
    start = time.perf_counter()
    rendered = error.render()
    assert time.perf_counter() - start < 5.0
    assert rendered.count("\n") == 3 * 20_000 - 1
