"""Controller expressions into the typed IR, every operator and function dimension-checked.

Every name is looked up once here and becomes an IR node (``legdsl.ir.controller``) that
carries its dimension; every operator, function, comparison and assignment is checked
for dimensions. Named actions are inlined at each call, with their parameters bound to
the caller's arguments, so an action is checked with what it is given: a mistake that
only shows inside a standard-library action is reported at the user's call, with a note
naming the action's line.

Dimension rules: ``+``, ``-``, comparisons, ``min``, ``max``, ``clamp`` and the branches of
``select`` need one dimension; ``*`` and ``/`` combine them; ``x ^ n`` needs a plain
number ``n`` when ``x`` has a dimension; ``sqrt`` halves it; ``sin``, ``cos`` and ``tan``
take an angle (or a plain number); ``asin``, ``acos``, ``atan`` and ``atan2`` give an
angle; ``exp`` and ``log`` take and give plain numbers. A bare ``0`` fits any dimension,
any other bare number is dimensionless.
"""

from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Callable

from legdsl.check.control_depth import signals_used, written_too_large
from legdsl.check.control_names import (
    KIND_WORDS,
    MEMBER_EXAMPLES,
    MISMATCH,
    Mismatch,
    NameResolver,
    Opaque,
    Value,
    thing_kind,
)
from legdsl.check.control_words import describe_type, expression_text
from legdsl.check.declared_unit import declared_unit
from legdsl.check.plain_declared import plain_declared
from legdsl.check.unit_hints import mismatch_hint, sqrt_hint, want_hint
from legdsl.check.values import article, did_you_mean
from legdsl.ir import controller as ir
from legdsl.ir.controller import BOOL, ONE, Type
from legdsl.lang import ast
from legdsl.lang.errors import Span
from legdsl.lang.units import Dim, describe, out_of_range

# name -> number of arguments (None: any number, at least one)
BUILTIN_FUNCTIONS: dict[str, int | None] = {
    "sin": 1, "cos": 1, "tan": 1, "asin": 1, "acos": 1, "atan": 1, "atan2": 2,
    "sqrt": 1, "abs": 1, "exp": 1, "log": 1, "sign": 1,
    "min": None, "max": None, "clamp": 3, "select": 3,
    "liftoff": 1, "touchdown": 1, "integral": 1,
}  # fmt: skip
EVENT_FUNCTIONS = ("liftoff", "touchdown")


class ExprChecker(NameResolver):
    """Expressions: numbers, conditions and events, with their dimensions."""

    def number(self, e: ast.Expr, local: dict[str, Value]) -> ir.Expr | None:
        """An expression used as a number: a body, leg, path... is not one, its members are."""
        return self._typed(e, local, want_bool=False)

    def condition(
        self, e: ast.Expr, local: dict[str, Value], event: bool = False
    ) -> ir.Expr | None:
        return self._typed(e, local, want_bool=True, event=event)

    def _typed(
        self, e: ast.Expr, local: dict[str, Value], want_bool: bool, event: bool = False
    ) -> ir.Expr | None:
        if not self.within_expression:  # a statement's: the signals it uses resolved first
            self.within_expression = True
            try:
                for name in signals_used(e, self.scope.signals, local):
                    if name not in self._signals_open:  # a cycle: told where it is named
                        self.signal(name)
                return self._typed(e, local, want_bool, event)
            finally:
                self.within_expression = False
        value = self.expr(e, local, event)
        if value is None:
            return None
        if isinstance(value, Opaque):  # of any type, and no constant (not a zero to divide by)
            return ir.Named("opaque", value.name, None)
        if isinstance(value, ir.Legs | ir.Part | ir.Alias):
            kind = thing_kind(value)
            text, word = expression_text(e), KIND_WORDS.get(kind, kind)
            self.err(
                e.span,
                f"'{text}' is {article(word)} {word}, not a number: use one of its "
                f"members, as in '{text}.{MEMBER_EXAMPLES[kind]}'",
            )
            return None
        if want_bool and value.type != BOOL:
            text = expression_text(e)
            if isinstance(value, ir.Read) and value.member == "touching":  # 1 or 0, as the
                thing = text.removesuffix(".touching")  # paper's flags; its events say it
                events = f"touchdown({thing}) or liftoff({thing}) (or " if event else "("
                self.err(
                    e.span, f"'{text}' is 1 or 0, not a condition: write {events}{text} > 0.5)"
                )
                return None
            self.err(
                e.span,
                f"a condition is needed here, such as 'x > 0', not {describe_type(value.type)}",
            )
            return None
        if not want_bool and value.type == BOOL:
            self.err(e.span, "a condition is not a number: use select(condition, a, b)")
            return None
        return value

    def expr(self, e: ast.Expr, local: dict[str, Value], event: bool = False) -> Value | None:
        if isinstance(e, ast.EQuantity):
            q = e.quantity
            trouble = out_of_range(e.text, q.value)
            if trouble is not None:
                self.err(e.span, trouble)
                return None
            if q.unitless:
                return ir.Num(q.value, None if q.value == 0 else ONE)
            return ir.Num(q.value, q.dim)
        if isinstance(e, ast.EName):
            return self.lookup(e.ident, local)
        if isinstance(e, ast.EAttr):
            if isinstance(e.base, ast.EName):  # an unknown name is told with what it reads
                base = self.lookup(e.base.ident, local, read=e.attr.name)
            else:
                base = self.expr(e.base, local)
            return None if base is None else self.member(base, e.attr)
        if isinstance(e, ast.EUnary):
            if e.op == "not":
                operand = self.condition(e.operand, local, event)
                return None if operand is None else ir.Unary("not", operand, BOOL)
            operand = self.number(e.operand, local)
            return None if operand is None else ir.Unary("-", operand, operand.type)
        if isinstance(e, ast.EBinary):
            return self.valued(e, self.binary(e, local, event))
        return self.valued(e, self.call(e, local, event))

    def valued(self, e: ast.Expr, node: ir.Expr | None) -> ir.Expr | None:
        """``node``, unless it is made of constants only and has no finite real value
        (``2 ^ 2000``, ``sqrt(-1)``): then an error, for the generated code would compute
        NaN, an infinity or a complex number there."""
        if node is None:
            return None
        too_large = written_too_large(node, self._depths, self._sizes, self.signal_ir)
        if too_large is not None:
            self.err(e.span, too_large)
            return None
        try:
            self.constant_value(node)
        except NoValue as why:
            self.err(e.span, str(why))
            return None
        return node

    def constant_value(self, e: ir.Expr) -> float | None:
        """The value of an expression of numbers, the model's constants, pi, g and the total
        mass; None for one that reads anything else. Raises ``NoValue``.

        Remembered per node (kept, so that its id is not reused): each expression is asked
        again as part of every larger one built on it."""
        known = self._constants.get(id(e))
        if known is None:
            known = self._constants[id(e)] = (e, self._constant_value(e))
        return known[1]

    def _constant_value(self, e: ir.Expr) -> float | None:
        if isinstance(e, ir.Num):
            return e.value
        if isinstance(e, ir.Named):
            if e.kind == "builtin" and e.name == "total_mass":
                return self.scope.model.total_mass
            builtins = {"pi": math.pi, "g": -self.scope.model.gravity[2]}
            return builtins.get(e.name) if e.kind == "builtin" else None
        if isinstance(e, ir.Unary) and e.op == "-":
            v = self.constant_value(e.operand)
            return None if v is None else -v
        if isinstance(e, ir.Binary) and e.op in _ARITHMETIC:
            a, b = self.constant_value(e.left), self.constant_value(e.right)
            if a is None or b is None:
                return None
            return _finite(lambda: _ARITHMETIC[e.op](a, b), e.op)
        if isinstance(e, ir.Call) and e.func in ir.FUNCTION_VALUES:
            args = [self.constant_value(a) for a in e.args]
            if any(a is None for a in args):
                return None
            return _finite(lambda: ir.FUNCTION_VALUES[e.func](*args), e.func)
        return None

    def binary(self, e: ast.EBinary, local: dict[str, Value], event: bool) -> ir.Expr | None:
        if e.op in ("and", "or"):
            left, right = (
                self.condition(e.left, local, event),
                self.condition(e.right, local, event),
            )
            return None if left is None or right is None else ir.Binary(e.op, left, right, BOOL)
        left, right = self.number(e.left, local), self.number(e.right, local)
        if left is None or right is None:
            return None
        if e.op == "/" and (
            zero := self.zeros.divisor(right, self.constant_value(right), self.signal_ir)
        ):
            self.err(e.right.span, f"division by zero: {zero}")
            return None
        if e.op in ("*", "/"):
            sign = 1 if e.op == "*" else -1
            return ir.Binary(e.op, left, right, _combine(left.type, right.type, sign))
        if e.op == "^":
            return self.power(e, left, right)
        same = self.same([left, right], [e.left, e.right], f"both sides of '{e.op}'")
        if isinstance(same, Mismatch):
            return None
        comparison = e.op in ("<", ">", "<=", ">=", "==", "!=")
        return ir.Binary(e.op, left, right, BOOL if comparison else same)

    def power(self, e: ast.EBinary, base: ir.Expr, exponent: ir.Expr) -> ir.Expr | None:
        if exponent.type not in (ONE, None):
            self.err(
                e.right.span, f"an exponent is a plain number, not {describe_type(exponent.type)}"
            )
            return None
        if base.type in (ONE, None):
            return ir.Binary("^", base, exponent, base.type)
        try:
            n = self.constant_value(exponent)
        except NoValue:  # (its own error is given where it is checked as a value)
            n = None
        assert isinstance(base.type, tuple)
        powered = None if n is None else tuple(d * n for d in base.type)
        if powered is None or any(abs(p - round(p)) > 1e-12 for p in powered):
            self.err(
                e.right.span,
                f"{describe_type(base.type)} can be raised only to a constant power that leaves whole "
                "powers of its units (as in 'x ^ 2')",
            )
            return None
        dim = tuple(round(p) for p in powered)
        return ir.Binary("^", base, exponent, (dim[0], dim[1], dim[2], dim[3]))

    def same(self, values: list[ir.Expr], exprs: list[ast.Expr], what: str) -> Type | Mismatch:
        """The one dimension of ``values`` (None if all fit any); False after an error."""
        found: Type = None
        for value in values:
            if value.type is None:
                continue
            if found is None:
                found = value.type
            elif value.type != found:
                if (told := plain_declared(self.scope.unitless, values)) is not None:
                    self.err(*told)  # the unit left out where it is declared
                    return MISMATCH
                spans = [x.span for x in exprs]
                span = Span(
                    spans[0].file,
                    spans[0].line,
                    spans[0].col,
                    spans[-1].end_line,
                    spans[-1].end_col,
                    spans[0].within,  # a shared part's line: whose controller it is
                )
                dims = " and ".join(
                    dict.fromkeys(describe_type(v.type) for v in values if v.type is not None)
                )
                if told := declared_unit(self.scope.declared, values, span, what, None, exprs):
                    self.err(*told)  # one input or parameter declared in another unit
                    return MISMATCH
                hint = gram_for_gravity(exprs) or mismatch_hint(values, exprs)
                self.err(span, f"{what} must have one dimension, but they are {dims}{hint}")
                return MISMATCH
        for value in values:
            self.record_use(value, found)
        return found

    def record_use(self, value: ir.Expr, dim: Type) -> None:
        """A record of no known unit yet (its writes are bare 0s, itself...) used where
        ``dim`` is needed: a unit it may take (``controller.elaborate``)."""
        while isinstance(value, ir.Unary) or (isinstance(value, ir.Call) and value.func == "abs"):
            value = value.operand if isinstance(value, ir.Unary) else value.args[0]
        unknown = isinstance(value, ir.Named) and value.kind == "record" and value.type is None
        if unknown and isinstance(value, ir.Named) and isinstance(dim, tuple):
            self.record_uses.setdefault(value.name, []).append(dim)

    def call(self, e: ast.ECall, local: dict[str, Value], event: bool) -> ir.Expr | None:
        name = e.func.name
        if name not in BUILTIN_FUNCTIONS:
            hint = (
                " (actions are statements, not values)"
                if name in self.scope.actions
                else did_you_mean(name, BUILTIN_FUNCTIONS)
            )
            if name in self.scope.names or name in self.scope.signals or name in local:
                value = "a built-in value" if name in ir.BUILTIN_VALUES else "a value"
                hint = f": '{name}' is {value}, not a function; to multiply by it, write '{name} * (...)'"
            self.err(e.func.span, f"unknown function '{name}'{hint}")
            return None
        arity = BUILTIN_FUNCTIONS[name]
        if (arity is not None and len(e.args) != arity) or (arity is None and not e.args):
            self.err(
                e.span,
                f"{name}() takes {arity if arity is not None else 'one or more'} argument(s), got {len(e.args)}",
            )
            return None
        if name in EVENT_FUNCTIONS:
            return self.event(e, local, event)
        if name == "integral":
            return self.integral(e, local)
        if name == "select":
            cond = self.condition(e.args[0], local, event)
            branches = [self.number(a, local) for a in e.args[1:]]
            if cond is None or branches[0] is None or branches[1] is None:
                return None
            same = self.same(
                [branches[0], branches[1]], list(e.args[1:]), "both branches of select()"
            )
            return (
                None
                if isinstance(same, Mismatch)
                else ir.Call(name, (cond, branches[0], branches[1]), same)
            )
        args = [self.number(a, local) for a in e.args]
        if any(a is None for a in args):
            return None
        checked = [a for a in args if a is not None]
        result = _FUNCTION_RULES[name](self, e, checked)
        return None if isinstance(result, Mismatch) else ir.Call(name, tuple(checked), result)

    def event(self, e: ast.ECall, local: dict[str, Value], event: bool) -> ir.Expr | None:
        name = e.func.name
        if not event:
            self.err(e.func.span, f"{name}() is an event: it belongs after 'on' in a table row")
            return None
        arg = e.args[0]
        if isinstance(arg, ast.EName) and self.lookup(arg.ident, local, report=False) is None:
            model, wrong = self.scope.model, arg.ident.name
            legs = [leg.name for leg in model.legs] + list(self.scope.roles)
            contacts = [c.name for c in model.contacts]
            self.err(
                arg.span,
                f"{name}() takes a leg, a role or a contact; creature '{model.name}' has no "
                f"'{wrong}' (legs and roles: {', '.join(legs) or 'none'}; contacts: "
                f"{', '.join(contacts) or 'none'}){did_you_mean(wrong, legs + contacts)}",
            )
            return None
        target = self.expr(arg, local)
        if isinstance(target, Opaque):
            return ir.Named("opaque", target.name, BOOL)
        ok = isinstance(target, ir.Legs) or (
            isinstance(target, ir.Part | ir.Alias) and target.kind == "contact"
        )
        if not ok:
            if target is not None:
                self.err(e.args[0].span, f"{name}() takes a leg, a role or a contact")
            return None
        assert isinstance(target, ir.Legs | ir.Part | ir.Alias)
        return ir.Event(name, target)

    def integral(self, e: ast.ECall, local: dict[str, Value]) -> ir.Expr | None:
        """``integral(INPUT)``: the input's commands integrated over the run's time, exactly
        (they are piecewise constant): its unit times a second."""
        value = self.expr(e.args[0], local)
        if isinstance(value, Opaque):
            return ir.Named("opaque", value.name, None)
        if isinstance(value, ir.Named) and value.kind == "input":
            return ir.Named("integral", value.name, _combine(value.type, ir.TIME, 1))
        if value is not None:
            inputs = [n for n, v in self.scope.names.items()
                      if isinstance(v, ir.Named) and v.kind == "input"]  # fmt: skip
            example = f"integral({inputs[0]})" if inputs else "integral(turn_rate)"
            written = isinstance(e.args[0], ast.EName | ast.EAttr)  # else 'this', unsaid
            self.err(
                e.args[0].span,
                f"integral() takes one of the controller's inputs, as in {example}; "
                f"'{expression_text(e.args[0])}' is not an input"
                if written
                else f"integral() takes the name of one of the controller's inputs, as in "
                f"{example}, not an expression: write what scales it outside, as in "
                f"'2 * {example}' (an input alone is integrated, its commands being known "
                "between ticks)",
            )
        return None

    def want(self, e: ast.ECall, args: list[ir.Expr], dims: tuple[Type, ...], what: str) -> bool:
        for arg, node in zip(args, e.args, strict=True):
            if arg.type is not None and arg.type not in dims:
                hint = want_hint(e.func.name, node, what, arg.type)
                self.err(
                    node.span, f"{e.func.name}() takes {what}, not {describe_type(arg.type)}{hint}"
                )
                return False
        return True


Rule = Callable[[ExprChecker, ast.ECall, list[ir.Expr]], Type | Mismatch]


def _trig(el: ExprChecker, e: ast.ECall, args: list[ir.Expr]) -> Type | Mismatch:
    return ONE if el.want(e, args, (ir.ANGLE, ONE), "an angle") else MISMATCH


def _inverse_trig(el: ExprChecker, e: ast.ECall, args: list[ir.Expr]) -> Type | Mismatch:
    return ir.ANGLE if el.want(e, args, (ONE,), "a plain number") else MISMATCH


def _plain(el: ExprChecker, e: ast.ECall, args: list[ir.Expr]) -> Type | Mismatch:
    return ONE if el.want(e, args, (ONE,), "a plain number") else MISMATCH


def _atan2(el: ExprChecker, e: ast.ECall, args: list[ir.Expr]) -> Type | Mismatch:
    same = el.same(args, list(e.args), "the two arguments of atan2()")
    return same if isinstance(same, Mismatch) else ir.ANGLE


def _alike(el: ExprChecker, e: ast.ECall, args: list[ir.Expr]) -> Type | Mismatch:
    return el.same(args, list(e.args), f"the arguments of {e.func.name}()")


def _sqrt(el: ExprChecker, e: ast.ECall, args: list[ir.Expr]) -> Type | Mismatch:
    t = args[0].type
    if not isinstance(t, tuple):
        return t
    if any(d % 2 for d in t):
        el.err(
            e.args[0].span,
            f"sqrt() of {describe_type(t)} has no unit: its powers are not all even"
            + sqrt_hint(e.args[0], t),
        )
        return MISMATCH
    return (t[0] // 2, t[1] // 2, t[2] // 2, t[3] // 2)


_FUNCTION_RULES: dict[str, Rule] = {
    "sin": _trig, "cos": _trig, "tan": _trig,
    "asin": _inverse_trig, "acos": _inverse_trig, "atan": _inverse_trig, "atan2": _atan2,
    "sqrt": _sqrt, "abs": lambda el, e, a: a[0].type, "sign": lambda el, e, a: ONE,
    "exp": _plain, "log": _plain, "min": _alike, "max": _alike, "clamp": _alike,
}  # fmt: skip


def _combine(a: Type, b: Type, sign: int) -> Type:
    if not isinstance(a, tuple) or not isinstance(b, tuple):
        if a is None and b is None:
            return None
        # a bare 0 times anything is 0 of any dimension
        return None
    return (a[0] + sign * b[0], a[1] + sign * b[1], a[2] + sign * b[2], a[3] + sign * b[3])


class NoValue(ValueError):
    """A constant expression with no finite real value; the message says why."""


_ARITHMETIC: dict[str, Callable[[float, float], float]] = {
    "+": lambda a, b: a + b, "-": lambda a, b: a - b, "*": lambda a, b: a * b,
    "/": lambda a, b: a / b, "^": lambda a, b: a**b,
}  # fmt: skip
_DOMAIN = {
    "sqrt": "sqrt() of a negative number",
    "log": "log() of zero or a negative number",
    "asin": "asin() of a number outside -1 to 1",
    "acos": "acos() of a number outside -1 to 1",
}


def _finite(compute: Callable[[], float], op: str) -> float:
    """``compute()``, which must give a finite real number; else ``NoValue`` saying why."""
    try:
        value = compute()
    except ZeroDivisionError:
        raise NoValue("this has no value: it divides by zero") from None
    except OverflowError:
        value = math.inf
    except ValueError:
        raise NoValue(
            f"this has no value: {_DOMAIN.get(op, f'{op}() outside its domain')}"
        ) from None
    if isinstance(value, complex):
        raise NoValue("this has no real value: a negative number raised to a fractional power")
    if not math.isfinite(value):
        raise NoValue("this is too large a number: it overflows a double")
    return value


def fits(t: Type, want: Dim) -> bool:
    return t is None or t == want


def unit_advice(want: Dim) -> str:
    return "" if want == ONE else f"; write it with a unit of {describe(want)}"


def gram_for_gravity(exprs: list[ast.Expr]) -> str:
    """The hint for a quantity among ``exprs`` with a gram where gravity, 'g', was meant: in
    '2 kg*g' the lexer reads 'kg*g' as one unit (kilogram times gram), and in '0.5 g' the
    'g' after the number is a gram; '' if there is none."""
    stack: list[object] = list(exprs)
    while stack:
        node = stack.pop()
        if isinstance(node, ast.EQuantity):
            if re.search(r"[A-Za-z]\*g(?![A-Za-z])", node.text):
                return (
                    f"; '{node.text}' is one unit, a gram in it: for gravity write "
                    f"'{node.text.replace('*g', ' * g')}', with spaces"
                )
            alone = re.fullmatch(r"(.*?\d\.?)[ \t]*g", node.text)
            if alone is not None:
                return (
                    f"; '{node.text}' is {alone.group(1)} gram: for gravity, multiply, as in "
                    f"'{alone.group(1)} * g'"
                )
        if dataclasses.is_dataclass(node) and not isinstance(node, type):
            stack.extend(getattr(node, f.name) for f in dataclasses.fields(node))
        elif isinstance(node, list | tuple):
            stack.extend(node)
    return ""
