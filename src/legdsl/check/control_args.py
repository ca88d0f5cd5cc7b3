"""Which argument of an action call a dimension mistake in the action's body comes from.

An action's parameters declare no dimension: the body is checked with what each call
gives. When that check fails, the body is checked again, silently, with one numeric
argument at a time given another dimension; if exactly one argument makes the body agree,
and only with certain dimensions, the mistake is that argument's and is reported at it,
named, instead of at an expression deep inside the action. When no one argument does, two
of different dimensions exchanged may (kv given for kp and kp for kv): the two are told as
swapped.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import replace
from itertools import combinations

from legdsl.check.control_names import Blame, NameResolver, Value
from legdsl.check.control_words import describe_type
from legdsl.check.plain_declared import plain_declared
from legdsl.check.values import per_second, place_of, written_unit
from legdsl.ir import controller as ir
from legdsl.ir.controller import ONE
from legdsl.lang import ast
from legdsl.lang.errors import Diagnostics, Span
from legdsl.lang.units import KINDS, Dim, describe

_ANGLE: Dim = KINDS["angle"][0]
_SHOWN = 30  # the longest argument quoted in the message
# Dimensions tried for an argument: the named kinds, each also per and times an angle
# (a rotary spring's energy is in N*m*rad, a gain may be per radian), and the argument's
# own dimension times or per each base unit.
_KIND_DIMS: tuple[Dim, ...] = tuple(dim for dim, _ in KINDS.values())


_BASES: tuple[Dim, ...] = ((1, 0, 0, 0), (0, 1, 0, 0), (0, 0, 1, 0), (0, 0, 0, 1))


def _times(a: Dim, b: Dim, sign: int = 1) -> Dim:
    return tuple(x + sign * y for x, y in zip(a, b, strict=True))  # type: ignore[return-value]


_CANDIDATES: tuple[Dim, ...] = tuple(
    dict.fromkeys(
        [
            *_KIND_DIMS,
            *(_times(d, _ANGLE, s) for d in _KIND_DIMS for s in (1, -1)),
            *(_times(ONE, b, -1) for b in _BASES),  # a gain per metre, say
        ]
    )
)


def candidates(own: Dim) -> list[Dim]:
    near = [_times(own, base, s) for base in _BASES for s in (1, -1)]
    return [d for d in dict.fromkeys([*_CANDIDATES, *near]) if d != own]


class ArgumentProbe(NameResolver):
    """Mixin state and helpers for ``Elaborator.invoke``."""

    probing = False  # inside a probe: nested calls check their bodies plainly
    blamed = 0  # mistakes told at a call's argument (record_readers counts the others)
    error_spans: list[Span]  # where each error was found, before it is moved to a call

    @contextmanager
    def captured(self) -> Iterator[Diagnostics]:
        """Errors go to a fresh ``Diagnostics`` for the duration (replayed or dropped after)."""
        real, self.diag = self.diag, self.diag.trial()
        try:
            yield self.diag
        finally:
            self.diag = real

    def snapshot(self) -> tuple[object, ...]:
        """What a check records (record types, aliases read, signals), to be put back."""
        return (
            {k: list(v) for k, v in self.record_types.items()},
            list(self.alias_uses),
            dict(self.signal_ir),
            set(self._planar_sites),
            set(self._reported_at_call),
            self.each_count,
            self.probing,
            {k: list(v) for k, v in self.untyped_records.items()},
            {k: list(v) for k, v in self.record_uses.items()},
        )

    def restore(self, saved: tuple[object, ...]) -> None:
        (
            self.record_types,
            self.alias_uses,
            self.signal_ir,
            self._planar_sites,
            self._reported_at_call,
            self.each_count,
            self.probing,
            self.untyped_records,
            self.record_uses,
        ) = saved  # type: ignore[assignment]

    def blame(
        self, args: list[Value], check: Callable[[list[Value]], object], used_at: Span
    ) -> Blame | None:
        """The one numeric argument that, given another dimension, makes ``check`` clean."""
        found: list[Blame] = []
        for i, value in enumerate(args):
            if not isinstance(value, ir.Expr) or not isinstance(value.type, tuple):
                continue  # a leg, a body, a condition, or a bare 0 (which fits any unit)
            if not self.fits_with(args, i, None, check):
                continue  # not even a value of any unit would do: not this argument
            fits = [d for d in candidates(value.type) if self.fits_with(args, i, d, check)]
            if fits:  # a plain number last: sin() takes one, but an angle is meant
                fits.sort(key=lambda d: d == ONE)
                found.append(Blame(i, value, tuple(fits), used_at))
        if len(found) > 1:  # several would do: the one meant as a named kind (a length...)
            found = [b for b in found if any(d in _KIND_DIMS for d in b.fits)]
        if len(found) != 1:
            return self.swapped(args, check, used_at)
        return self.with_other_motion(found[0], args, check)

    def swapped(
        self, args: list[Value], check: Callable[[list[Value]], object], used_at: Span
    ) -> Blame | None:
        """The one pair of numeric arguments of different dimensions that, exchanged, make
        ``check`` clean (kv given for kp and kp for kv)."""
        numbers = [i for i, v in enumerate(args) if isinstance(v, ir.Expr) and v.type is not None]
        found: list[Blame] = []
        for i, j in combinations(numbers, 2):
            a, b = args[i], args[j]
            assert isinstance(a, ir.Expr) and isinstance(b, ir.Expr)
            if a.type == b.type or not isinstance(a.type, tuple) or not isinstance(b.type, tuple):
                continue
            trial = list(args)
            trial[i], trial[j] = retyped(a, b.type), retyped(b, a.type)
            if self.clean_with(trial, check):
                found.append(Blame(i, a, (b.type,), used_at, swapped=j))
        return found[0] if len(found) == 1 else None

    def corrected(self, given: list[Value], blame: Blame) -> None:
        """``given`` as the blame says it should be, so that the body is checked as if right."""
        given[blame.index] = retyped(blame.given, blame.fits[0])
        if blame.swapped is not None:
            other = given[blame.swapped]
            assert isinstance(other, ir.Expr) and isinstance(blame.given.type, tuple)
            given[blame.swapped] = retyped(other, blame.given.type)

    def with_other_motion(
        self, blame: Blame, args: list[Value], check: Callable[[list[Value]], object]
    ) -> Blame:
        """``blame`` with the dimensions the argument would need where it is used, were the
        actuators the call reads of the other motion (hop_apex's sweep: 1 rad for a rotary
        leg spring, 1 for a sliding one); none if that makes no difference."""
        self.motions_read = {}
        self.fits_with(args, blame.index, blame.fits[0], check)
        if len(set(self.motions_read.values())) != 1:
            return blame  # no actuator read, or both kinds: nothing to tell
        names = tuple(self.motions_read)
        rotary = self.motions_read[names[0]]
        own = blame.given.type
        assert isinstance(own, tuple)  # blame() tries numbers with a dimension only
        self.flipped_motion = frozenset(a.name for a in self.scope.model.actuators)
        try:
            other = [
                d
                for d in [own, *candidates(own)]  # as given may be right for the other
                if self.fits_with(args, blame.index, d, check, only_at=blame.used_at)
            ]
        finally:
            self.flipped_motion = frozenset()
        if not other or len(other) > 2 or set(other) == set(blame.fits):
            return blame  # the same, or the other motion spoils more than this argument
        other.sort(key=lambda d: d == ONE)
        return replace(blame, otherwise=(names, rotary, tuple(other)))

    def fits_with(
        self,
        args: list[Value],
        index: int,
        dim: Dim | None,
        check: Callable[[list[Value]], object],
        only_at: Span | None = None,
    ) -> bool:
        """Whether the call checks clean with argument ``index`` of dimension ``dim``
        (None: of any dimension); with ``only_at``, clean there."""
        trial = list(args)
        value = trial[index]
        assert isinstance(value, ir.Expr)
        trial[index] = ir.Named("opaque", "argument", None) if dim is None else retyped(value, dim)
        return self.clean_with(trial, check, only_at)

    def clean_with(
        self,
        trial: list[Value],
        check: Callable[[list[Value]], object],
        only_at: Span | None = None,
    ) -> bool:
        """Whether the call checks clean with the arguments ``trial``; with ``only_at``,
        clean there."""
        first = len(self.error_spans)
        saved = self.snapshot()
        self.probing = True
        try:
            with self.captured() as diag:
                check(trial)
        finally:
            self.restore(saved)
        if only_at is not None:
            return only_at not in self.error_spans[first:]
        return not diag.items

    def report_swap(self, s: ast.InvokeStmt, action: ast.ActionDef, blame: Blame) -> None:
        """At the two arguments: their names and places, what each is, and how the action
        uses each."""
        assert blame.swapped is not None
        i, j = blame.index, blame.swapped
        first, second = s.args[i].span, s.args[j].span
        texts = [_text(self.diag.sources, x.span) for x in (s.args[i], s.args[j])]
        a, b = (f"'{t}'" if len(t) <= _SHOWN else "it" for t in texts)
        given = [describe_type(blame.given.type), describe_type(blame.fits[0])]
        names = [action.params[i].name, action.params[j].name]
        adjacent = j == i + 1 and all(len(t) <= _SHOWN for t in texts)
        fix = f": '{texts[1]}, {texts[0]}'" if adjacent else ", each in the other's place"
        self.blamed += 1
        self.err(
            Span(first.file, first.line, first.col, second.end_line, second.end_col, first.within),
            f"arguments '{names[0]}' ({_ordinal(i + 1)}) and '{names[1]}' ({_ordinal(j + 1)}) "
            f"of action '{action.name.name}' look swapped: {a} is {given[0]} and {b} "
            f"{given[1]}, but the action uses '{names[0]}' as {given[1]} and "
            f"'{names[1]}' as {given[0]} ({place_of(blame.used_at)}); write them the other "
            f"way round{fix}",
        )

    def report_blame(self, s: ast.InvokeStmt, action: ast.ActionDef, blame: Blame) -> None:
        """At the argument: its name and place in the signature, and the dimension it needs."""
        if blame.swapped is not None:
            self.report_swap(s, action, blame)
            return
        arg = s.args[blame.index]
        told = plain_declared(self.scope.unitless, [blame.given], blame.fits[0])
        if told is not None and len(blame.fits) == 1 and blame.otherwise is None:
            self.blamed += 1
            self.err(*told)  # an input or parameter given with no unit: told where it is
            return
        text = _text(self.diag.sources, arg.span)
        needed = " or ".join(describe_type(d) for d in blame.fits)
        if blame.otherwise is not None:
            names, rotary, fits = blame.otherwise
            this, other = ("rotary", "sliding") if rotary else ("sliding", "rotary")
            one = len(names) == 1
            which = f"'{names[0]}' is" if one else "the actuators it reads are"
            needed += (
                f" since {which} {this} (were {'it' if one else 'they'} "
                f"{other}: {' or '.join(describe_type(d) for d in fits)})"
            )
        where = place_of(blame.used_at)
        self.blamed += 1
        shown = f"'{text}', " if len(text) <= _SHOWN else ""
        self.err(
            arg.span,
            f"argument '{action.params[blame.index].name}' ({_ordinal(blame.index + 1)}) of "
            f"action '{action.name.name}' is {shown}{describe_type(blame.given.type)}, but the "
            f"action uses it as {needed} ({where}){_advice(text, arg, blame.fits[0])}",
        )


def retyped(value: ir.Expr, dim: Dim) -> ir.Expr:
    """The argument with another dimension: a constant keeps its value (for the checks of
    constants), anything else becomes a name of that dimension."""
    if isinstance(value, ir.Num):
        return ir.Num(value.value, dim)
    return ir.Named("opaque", "argument", dim)


def _advice(text: str, arg: ast.Expr, dim: Dim) -> str:
    if dim == ONE:
        return "; give it no unit"
    if isinstance(arg, ast.EQuantity) and arg.quantity.unitless:
        return f": write e.g. '{text} {_unit(dim)}'"
    rate = per_second(written_unit(text), dim) if isinstance(arg, ast.EQuantity) else None
    if rate is not None:  # '20 deg' for a turn rate is '20 deg/s', not '20 rad/s'
        return f"; write e.g. '{text[: len(text) - len(written_unit(text))].strip()} {rate}'"
    return f"; write it with a unit of {describe(dim)}"


def _unit(dim: Dim) -> str:
    """A unit to write for ``dim``: the kind's own, in radians for angles (where a gain or
    a sweep of 1 is meant, 1 deg would be another number)."""
    if dim == _ANGLE:
        return "rad"
    for kind_dim, example in KINDS.values():
        if kind_dim == dim:
            return example
    symbols = zip(("kg", "m", "s", "rad"), dim, strict=True)
    return "*".join(s if p == 1 else f"{s}^{p}" for s, p in symbols if p)


def _ordinal(n: int) -> str:
    suffix = "th" if 10 <= n % 100 <= 20 else {1: "st", 2: "nd", 3: "rd"}.get(n % 10, "th")
    return f"{n}{suffix}"


def _text(sources: dict[str, str], span: Span) -> str:
    lines = sources.get(span.file, "").split("\n")
    if span.line != span.end_line or span.line > len(lines):
        return "this"
    return lines[span.line - 1][span.col - 1 : span.end_col - 1]
