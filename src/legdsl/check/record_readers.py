"""A record written inside an action takes the dimension its readers need.

A record's dimension is that of the values recorded into it. When an action records a
value built from a wrong-unit argument (``trim_speed(speed, 2 kg)`` integrates
``2 kg * (speed - com.vx)`` into ``speed_trim``), its body still checks clean and the
mistake would surface only where the controller reads the record (``speed + speed_trim``),
far from the call and not naming it. So when a controller has mistakes, each record
written in an action is tried with the other dimensions: if exactly one leaves only
mistakes that are told at a call's argument (control_args), the record is given it, and
the call's body, no longer agreeing with it, names the argument at fault.

A record whose writes tell no unit (a bare 0, which fits any, and records of no known unit,
itself among them) takes the one its first use gives it (``record mark = 0`` read as
``mark > 1 s``: a time), and its other uses are checked against it. One whose uses tell
none either could be compared with anything: that is an error at its first write, saying
how to give it one (a record read by nothing but its own writes, `record r = r`, has no use
to check, and needs none).
"""

from __future__ import annotations

from collections.abc import Callable

from legdsl.check.control_args import candidates
from legdsl.check.control_names import Scope
from legdsl.check.control_stmts import Elaborator
from legdsl.ir import controller as ir
from legdsl.lang import ast
from legdsl.lang.errors import Diagnostics, Span

# A checking pass over the table with the scope's records as they are: its Elaborator.
Pass = Callable[[Diagnostics], Elaborator]


def mistakes(run: Pass, sources: dict[str, str]) -> tuple[int, int]:
    """How many mistakes a pass finds that are not told at a call's argument, and how many are."""
    diag = Diagnostics(sources)
    el = run(diag)
    return len(diag.items) - el.blamed, el.blamed


def settle_by_readers(scope: Scope, run: Pass, sources: dict[str, str]) -> None:
    """Give each record written in an action the one dimension its readers need, if any:
    the one that leaves fewer mistakes, all but one more told at a call's argument."""
    base = mistakes(run, sources)
    if base[0] == 0:
        return
    for name in _written_in_actions(scope, run(Diagnostics(sources))):
        own = scope.records.get(name)
        if not isinstance(own, tuple):
            continue
        scope.records[name] = None  # of any dimension: do its readers then agree?
        if mistakes(run, sources)[0] >= base[0]:
            scope.records[name] = own
            continue
        fits = []
        for dim in candidates(own):
            scope.records[name] = dim
            left, blamed = mistakes(run, sources)
            if left < base[0] and blamed == base[1] + 1:
                fits.append((dim, (left, blamed)))
        scope.records[name] = fits[0][0] if len(fits) == 1 else own
        if len(fits) == 1:
            base = fits[0][1]
            if base[0] == 0:
                return


def _written_in_actions(scope: Scope, el: Elaborator) -> list[str]:
    """The records some ``record`` statement inside an action writes."""
    bodies = [a.span for a in scope.actions.values() if isinstance(a, ast.ActionDef)]
    return [
        name
        for name, writes in el.record_types.items()
        if any(_within(span, body) for _, span in writes for body in bodies)
    ]


def _within(span: Span, outer: Span) -> bool:
    start, end = (span.line, span.col), (span.end_line, span.end_col)
    return span.file == outer.file and (outer.line, outer.col) <= start <= end <= (
        outer.end_line,
        outer.end_col,
    )


def tell_unknown_unit(el: Elaborator, name: str) -> None:
    """The error for a record of no known unit, at its first write (or the user's call that
    leads to it); none if a write failed, its own mistake being the one to fix."""
    writes = el.untyped_records.get(name, [])
    if not writes or any(w is None for w in writes):
        return
    if el.record_reads.get(name, 0) <= el.self_reads.get(name, 0):
        return  # read only by its own writes ('record r = r'): no use to check
    first = writes[0]
    assert first is not None
    stmt, value, calls = first
    leaves = list(ir.leaves(value))
    read = dict.fromkeys(x.name for x in leaves if isinstance(x, ir.Named) and x.kind == "record")
    zero = any(isinstance(x, ir.Num) and x.type is None for x in leaves)
    parts = ["a bare 0, which fits any unit"] if zero else []
    parts += [f"'{r}' itself" if r == name else f"'{r}', of no known unit" for r in read]
    fix = (
        "write the 0 with the unit the record is meant to have, as in '0 m'"
        if zero and not calls
        else "record a value of known unit into it"
    )
    saved, el.calls = el.calls, list(calls)
    try:
        el.err(
            stmt.value.span,
            f"the unit of 'record {name}' cannot be told: what is recorded into it "
            f"({', and '.join(parts) or 'a number of any unit'}) has none, nor does any use "
            f"give it one, so its uses cannot be checked; {fix}",
        )
    finally:
        el.calls = saved
