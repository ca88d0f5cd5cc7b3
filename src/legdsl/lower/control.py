"""Lower a checked controller to sympy: per role binding and per state, what to compute.

The input is the controller IR (``legdsl.ir.controller``): every name already resolved,
actions inlined, and the role bindings that the table's swaps reach enumerated. Roles
(``active``, ``idle``) are names bound to legs or groups of legs and exchanged by
``swap``; each state's code is specialised here for each binding, so the generated module
never looks a role up at run time: it only keeps the index of the current binding.

Semantics of a table row ``state S on EVENT: statements``:

* the machine advances through the rows in order; in state i it tests only
  the event of row i+1 (the last row is followed by the first), as in
  Figure 4 of the paper;
* on entering a state, its ``swap`` statements run first (so the row's other
  statements see the new binding), then its ``record`` statements, once;
* every control tick while the state is active, its ``let`` and assignment
  statements run in order; an actuator keeps the last value it was given.

Reading a member of a group of legs reads the group as one virtual leg: the mean of
its members (``touching`` is true if any foot touches, ``stance_time`` the longest
member's, ``flight_time`` the shortest's, ``feet_down`` counts the feet down); writing it
writes every leg of the group. ``each LEG in GROUP { ... }`` lowers its statements once
per member, LEG bound to that member alone.
``touchdown(X)`` holds when any of X's feet touches and ``liftoff(X)`` when
none does: as events they are tested only while the machine waits for them.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any

import sympy
from sympy import Expr, Symbol

from legdsl.ir import controller as ir
from legdsl.ir.constants import body_constant, coord_constant, leg_constant
from legdsl.ir.controller import Binding, Controller
from legdsl.ir.model import Model
from legdsl.lang.errors import InternalError, LegError, Span
from legdsl.lower.folds import NO_VALUE, dropped, past_double

Roles = dict[str, tuple[str, ...]]  # role -> legs, under one binding


def sensor_symbol(key: str) -> Symbol:
    """``leg.main.length`` -> the symbol ``leg_main_length`` (names in generated code)."""
    return Symbol(key.replace(".", "_"))


@dataclass(frozen=True)
class EachPass:
    """One member's pass through an ``each VAR in GROUP { ... }`` block (``span``: the
    block's), as a place a statement came through."""

    span: Span
    var: str
    leg: str

    # where a Span is read (the generated code's origins): the block's place
    file = property(lambda self: self.span.file)
    line = property(lambda self: self.span.line)
    col = property(lambda self: self.span.col)


# Where a statement came from: its span, then the action calls and each blocks it was inlined
# through, innermost first (for run-time faults; generated code does not depend on it).
Where = tuple[Span | EachPass, ...]


@dataclass(frozen=True)
class Setting:
    actuator: str
    key: str
    value: Expr
    where: Where = ()


@dataclass(frozen=True)
class Place:
    """A kinematic solve: the servos' setpoints such that the leg's foot sits at ``goals`` from its hip."""

    leg: str
    axes: tuple[str, ...]
    goals: tuple[Expr, ...]
    servos: tuple[str, ...]
    where: Where = ()


@dataclass(frozen=True)
class StateBody:
    """What one state does under one binding: once on entry (records), and every tick (settings, places)."""

    records: tuple[tuple[str, Expr], ...]
    settings: tuple[Setting, ...]
    places: tuple[Place, ...] = ()
    record_where: tuple[Where, ...] = ()  # one per entry of ``records``


@dataclass
class LoweredController:
    name: str
    creature: str
    states: tuple[str, ...]
    start: int
    bindings: tuple[Binding, ...]
    # (binding while waiting, state) -> the condition to enter the state
    events: dict[tuple[int, int], sympy.Basic]
    # (binding while waiting, state) -> the binding once the state's swaps are done
    after_entry: dict[tuple[int, int], int]
    # (binding the state runs under, state) -> its records and settings
    bodies: dict[tuple[int, int], StateBody]
    inputs: tuple[tuple[str, float], ...]
    params: tuple[tuple[str, float], ...]
    records: tuple[str, ...]
    sensors: tuple[str, ...] = ()
    # (binding while waiting, state) -> where the state's row is (its event)
    event_where: dict[tuple[int, int], Where] = field(default_factory=dict)


class Lowerer:
    """Turns one controller's IR into sympy, state by state under each role binding."""

    def __init__(self, model: Model, controller: Controller):
        self.model = model
        self.ctl = controller
        self.aliases = {leg.name: dict(leg.aliases) for leg in model.legs}
        self.kinds: dict[str, str] = {}
        for b in model.bodies:
            self.kinds[b.name] = "body"
        for c in model.contacts:
            self.kinds[c.name] = "contact"
        for d in model.dofs:
            self.kinds[d.name] = "coord"
        for a in model.actuators:
            self.kinds[a.name] = "actuator"
        self.signals = {s.name: s.value for s in controller.signals}
        self.sensors: set[str] = set()
        # a function of the same arguments, called again (an action inlined in several states
        # and bindings): its value once, for sympy's Min and Max compare their every pair of
        # arguments, which takes seconds on a placement's expressions
        self._calls: dict[tuple[str, tuple[Any, ...]], Any] = {}
        self._hold_branches = False  # see value()
        # the first part found with no finite value, or left out by a fold: where (the signal
        # it is in), and what to tell
        self._fault: tuple[Span | None, str] | None = None
        self._in_signals: list[Span] = []  # the signals being written out, innermost last
        self._spans = {s.name: s.span for s in controller.signals}
        self._declared = {
            Symbol(f"{kind}_{c.name}"): sympy.Float(c.value)
            for kind, values in (("input", controller.inputs), ("param", controller.params))
            for c in values
        }

    def lower(self) -> LoweredController:
        events: dict[tuple[int, int], sympy.Basic] = {}
        bodies: dict[tuple[int, int], StateBody] = {}
        event_where: dict[tuple[int, int], Where] = {}
        for b, binding in enumerate(self.ctl.bindings):
            roles = dict(binding)
            for s, state in enumerate(self.ctl.states):
                at = state.event_span if state.event_span.line > 0 else state.span
                events[(b, s)] = self.value(state.event, roles, (at,))
                event_where[(b, s)] = (at,)
                records: list[tuple[str, Expr]] = []
                settings: list[Setting] = []
                places: list[Place] = []
                record_where: list[Where] = []
                self.statements(state.body, roles, records, settings, places, (), record_where)
                bodies[(b, s)] = StateBody(
                    tuple(records), tuple(settings), tuple(places), tuple(record_where)
                )
        return LoweredController(
            name=self.ctl.name,
            creature=self.model.name,
            states=self.ctl.state_names,
            start=self.ctl.state_names.index(self.ctl.start),
            bindings=self.ctl.bindings,
            events=events,
            after_entry=dict(self.ctl.after_entry),
            bodies=bodies,
            inputs=tuple((c.name, c.value) for c in self.ctl.inputs),
            params=tuple((c.name, c.value) for c in self.ctl.params),
            records=self.ctl.record_names,
            sensors=tuple(sorted(self.sensors)),
            event_where=event_where,
        )

    def statements(
        self,
        stmts: Iterable[ir.Stmt],
        roles: Roles,
        records: list[tuple[str, Expr]],
        settings: list[Setting],
        places: list[Place],
        calls: Where = (),
        record_where: list[Where] | None = None,
    ) -> None:
        for s in stmts:
            if isinstance(s, ir.Record):
                records.append((s.name, self.value(s.value, roles, (s.span, *calls))))
                if record_where is not None:
                    record_where.append((s.span, *calls))
            elif isinstance(s, ir.Assign):
                value = self.value(s.value, roles, (s.span, *calls))
                for part in self.parts(s.actuator, roles):
                    settings.append(Setting(part.name, s.key, value, (s.span, *calls)))
            elif isinstance(s, ir.Do):
                inner = (s.span, *calls)
                self.statements(s.body, roles, records, settings, places, inner, record_where)
            elif isinstance(s, ir.Place):
                places.extend(self.place(s, roles, (s.span, *calls)))
            elif isinstance(s, ir.Each):
                for leg in self.legs(s.group, roles):
                    member, inner = {**roles, s.var: (leg,)}, (EachPass(s.span, s.var, leg), *calls)
                    self.statements(s.body, member, records, settings, places, inner, record_where)
            # swaps are done on entry, before anything else (the IR's bindings)

    def place(self, s: ir.Place, roles: Roles, where: Where = ()) -> list[Place]:
        """One solve per leg of the role (each foot placed from its own hip)."""
        legs = self.legs(s.legs, roles)
        goals = tuple(self.value(goal, roles, where) for goal in s.goals)
        per_servo = [self.parts(servo, roles) for servo in s.servos]
        return [
            Place(
                leg,
                s.axes,
                goals,
                tuple(parts[min(k, len(parts) - 1)].name for parts in per_servo),
                where,
            )
            for k, leg in enumerate(legs)
        ]

    # ------------------------------------------------------------ things
    def value(self, e: ir.Expr, roles: Roles, where: Where) -> Any:
        """``e`` in sympy; an error where sympy has made a number of it, or of a part of it,
        that is infinite, NaN or complex in every state (a division by a difference that is
        always 0), or past a double (sympy gathers a product's numbers into one: ``x * 1e200
        * 1e200`` is ``1e400*x``), or where folding leaves out a part that has no value with
        the parameters and inputs as declared (``0 * (x / zero)``, ``zero`` declared 0, is 0 to
        sympy: the division that a run would refuse is never made). The error is at the
        signal the part is in, if it is the user's, else at the statement's line. A part is
        looked at before it is used, since sympy's min, max and comparisons raise on an
        infinity. A select's branch with no value is the run's fault where it is taken, not
        the file's."""
        value = self._try(e, roles)
        if not _finite_everywhere(value):
            # sympy carries a function into a select's branches (sqrt(select(c, -1, x)) is
            # select(c, I, sqrt(x))): a branch with no value is a run-time fault, as the same
            # function of a state would be, where it is taken; so keep numbers there unevaluated
            self._hold_branches = True
            try:
                value = self._try(e, roles)
            finally:
                self._hold_branches = False
        if not _finite_everywhere(value) or self._fault is not None:
            at, why = self._fault or (None, NO_VALUE)
            user = next((w for w in where if w.file == self.model.span.file), where[-1])
            if at is not None and at.file == self.model.span.file:
                user = at
            raise LegError.at(user.span if isinstance(user, EachPass) else user, why)
        return value

    def _try(self, e: ir.Expr, roles: Roles) -> Any:
        self._fault = None
        self._in_signals = []
        try:
            return self.expr(e, roles)
        except _NoValue:
            return sympy.nan

    def _look(self, e: ir.Binary | ir.Call, operands: tuple[Any, ...], result: Any) -> Any:
        """``result`` of ``e`` on ``operands``; notes the first part that is not finite (past
        a double, or no number at all), and a fold that leaves out a part with no value."""
        if self._fault is not None:
            return result
        at = self._in_signals[-1] if self._in_signals else None
        if not _finite_everywhere(result):
            past = [
                f
                for f in getattr(result, "atoms", lambda _: ())(sympy.Float)
                if not math.isfinite(float(f))
            ]
            if past and not result.has(sympy.zoo, sympy.oo, -sympy.oo, sympy.nan, sympy.I):
                self._fault = (at, past_double(past[0], operands))
            elif at is not None:
                self._fault = (at, NO_VALUE)
        elif getattr(result, "is_Number", False) and any(
            isinstance(x, sympy.Basic) and x.free_symbols for x in operands
        ):
            # folded to a number: made again of the operands with the parameters and inputs
            # as declared, it has no value if what the fold left out has none
            declared = [x.subs(self._declared) for x in operands]
            op = _BINARY[e.op] if isinstance(e, ir.Binary) else FUNCTIONS[e.func]
            try:
                finite = all(_finite_everywhere(x) for x in (*declared, op(*declared)))
            except (TypeError, ValueError, ZeroDivisionError):  # (min and max refuse zoo)
                finite = False
            if not finite:
                self._fault = (at, dropped(e, result, operands))
        return result

    def legs(self, legs: ir.Legs, roles: Roles) -> tuple[str, ...]:
        if legs.each is not None:
            return roles[legs.each]  # the member an `each` block is at
        return roles[legs.role] if legs.role is not None else (legs.leg or "",)

    def parts(self, thing: ir.Part | ir.Alias, roles: Roles) -> list[ir.Part]:
        """The part itself, or what the alias names on each leg of its role."""
        if isinstance(thing, ir.Part):
            return [thing]
        names = [self.aliases[leg][thing.alias] for leg in self.legs(thing.legs, roles)]
        return [ir.Part(self.kinds[name], name) for name in names]

    # ------------------------------------------------------------ expressions
    def expr(self, e: ir.Expr, roles: Roles) -> Any:
        if isinstance(e, ir.Num):
            return sympy.Float(e.value)
        if isinstance(e, ir.Named):
            return self.named(e, roles)
        if isinstance(e, ir.Read):
            return self.read(e.thing, e.member, roles)
        if isinstance(e, ir.Unary):
            operand = self.expr(e.operand, roles)
            return -operand if e.op == "-" else sympy.Not(operand)
        if isinstance(e, ir.Binary):
            operands = (self.expr(e.left, roles), self.expr(e.right, roles))
            result = _BINARY[e.op](*_finite(*operands, real=e.op in _COMPARED))
            return self._look(e, operands, result)
        if isinstance(e, ir.Event):
            flags = self.flags(e.thing, roles)
            if e.kind == "touchdown":
                return sympy.Or(*[f > 0.5 for f in flags])
            return sympy.And(*[f < 0.5 for f in flags])
        if e.func == "select":
            condition, a, b = _finite(*(self.expr(x, roles) for x in e.args))
            if self._hold_branches:
                a, b = (sympy.UnevaluatedExpr(x) if x.is_Number else x for x in (a, b))
            return sympy.Piecewise((a, condition), (b, True))
        args = _finite(*(self.expr(a, roles) for a in e.args), real=e.func in _COMPARED)
        key = (e.func, args)
        if key not in self._calls:
            self._calls[key] = FUNCTIONS[e.func](*args)
        return self._look(e, args, self._calls[key])

    def calls(self) -> list[tuple[str, tuple[Any, ...], Any]]:
        """Each built-in function's call lowered so far, as written (its name and arguments),
        with what sympy made of it (``asin(x - 0.5)`` is ``-asin(0.5 - x)`` to it)."""
        return [(func, args, result) for (func, args), result in self._calls.items()]

    def named(self, e: ir.Named, roles: Roles) -> Any:
        if e.kind in ("input", "param", "record"):
            return Symbol(f"{e.kind}_{e.name}")
        if e.kind == "integral":  # the machine's, read as a sensor (legdsl.sim.machine)
            return self.sense(f"integral.{e.name}")
        if e.kind == "signal":
            self._in_signals.append(self._spans[e.name])
            try:
                return self.expr(self.signals[e.name], roles)
            finally:
                self._in_signals.pop()
        if e.name == "time":
            self.sensors.add("time")
            return Symbol("time")
        if e.name == "time_in_state":
            return Symbol("time_in_state")
        if e.name == "pi":
            return sympy.pi
        if e.name == "g":
            return sympy.Float(-self.model.gravity[2])
        if e.name == "total_mass":
            return sympy.Float(self.model.total_mass)
        raise InternalError(f"a named value of kind {e.kind}: {e.name}")

    def read(self, thing: ir.Thing, member: str, roles: Roles) -> Expr:
        """A member of a thing; of several legs (a group role) it is their mean, ``touching``
        their maximum (any foot touches)."""
        if isinstance(thing, ir.Legs):
            legs = self.legs(thing, roles)
            if member in ir.LEG_CONSTANTS:
                constants = [sympy.Float(leg_constant(self.model, leg, member)) for leg in legs]
                return sympy.Add(*constants) / len(constants)
            if member == "feet_down":
                return sympy.Add(*[self.sense(f"leg.{leg}.touching") for leg in legs])
            values = [self.sense(f"leg.{leg}.{member}") for leg in legs]
            if len(values) == 1:
                return values[0]
            return _GROUP.get(member, _mean)(*values)
        parts = self.parts(thing, roles)
        values = [self.value_of(part, member) for part in parts]
        return values[0] if len(values) == 1 else sympy.Add(*values) / len(values)

    def value_of(self, part: ir.Part, member: str) -> Expr:
        """A part's member: a sensor, or a constant of the model read through an alias."""
        if member in ir.COORD_CONSTANTS and part.kind == "coord":
            return sympy.Float(coord_constant(self.model, part.name, member))
        if member in ir.BODY_CONSTANTS and part.kind == "body":
            value = body_constant(self.model, part.name, member)
            if value is None:
                raise InternalError(f"body {part.name} has no length")  # the checker says so
            return sympy.Float(value)
        return self.sense(_sensor_key(part, member))

    def flags(self, thing: ir.Thing, roles: Roles) -> list[Symbol]:
        if isinstance(thing, ir.Legs):
            return [self.sense(f"leg.{leg}.touching") for leg in self.legs(thing, roles)]
        return [self.sense(_sensor_key(part, "touching")) for part in self.parts(thing, roles)]

    def sense(self, key: str) -> Symbol:
        self.sensors.add(key)
        return sensor_symbol(key)


def _sensor_key(part: ir.Part, member: str) -> str:
    if part.kind in ("com", "terrain"):
        return f"{part.kind}.{member}"
    if part.kind == "actuator":
        return f"act.{part.name}.{member}"
    return f"{part.kind}.{part.name}.{member}"


def _finite_everywhere(value: Any) -> bool:
    """Whether an expression holds no infinity, NaN or imaginary unit, and no number past
    a double (sympy's floats go further: 1e200 * 1e200 is 1e400 to it, inf to the code)."""
    if not isinstance(value, sympy.Basic):
        return True
    if value.has(sympy.zoo, sympy.oo, -sympy.oo, sympy.nan, sympy.I):
        return False
    return all(math.isfinite(float(f)) for f in value.atoms(sympy.Float))


class _NoValue(Exception):
    """A part of an expression has no finite real value in any state."""


def _finite(*values: Any, real: bool = False) -> tuple[Any, ...]:
    """``values``, each finite wherever it is real; ``real``: also real somewhere (sympy
    compares the arguments of min, max and a comparison, and raises on one it knows is
    never real, as ``sqrt(min(x, -1))``)."""
    if not all(_finite_everywhere(v) for v in values):
        raise _NoValue
    if real and any(getattr(v, "is_extended_real", None) is False for v in values):
        raise _NoValue
    return values


# where sympy compares its operands, and an operand that is never real has no value
_COMPARED = {"min", "max", "clamp", "<", ">", "<=", ">=", "==", "!="}


def _mean(*values: Expr) -> Expr:
    return sympy.Add(*values) / len(values)


# A group of legs read as one virtual leg: its foot, hip, length and rate are its members'
# means; it touches when any member does (touchdown: the first lands; liftoff: the last
# leaves); its stance lasts as long as the longest member's, its flight as the shortest's.
_GROUP = {"touching": sympy.Max, "stance_time": sympy.Max, "flight_time": sympy.Min}


def _relation(relation: Any, a: Any, b: Any) -> Any:
    """``a`` compared with ``b``; as ``a - b`` with 0 where sympy's canonical form of the
    comparison never settles (``19.62*x == -4.905*x`` turns into ``4.905*x == -19.62*x`` and
    back): a select() on it recursed in sympy until Python's stack ran out."""
    rel = relation(a, b)
    if isinstance(rel, sympy.core.relational.Relational):
        canonical = rel.canonical
        if canonical.canonical != canonical:
            return relation(a - b, 0)
    return rel


_BINARY = {
    "+": lambda a, b: a + b,
    "-": lambda a, b: a - b,
    "*": lambda a, b: a * b,
    "/": lambda a, b: a / b,
    "^": lambda a, b: a**b,
    "<": lambda a, b: _relation(sympy.StrictLessThan, a, b),
    ">": lambda a, b: _relation(sympy.StrictGreaterThan, a, b),
    "<=": lambda a, b: _relation(sympy.LessThan, a, b),
    ">=": lambda a, b: _relation(sympy.GreaterThan, a, b),
    "==": lambda a, b: _relation(sympy.Eq, a, b),
    "!=": lambda a, b: _relation(sympy.Ne, a, b),
    "and": lambda a, b: sympy.And(a, b),
    "or": lambda a, b: sympy.Or(a, b),
}

FUNCTIONS = {  # a control law's built-in functions in sympy (their values: ir FUNCTION_VALUES)
    "sin": sympy.sin,
    "cos": sympy.cos,
    "tan": sympy.tan,
    "asin": sympy.asin,
    "acos": sympy.acos,
    "atan": sympy.atan,
    "atan2": sympy.atan2,
    "sqrt": sympy.sqrt,
    "abs": sympy.Abs,
    "exp": sympy.exp,
    "log": sympy.log,
    "sign": sympy.sign,
    "min": sympy.Min,
    "max": sympy.Max,
    "clamp": lambda x, lo, hi: sympy.Min(sympy.Max(x, lo), hi),
}


def lower_controller(model: Model, controller: Controller) -> LoweredController:
    return Lowerer(model, controller).lower()
