"""Straight-line programs: the body of one generated function, built step by step.

The symbolic algorithms do their arithmetic on sympy expressions. After each
step they pass every result through ``Block.let``, which keeps numbers and
plain symbols inline and names anything bigger with a fresh temporary (or
reuses the temporary of an identical expression). Expressions therefore stay
small, constants stay folded, and the code grows linearly with the link tree.

``Block.finish`` then drops every assignment that no output needs, runs
sympy's ``cse`` over what is left, and numbers the temporaries ``t1, t2, ...``
in the order they are assigned, so the result does not depend on how many
temporaries were made and thrown away, nor on the hash seed. After that it
only drops assignments and chooses printed names (``Program``): a value
assigned twice is assigned once, the base of an unrolled power such as
``min(a, b)**2`` gets a temporary, and the outputs get names such as
``toe_x``. The sympy names stay, so that no sum or product changes order.
"""

from __future__ import annotations

import keyword
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass, field

import sympy
from sympy import Expr, Float, Integer, Rational, Symbol


def num(value: float) -> Expr:
    """A model number as a sympy constant; whole numbers become exact so that 0 and 1 fold."""
    if value == int(value) and abs(value) < 2**53:
        return Integer(int(value))
    return Float(value)


def fold(expr: Expr) -> Expr:
    """Whole-valued floats that arithmetic produced (1.0, -2.0) become exact integers, fractions floats."""
    expr = sympy.sympify(expr)
    # (float(f), not f: sympy's Float(1.0) == 1 is False)
    numbers = {f: Integer(int(f)) for f in expr.atoms(Float) if float(f).is_integer()}
    # fractions such as 1/2 print and run as floats
    numbers |= {r: Float(r) for r in expr.atoms(Rational) if not r.is_Integer}
    return substituted(expr, numbers) if numbers else expr


def substituted(
    expr: sympy.Basic,
    subs: Mapping[sympy.Basic, sympy.Basic],
    memo: dict[sympy.Basic, sympy.Basic] | None = None,
) -> sympy.Basic:
    """``expr.xreplace(subs)`` for a ``subs`` that changes no value (symbols renamed one to
    one, a float by the equal integer), without evaluating each ``Min`` and ``Max`` again.
    They were evaluated when built, and such a substitution lets none of them drop an argument,
    but sympy's search for one compares every pair of their arguments (seconds, on a foot
    placement). Their arguments still go in sympy's canonical order, so the result is
    ``xreplace``'s. ``memo`` carries the work done over several calls."""
    if expr in subs:
        return subs[expr]
    if not expr.args:
        return expr
    memo = {} if memo is None else memo
    done = memo.get(expr)
    if done is not None:
        return done
    args = tuple(substituted(a, subs, memo) for a in expr.args)
    if args == expr.args:
        out = expr
    elif isinstance(expr, sympy.Min | sympy.Max):
        out = expr.func(*args, evaluate=False)
    else:
        out = expr.func(*args)
    memo[expr] = out
    return out


# Powers of a name up to this exponent print as products (x*x*x).
UNROLLED_POWER = 4


def is_unrolled_power(expr: Expr) -> bool:
    """``x**2`` ... ``x**4`` and ``x**-2`` ... ``x**-4``: printed as products of the base."""
    return bool(expr.is_Pow and expr.exp.is_Integer and 1 < abs(int(expr.exp)) <= UNROLLED_POWER)


def is_cheap(expr: Expr) -> bool:
    """Numbers, symbols and ``number * symbol`` are cheaper inline than as a temporary."""
    if expr.is_Atom:
        return True
    return bool(
        expr.is_Mul and len(expr.args) == 2 and expr.args[0].is_Number and expr.args[1].is_Symbol
    )


@dataclass(frozen=True)
class Unpack:
    """``target = array[index]``: an input coordinate under its own name."""

    target: Symbol
    array: str
    index: int


@dataclass(frozen=True)
class Assign:
    target: Symbol
    value: Expr


@dataclass(frozen=True)
class Comment:
    text: str


Statement = Unpack | Assign | Comment

# The arrays a generated function unpacks, in the order it unpacks them.
ARRAYS = ("q", "v", "tau", "s", "u", "p", "r")  # dynamics inputs, then control inputs

# Temporaries are named with this mark until they are numbered: no identifier contains it.
TEMPORARY = "#"


def is_temporary(sym: Symbol) -> bool:
    return bool(sym.name.startswith(TEMPORARY))


def python_name(wanted: str, taken: set[str]) -> str:
    """``wanted`` if it is a free Python identifier, else ``wanted_``, ``wanted_2``, ..."""
    name = wanted + "_" if keyword.iskeyword(wanted) else wanted
    base, n = name, 1
    while name in taken:
        n += 1
        name = f"{base}_{n}"
    taken.add(name)
    return name


@dataclass(frozen=True)
class Program:
    """A finished function body: statements, and the outputs in terms of their targets.

    Every symbol keeps its canonical name (``t1, t2, ...`` as numbered before
    repeated values are merged, bases named and outputs named): sympy orders the
    terms of a sum or product by symbol name, so these names fix the order in
    which the printed code adds and multiplies, and so every rounding. ``names``
    says what a symbol prints as instead. ``bases`` names the base of a power the
    printer unrolls (``b = min(x, y)``, then ``b*b``).
    """

    statements: tuple[Statement, ...]
    outputs: tuple[Expr, ...]
    names: Mapping[Symbol, str] = field(default_factory=dict)
    bases: Mapping[Expr, Symbol] = field(default_factory=dict)

    def name(self, sym: Symbol) -> str:
        return self.names.get(sym, sym.name)


class Block:
    """Collects the statements of one function. Names in ``reserved`` are never used for locals."""

    def __init__(self, reserved: Iterable[str] = ()):
        self._taken = set(reserved)
        self._inputs: dict[Symbol, Unpack] = {}
        self._statements: list[Assign | Comment] = []
        self._known: dict[Expr, Symbol] = {}
        self._count = 0

    def input(self, wanted: str, array: str, index: int) -> Symbol:
        """A local that unpacks ``array[index]``; only unpacked if some output needs it."""
        for sym, unpack in self._inputs.items():
            if (unpack.array, unpack.index) == (array, index):
                return sym
        sym = Symbol(python_name(wanted, self._taken))
        self._inputs[sym] = Unpack(sym, array, index)
        return sym

    def define(self, wanted: str, expr: Expr) -> Expr:
        """Like ``let``, but under a chosen name such as ``c_hip`` (if the value is new)."""
        expr = fold(expr)
        if is_cheap(expr):
            return expr
        if expr in self._known:
            return self._known[expr]
        sym = Symbol(python_name(wanted, self._taken))
        self._statements.append(Assign(sym, expr))
        self._known[expr] = sym
        return sym

    def let(self, expr: Expr) -> Expr:
        """The value of ``expr`` as something cheap to use again: itself or a temporary."""
        expr = fold(expr)
        if is_cheap(expr):
            return expr
        known = self._known.get(expr)
        if known is not None:
            return known
        sym = self._temporary()  # numbered t1, t2, ... in finish()
        self._statements.append(Assign(sym, expr))
        self._known[expr] = sym
        return sym

    def _temporary(self) -> Symbol:
        self._count += 1
        return Symbol(f"{TEMPORARY}{self._count}")

    def note(self, text: str) -> None:
        """A comment before the statements that follow (dropped if all of them are dead)."""
        self._statements.append(Comment(text))

    def finish(
        self,
        outputs: Iterable[Expr],
        cse: bool = True,
        names: Iterable[str | None] | None = None,
    ) -> Program:
        """The program computing ``outputs``; ``names`` (one per output, or None) names them.

        Dead code goes, sympy's ``cse`` runs, trivial temporaries go back inline,
        and the temporaries are numbered ``t1, t2, ...``. Then an assignment of a
        value already assigned is dropped (its target prints as the first one),
        the non-trivial base of a small integer power gets a temporary of its own,
        and an output that is a temporary or a bigger expression is assigned to
        its name from ``names``. The last three only rename and drop: see
        ``Program``. Finally the temporaries left print as ``t1, t2, ...`` again.
        """
        outs = [fold(o) for o in outputs]
        live = _drop_dead(self._statements, outs)
        if cse:
            live = _common_subexpressions(live)
        live, outs = _inline_cheap(live, outs)
        body, outs, temporaries = self._number(live, outs)
        body, alias = _merge_repeats(body)
        body, bases = self._name_bases(body, outs, alias)
        display: dict[Symbol, str] = {}
        if names is not None:
            body, outs = self._name_outputs(body, outs, list(names), display, temporaries, alias)
        n = 0
        for st in body:
            if (
                isinstance(st, Assign)
                and st.target not in display
                and (st.target in temporaries or is_temporary(st.target))
            ):
                n += 1
                while f"t{n}" in self._taken:
                    n += 1
                display[st.target] = f"t{n}"
        for sym, target in alias.items():
            display[sym] = display.get(target, target.name)
        unpacks = self._unpacks([*(s.value for s in body if isinstance(s, Assign)), *outs])
        return Program((*unpacks, *_drop_empty_headings(body)), tuple(outs), display, bases)

    def _number(
        self, body: list[Assign | Comment], outputs: list[Expr]
    ) -> tuple[list[Assign | Comment], list[Expr], set[Symbol]]:
        """Temporaries named ``t1, t2, ...`` in order (the names that order their terms)."""
        rename: dict[Symbol, Symbol] = {}
        n = 0
        for st in body:
            if isinstance(st, Assign) and is_temporary(st.target):
                n += 1
                while f"t{n}" in self._taken:
                    n += 1
                rename[st.target] = Symbol(f"t{n}")
        memo: dict[sympy.Basic, sympy.Basic] = {}
        statements = [
            Assign(rename.get(st.target, st.target), substituted(st.value, rename, memo))
            if isinstance(st, Assign)
            else st
            for st in body
        ]
        outputs = [substituted(o, rename, memo) for o in outputs]
        return statements, outputs, set(rename.values())

    def _unpacks(self, exprs: list[Expr]) -> list[Unpack]:
        needed = _symbols_of(exprs)
        unpacks = [u for s, u in self._inputs.items() if s in needed]
        unpacks.sort(key=lambda u: (ARRAYS.index(u.array), u.index))
        return unpacks

    def _name_bases(
        self, body: list[Assign | Comment], outputs: list[Expr], alias: dict[Symbol, Symbol]
    ) -> tuple[list[Assign | Comment], dict[Expr, Symbol]]:
        """A temporary for the base of every unrolled power of something bigger than a name.

        The printer writes ``x**2`` as ``x*x``; the base of ``min(a, b)**2`` is assigned
        first (or found among the values already assigned), so that it is evaluated once.
        """
        bases: dict[Expr, Symbol] = {}
        known: dict[Expr, Assign] = {}  # the values assigned so far
        out: list[Assign | Comment] = []

        def same(base: Expr, earlier: Assign) -> bool:
            return base == earlier.value or (
                evaluation_order(base, alias) == evaluation_order(earlier.value, alias)
            )

        def name_bases(expr: Expr) -> None:
            for sub in sympy.postorder_traversal(expr):
                if is_unrolled_power(sub) and not sub.base.is_Atom and sub.base not in bases:
                    earlier = known.get(sub.base.xreplace(alias))
                    if earlier is None or not same(sub.base, earlier):
                        earlier = Assign(self._temporary(), sub.base)
                        out.append(earlier)
                        known.setdefault(sub.base.xreplace(alias), earlier)
                    bases[sub.base] = earlier.target

        for st in body:
            if isinstance(st, Assign):
                name_bases(st.value)
                known.setdefault(st.value.xreplace(alias), st)
            out.append(st)
        for o in outputs:
            name_bases(o)
        return out, bases

    def _name_outputs(
        self,
        body: list[Assign | Comment],
        outputs: list[Expr],
        names: list[str | None],
        display: dict[Symbol, str],
        temporaries: set[Symbol],
        alias: dict[Symbol, Symbol],
    ) -> tuple[list[Assign | Comment], list[Expr]]:
        """Outputs that are temporaries print under their names; bigger ones are assigned."""
        assigned: dict[Expr, Symbol] = {}
        tail: list[Assign | Comment] = []
        outs: list[Expr] = []
        for value, wanted in zip(outputs, names, strict=True):
            value = alias.get(value, value) if value.is_Symbol else value
            if wanted is None or value in display:
                pass
            elif value in temporaries:
                display[value] = python_name(wanted, self._taken)
            elif not is_cheap(value):
                if value not in assigned:
                    assigned[value] = self._temporary()
                    display[assigned[value]] = python_name(wanted, self._taken)
                    tail.append(Assign(assigned[value], value))
                value = assigned[value]
            outs.append(value)
        return body + tail, outs


def _drop_empty_headings(body: list[Assign | Comment]) -> list[Assign | Comment]:
    """Comments that no assignment follows (before the next comment) head nothing."""
    return [
        st
        for k, st in enumerate(body)
        if isinstance(st, Assign) or (k + 1 < len(body) and isinstance(body[k + 1], Assign))
    ]


def _symbols_of(exprs: Iterable[Expr]) -> set[Symbol]:
    out: set[Symbol] = set()
    for e in exprs:
        out |= e.free_symbols
    return out


def _drop_dead(statements: list[Assign | Comment], outputs: list[Expr]) -> list[Assign | Comment]:
    """Keep the assignments some output depends on, and the comments heading kept ones."""
    needed = _symbols_of(outputs)
    kept: list[Assign | Comment] = []
    heading_used = False
    for st in reversed(statements):
        if isinstance(st, Assign):
            if st.target in needed:
                needed |= st.value.free_symbols
                kept.append(st)
                heading_used = True
        elif heading_used:
            kept.append(st)
            heading_used = False
    kept.reverse()
    return kept


def _merge_repeats(
    body: list[Assign | Comment],
) -> tuple[list[Assign | Comment], dict[Symbol, Symbol]]:
    """Drop an assignment whose value an earlier one already computes; say which it repeats.

    ``let`` reuses the temporary of an identical expression, but two values can
    become identical later, once ``cse`` and ``_inline_cheap`` have rewritten them
    (and then so can the values computed from them). The values keep their
    symbols, so their terms keep their order: see ``Program``. A value computed
    from a merged one is merged in turn only if it adds and multiplies in the
    same order as the value it repeats, so that both round alike.
    """
    alias: dict[Symbol, Symbol] = {}
    first: dict[Expr, Assign] = {}
    out: list[Assign | Comment] = []
    for st in body:
        if isinstance(st, Assign):
            value = st.value.xreplace(alias) if alias else st.value
            earlier = first.get(value)
            if earlier is not None and (
                st.value == earlier.value
                or evaluation_order(st.value, alias) == evaluation_order(earlier.value, alias)
            ):
                alias[st.target] = earlier.target
                continue
            first.setdefault(value, st)
        out.append(st)
    return out, alias


def evaluation_order(expr: Expr, alias: Mapping[Symbol, Symbol]) -> object:
    """The tree the printer walks: sums and products in the order they are printed in."""
    if expr.is_Symbol:
        return alias.get(expr, expr).name
    if expr.is_Atom:
        return (type(expr).__name__, str(expr))
    if expr.is_Add:
        args = expr.as_ordered_terms()
    elif expr.is_Mul:
        args = expr.as_ordered_factors()
    else:
        args = list(expr.args)
    return (type(expr).__name__, tuple(evaluation_order(a, alias) for a in args))


def _inline_cheap(
    body: list[Assign | Comment], outputs: list[Expr]
) -> tuple[list[Assign | Comment], list[Expr]]:
    """Put temporaries whose value is just ``-t3`` or ``2*x`` back where they are used."""
    inline: dict[Symbol, Expr] = {}
    out: list[Assign | Comment] = []
    for st in body:
        if isinstance(st, Assign):
            value = fold(st.value.xreplace(inline)) if inline else st.value
            if is_cheap(value) and is_temporary(st.target):
                inline[st.target] = value
                continue
            st = Assign(st.target, value)
        out.append(st)
    return out, [fold(o.xreplace(inline)) for o in outputs]


def _cse_names() -> Iterator[Symbol]:
    n = 0
    while True:
        n += 1
        yield Symbol(f"{TEMPORARY}cse{n}")


def _common_subexpressions(body: list[Assign | Comment]) -> list[Assign | Comment]:
    """sympy's cse across the whole body; each shared piece is assigned just before its first use."""
    where = [i for i, st in enumerate(body) if isinstance(st, Assign)]
    targets = {i: st.target for i, st in enumerate(body) if isinstance(st, Assign)}
    if not where:
        return body
    shared, reduced = sympy.cse(
        [st.value for st in body if isinstance(st, Assign)],
        symbols=_cse_names(),
        order="none",
        list=True,
    )
    if not shared:
        return body
    # Pieces such as -x cost more as a line of their own than inline: put them back.
    inline: dict[Symbol, Expr] = {}
    kept: list[tuple[Symbol, Expr]] = []
    for sym, expr in shared:
        expr = expr.xreplace(inline)
        if is_cheap(expr):
            inline[sym] = expr
        else:
            kept.append((sym, expr))
    # (putting pieces back gives what cse was given, so no Min or Max simplifies further)
    value_at = {i: fold(substituted(v, inline)) for i, v in zip(where, reduced, strict=True)}
    # A piece that is the whole value of an assignment takes that assignment's name.
    pieces_named = {s for s, _ in kept}
    alias: dict[Symbol, Symbol] = {}
    for i, v in value_at.items():
        if v in pieces_named:
            alias.setdefault(v, targets[i])
    pieces = [(alias.get(s, s), fold(e.xreplace(alias))) for s, e in kept]
    value_at = {i: v.xreplace(alias) for i, v in value_at.items()}
    # Where each piece is first needed: directly, or through a later piece that uses it.
    first_use = {s: len(body) for s, _ in pieces}
    for i in reversed(where):
        for s in value_at[i].free_symbols & first_use.keys():
            first_use[s] = i
    for s, e in reversed(pieces):
        for used in e.free_symbols & first_use.keys():
            first_use[used] = min(first_use[used], first_use[s])
    # grouped by where each goes first (a scan of every piece at every line was quadratic)
    pieces_at: dict[int, list[Assign]] = {}
    for s, e in pieces:
        pieces_at.setdefault(first_use[s], []).append(Assign(s, e))
    out: list[Assign | Comment] = []
    for i, st in enumerate(body):
        if isinstance(st, Comment):
            out.append(st)
            continue
        out += pieces_at.get(i, [])
        if value_at[i] != st.target:  # not already assigned as a piece
            out.append(Assign(st.target, value_at[i]))
    return out
