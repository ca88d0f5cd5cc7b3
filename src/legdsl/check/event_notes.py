"""Events that can never hold: a state that waits for one is never entered, and the machine
stays in the state before it for good, with no error, in every run.

An event is false in every state when a comparison's sides differ by a constant
(``trunk.z > trunk.z``, once signals are written out: ``always_zero``'s polynomials), when
it asks at once for ``touchdown(X)`` and ``liftoff(X)``, or for one difference of what it reads
to be in two ranges that do not meet (``com.z > 1 m and com.z < 0.5 m``). These are notes
from ``legdsl check`` and ``show``, not errors: the table is well-formed, and a user may be
building it up.
"""

from __future__ import annotations

import math
import operator
from collections.abc import Callable

from legdsl.check.always_zero import Poly, ZeroTest
from legdsl.ir import controller as ir
from legdsl.ir.model import Model

_COMPARE: dict[str, Callable[[float, float], bool]] = {
    "<": operator.lt, ">": operator.gt, "<=": operator.le, ">=": operator.ge,
    "==": operator.eq, "!=": operator.ne,
}  # fmt: skip
_NEGATED = {"<": ">=", ">": "<=", "<=": ">", ">=": "<", "==": "!=", "!=": "=="}
_FLIPPED = {"<": ">", ">": "<", "<=": ">=", ">=": "<="}  # both sides times a negative number


def never_entered(model: Model) -> list[str]:
    """A note for each state of each controller whose event is false in every state."""
    notes = []
    for controller in model.controllers:
        zero = ZeroTest()
        zero.signal_ir = {s.name: s.value for s in controller.signals}
        states = controller.states
        for k, state in enumerate(states):
            if _truth(state.event, zero, True) is False:
                before = states[k - 1].name
                notes.append(
                    f"{state.span}: controller {controller.name}: state {state.name}'s event "
                    f"({state.event_text}) is false whatever the creature's state, so the "
                    f"machine never leaves {before}; give it an event that can hold"
                )
    return notes


def _truth(e: ir.Expr, zero: ZeroTest, holds: bool) -> bool | None:
    """Whether ``e`` (negated unless ``holds``) is true in every state, false in every
    state, or None: it depends on the state, or this cannot tell."""
    if isinstance(e, ir.Unary) and e.op == "not":
        return _truth(e.operand, zero, not holds)
    if isinstance(e, ir.Binary) and e.op in ("and", "or"):
        conjunction = (e.op == "and") == holds  # not (a or b) is (not a) and (not b)
        sides = [_truth(e.left, zero, holds), _truth(e.right, zero, holds)]
        if conjunction:
            if False in sides or not _can_meet(_conjuncts(e, holds), zero):
                return False
            return True if sides == [True, True] else None
        if True in sides:
            return True
        return False if sides == [False, False] else None
    if isinstance(e, ir.Binary) and e.op in _COMPARE:
        op = e.op if holds else _NEGATED[e.op]
        difference = _difference(e, zero)
        if difference is None or set(difference) - {()}:
            return None
        return _COMPARE[op](difference.get((), 0.0), 0.0)
    return None


def _difference(e: ir.Binary, zero: ZeroTest) -> Poly | None:
    """``left - right`` of a comparison as a polynomial in what it reads (None: unknown)."""
    return zero.poly(ir.Binary("-", e.left, e.right, e.left.type))


def _conjuncts(e: ir.Expr, holds: bool) -> list[tuple[ir.Expr, bool]]:
    """The terms of a conjunction (``a and b``, or ``not (a or b)``), each with whether it
    holds or its negation does."""
    if isinstance(e, ir.Unary) and e.op == "not":
        return _conjuncts(e.operand, not holds)
    if isinstance(e, ir.Binary) and (e.op, holds) in (("and", True), ("or", False)):
        return _conjuncts(e.left, holds) + _conjuncts(e.right, holds)
    return [(e, holds)]


def _can_meet(terms: list[tuple[ir.Expr, bool]], zero: ZeroTest) -> bool:
    """False when the terms ask for touchdown(X) and liftoff(X) at once, or for one
    difference (what a comparison reads, less its constant) in ranges that do not meet."""
    touching: dict[object, bool] = {}
    ranges: dict[tuple[object, ...], list[float]] = {}  # [low, high, low open, high open]
    for e, holds in terms:
        if isinstance(e, ir.Event):
            down = (e.kind == "touchdown") == holds
            if touching.setdefault(e.thing, down) != down:
                return False
        elif isinstance(e, ir.Binary) and e.op in _COMPARE and e.op not in ("==", "!="):
            difference = _difference(e, zero)
            if difference is None or not set(difference) - {()}:
                continue
            # difference = part + c: the comparison bounds part against -c, part scaled so
            # that its first coefficient is 1 (x > 1 and 2 - 2 x > 0 bound one part)
            op = e.op if holds else _NEGATED[e.op]
            written = sorted((m, v) for m, v in difference.items() if m != ())
            lead = written[0][1]
            if lead < 0:
                op = _FLIPPED[op]
            part = tuple((m, v / lead) for m, v in written)
            c = difference.get((), 0.0) / lead
            low, high, low_open, high_open = ranges.setdefault(part, [-math.inf, math.inf, 1, 1])
            if op in (">", ">="):
                if -c > low or (-c == low and op == ">"):
                    low, low_open = -c, float(op == ">")
            elif -c < high or (-c == high and op == "<"):
                high, high_open = -c, float(op == "<")
            ranges[part] = [low, high, low_open, high_open]
            if low > high or (low == high and (low_open or high_open)):
                return False
    return True
