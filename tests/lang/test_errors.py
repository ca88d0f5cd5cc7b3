"""A LegError renders every mistake with its line and caret, and travels between processes."""

from __future__ import annotations

import pickle

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
