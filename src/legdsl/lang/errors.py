"""Source positions and the two kinds of error.

A ``LegError`` is the user's mistake: it carries one or more diagnostics, each
with a span into a ``.leg`` file, and the CLI prints them and exits 2.
An ``InternalError`` is ours: it is never caught by the CLI's user-error path.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field


@dataclass(frozen=True, order=True)
class Span:
    """A region of a source file; lines and columns count from 1, ``end_col`` is exclusive."""

    file: str
    line: int
    col: int
    end_line: int
    end_col: int
    # Set on the lines of a template as one instance expands them: an error there names
    # the instance, "(in instance 'fr' of template 'leg')". Not part of the position.
    within: str = field(default="", compare=False)

    def __str__(self) -> str:
        if self.line <= 0:  # the whole file (one that cannot be read, say)
            return self.file
        return f"{self.file}:{self.line}:{self.col}"


# A span for things that come from no file (built-in defaults, synthesised nodes).
NOWHERE = Span("<builtin>", 0, 0, 0, 0)


@dataclass(frozen=True)
class Diagnostic:
    span: Span
    message: str

    def render(self, sources: dict[str, str] | None = None) -> str:
        """``file:line:col: message``, then the source line and a caret under the span."""
        head = f"{self.span}: error: {self.message}"
        text = (sources or {}).get(self.span.file)
        if text is None or self.span.line <= 0:
            return head
        lines = _lines(text)
        if self.span.line > len(lines):
            return head
        # a control character is shown as '\ufffd', as an undecodable byte is: never raw
        line = lines[self.span.line - 1].rstrip("\r").expandtabs(1).translate(_CONTROLS)
        start = max(self.span.col, 1)
        if self.span.end_line == self.span.line and self.span.end_col > start:
            width = self.span.end_col - start
        else:
            width = max(len(line) - start + 1, 1)
        width = max(1, min(width, max(len(line) - start + 1, 1)))
        if len(line) > SHOWN:  # a long line is shown around the caret, cut with "..."
            left = max(0, min(start - 1 - SHOWN // 3, len(line) - SHOWN))
            prefix = "..." if left else ""
            cut = prefix + line[left : left + SHOWN]
            line = cut + ("..." if left + SHOWN < len(line) else "")
            start += len(prefix) - left
            width = min(width, len(cut) - start + 1)
        caret = " " * (start - 1) + "^" + "~" * (width - 1)
        return f"{head}\n    {line}\n    {caret}"


_CONTROLS = {c: "\ufffd" for c in (*range(0x20), *range(0x7F, 0xA0))}
SHOWN = 120  # the most of a source line an error shows


@functools.lru_cache(maxsize=16)
def _lines(text: str) -> tuple[str, ...]:
    """A source's lines, as the parser counts them (not str.splitlines); split once for all
    its diagnostics (20 000 of them in a 20 000-line file took minutes, each splitting it)."""
    return tuple(text.split("\n"))


@dataclass
class LegError(Exception):
    """One or more mistakes in the user's input, sorted by position."""

    diagnostics: list[Diagnostic]
    sources: dict[str, str] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.diagnostics = sorted(
            self.diagnostics, key=lambda d: (d.span.file, d.span.line, d.span.col, d.message)
        )
        super().__init__(self.render())

    def __reduce__(self) -> tuple[type[LegError], tuple[list[Diagnostic], dict[str, str]]]:
        # pickled as its fields (a compile's worker process sends it back), not its text
        return (LegError, (self.diagnostics, self.sources))

    @classmethod
    def at(cls, span: Span, message: str, sources: dict[str, str] | None = None) -> LegError:
        return cls([Diagnostic(span, message + span.within)], dict(sources or {}))

    def render(self) -> str:
        return "\n".join(d.render(self.sources) for d in self.diagnostics)


class UsageError(Exception):
    """A mistake on the command line (not in a .leg file): one line, exit status 2."""


class InternalError(Exception):
    """A bug in legdsl, not in the user's input."""


def thread_refused(e: BaseException) -> bool:
    """Python's "can't start new thread": the system refused a thread's stack or task (``ulimit
    -v`` or ``-u``), a shortage to tell the user, not a bug."""
    return isinstance(e, RuntimeError) and "can't start new thread" in str(e)


class Diagnostics:
    """Collects every mistake found in a pass so that all are reported at once."""

    def __init__(self, sources: dict[str, str], unknown: set[str] | None = None):
        self.sources = sources
        self.items: list[Diagnostic] = []
        # what a mistake already reported left unknown ("thigh.length": a length written
        # without its unit): a later check that needs it is quiet, not a second, false error
        self.unknown: set[str] = set() if unknown is None else unknown

    def trial(self) -> Diagnostics:
        """Fresh diagnostics for a trial pass (its mistakes dropped or replayed), knowing what
        these know is unknown."""
        return Diagnostics(self.sources, self.unknown)

    def error(self, span: Span, message: str) -> None:
        self.items.append(Diagnostic(span, message + span.within))

    def raise_if_any(self) -> None:
        if self.items:
            raise LegError(list(dict.fromkeys(self.items)), self.sources)
