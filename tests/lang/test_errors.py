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


def test_a_mistake_on_a_very_long_line_shows_the_line_around_its_caret() -> None:
    """A mistake on a 10 000-character line (a generated file, a line without breaks)
    printed the whole line: now 120 characters of it around the caret, cut with '...'."""
    line = "x" * 5000 + " mass 3 kgg " + "y" * 5000
    sources = {"f.leg": line + "\n"}
    for col, word in [(line.index("kgg") + 1, "kgg"), (1, "xxx"), (len(line) - 1, "yy")]:
        text = Diagnostic(Span("f.leg", 1, col, 1, col + len(word)), "m").render(sources)
        _, shown, caret = text.split("\n")
        assert len(shown) <= 4 + 3 + 120 + 3
        at = caret.index("^")
        assert shown[at : at + len(word)] == word and len(caret.strip()) == len(word)
        assert shown.strip().startswith("...") == (col > 100)
        assert shown.endswith("...") == (col < 9000)
    short = Diagnostic(Span("f.leg", 1, 3, 1, 5), "m").render({"f.leg": "ab cd ef"})
    assert short.split("\n")[1:] == ["    ab cd ef", "      ^~"]
