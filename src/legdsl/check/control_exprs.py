"""Resolve a controller's expressions and statements into the typed controller IR.

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

import math
from collections.abc import Callable
from dataclasses import dataclass, field

from legdsl.check.values import did_you_mean, place_of
from legdsl.ir import controller as ir
from legdsl.ir.controller import BOOL, ONE, Type
from legdsl.ir.model import Model, setting_kind
from legdsl.lang import ast
from legdsl.lang.errors import Diagnostics, Span
from legdsl.lang.units import KINDS, Dim, describe

# name -> number of arguments (None: any number, at least one)
BUILTIN_FUNCTIONS: dict[str, int | None] = {
    "sin": 1, "cos": 1, "tan": 1, "asin": 1, "acos": 1, "atan": 1, "atan2": 2,
    "sqrt": 1, "abs": 1, "exp": 1, "log": 1, "sign": 1,
    "min": None, "max": None, "clamp": 3, "select": 3,
    "liftoff": 1, "touchdown": 1,
}  # fmt: skip
EVENT_FUNCTIONS = ("liftoff", "touchdown")
_KIND_WORDS = {"coord": "joint coordinate", "path": "path", "com": "centre of mass"}
_MEMBER_EXAMPLES = {
    "body": "z", "leg": "length", "role": "length", "contact": "z", "com": "vx",
    "coord": "value", "actuator": "force", "path": "lateral",
}  # fmt: skip


class Mismatch:
    """Dimensions that do not agree (already reported)."""


MISMATCH = Mismatch()


@dataclass(frozen=True)
class Opaque:
    """A parameter of an action that no table calls: its names are checked, not its meaning."""

    name: str


Value = ir.Expr | ir.Thing | Opaque


@dataclass
class Scope:
    """What the names of one controller stand for (the creature's, then the controller's)."""

    model: Model
    names: dict[str, Value]
    roles: dict[str, tuple[str, ...]]  # role -> legs of the initial binding
    actions: dict[str, ast.ActionDef]
    signals: dict[str, ast.SignalDecl]
    records: dict[str, Type]  # record -> its type as far as known
    user_file: str  # the controller's file: errors elsewhere are reported at its calls
    aliases: dict[str, dict[str, str]] = field(init=False)

    def __post_init__(self) -> None:
        self.aliases = {leg.name: dict(leg.aliases) for leg in self.model.legs}


@dataclass(frozen=True)
class AliasUse:
    """A role's alias, to be checked on every leg the role is bound to once bindings are known."""

    alias: ir.Alias
    span: Span
    context: tuple[ast.InvokeStmt, ...]


class Elaborator:
    """Turns syntax into IR nodes under one ``Scope``; mistakes go to ``diag``."""

    def __init__(self, scope: Scope, diag: Diagnostics):
        self.scope = scope
        self.diag = diag
        self.calls: list[tuple[ast.InvokeStmt, ast.ActionDef]] = []
        self.alias_uses: list[AliasUse] = []
        self.record_types: dict[str, list[tuple[Type, Span]]] = {}
        self.signal_ir: dict[str, ir.Expr | None] = {}
        self._signals_open: list[str] = []
        self._planar_sites: set[Span] = set()

    # ------------------------------------------------------------ errors
    def err(self, span: Span, message: str) -> None:
        """Report at ``span``, or, inside an action from another file, at the user's call."""
        site = self._user_site()
        if site is None or span.file == self.scope.user_file:
            self.diag.error(span, message)
            return
        action = self.calls[-1][1]
        self.diag.error(
            site.span, f"{message} (in action '{action.name.name}', {place_of(span)}, called here)"
        )

    def planar_error(self, span: Span, message: str, hint: str) -> None:
        """A 3D-only thing in a planar creature: once per call of a library action (a 3D
        action reads many), else where it is written."""
        site = self._user_site()
        if site is not None:
            if site.span in self._planar_sites:
                return
            self._planar_sites.add(site.span)
            hint = f"action '{self.calls[-1][1].name.name}' is for 3D creatures"
        self.err(span, f"{message} ({hint})")

    def _user_site(self) -> ast.InvokeStmt | None:
        """The call in the user's file that leads into another file's action, if any."""
        if not self.calls or self.calls[-1][1].span.file == self.scope.user_file:
            return None
        return next(
            (c for c, _ in reversed(self.calls) if c.span.file == self.scope.user_file),
            self.calls[0][0],
        )

    # ------------------------------------------------------------ statements
    def stmts(self, stmts: tuple[ast.Stmt, ...], local: dict[str, Value]) -> list[ir.Stmt]:
        local = dict(local)
        out: list[ir.Stmt] = []
        for s in stmts:
            if isinstance(s, ast.LetStmt):
                value = self.number(s.value, local)
                local[s.name.name] = value if value is not None else ir.Num(0.0, None)
            elif isinstance(s, ast.AssignStmt):
                out += self.assign(s, local)
            elif isinstance(s, ast.RecordStmt):
                value = self.number(s.value, local)
                if value is not None:
                    self.record_types.setdefault(s.name.name, []).append((value.type, s.span))
                    out.append(ir.Record(s.name.name, value, s.span))
            elif isinstance(s, ast.SwapStmt):
                roles = [self.role(ident, local) for ident in (s.first, s.second)]
                if roles[0] is not None and roles[1] is not None:
                    out.append(ir.Swap(roles[0], roles[1], s.span))
            elif isinstance(s, ast.InvokeStmt):
                done = self.invoke(s, local)
                if done is not None:
                    out.append(done)
            elif isinstance(s, ast.PlaceStmt):
                place = self.place(s, local)
                if place is not None:
                    out.append(place)
        return out

    def assign(self, s: ast.AssignStmt, local: dict[str, Value]) -> list[ir.Stmt]:
        value = self.number(s.value, local)
        target = self.path(s.target[:-1], local) if len(s.target) > 1 else None
        key = s.target[-1]
        text = ".".join(t.name for t in s.target)
        if len(s.target) == 1:
            self.lookup(key, local)  # an unknown name is reported as such
            found = self.scope.names.get(key.name, local.get(key.name))
            if found is not None:
                self.err(key.span, _cannot_set(text))
            return []
        if target is None or isinstance(target, Opaque):
            return []
        actuator = self.actuator_of(target)
        if actuator is None:
            self.err(key.span, _cannot_set(text))
            return []
        kind, rotary = actuator
        settable = ir.ACTUATOR_MEMBERS[kind][0]
        if key.name not in settable:
            readable = ir.ACTUATOR_MEMBERS[kind][1]
            self.err(
                key.span,
                _cannot_set(text)
                if key.name in readable
                else f"a {kind} actuator has no '{key.name}'; it has "
                f"{', '.join(settable + readable)}{did_you_mean(key.name, settable + readable)}",
            )
            return []
        want = KINDS[setting_kind(key.name, rotary)][0]
        if value is None:
            return []
        if not _fits(value.type, want):
            self.err(
                s.value.span,
                f"'{text}' is {describe_type(want)}, but the value is {describe_type(value.type)}"
                f"{_unit_advice(want)}",
            )
            return []
        assert isinstance(target, ir.Part | ir.Alias)
        return [ir.Assign(target, key.name, value, s.span)]

    def invoke(self, s: ast.InvokeStmt, local: dict[str, Value]) -> ir.Do | None:
        action = self.scope.actions.get(s.action.name)
        args = [self.expr(a, local) for a in s.args]
        if action is None:
            self.err(
                s.action.span,
                f"unknown action '{s.action.name}'; define it with 'action {s.action.name}(...) "
                f"{{ ... }}' or 'use' a library that has it"
                f"{did_you_mean(s.action.name, self.scope.actions)}",
            )
            return None
        if len(s.args) != len(action.params):
            self.err(
                s.span,
                f"action '{s.action.name}' takes {len(action.params)} argument(s), got {len(s.args)}",
            )
            return None
        if any(a is action for _, a in self.calls):
            self.err(s.action.span, f"action '{s.action.name}' calls itself")
            return None
        bound: dict[str, Value] = {}
        for param, arg, value in zip(action.params, s.args, args, strict=True):
            bound[param.name] = value if value is not None else Opaque(_text(arg))
        self.calls.append((s, action))
        try:
            body = self.stmts(action.body, bound)
        finally:
            self.calls.pop()
        return ir.Do(s.action.name, tuple(body), s.span)

    def place(self, s: ast.PlaceStmt, local: dict[str, Value]) -> ir.Place | None:
        """``place LEG at (x = .., z = ..) using SERVO, ..``: a leg, known axes, one servo per goal."""
        legs = self.lookup(s.leg, local)
        opaque = isinstance(legs, Opaque)
        if legs is not None and not opaque and not isinstance(legs, ir.Legs):
            self.err(
                s.leg.span,
                f"'place' moves the foot of a leg or role; '{s.leg.name}' is {_what(legs)}",
            )
            legs = None
        planar = self.scope.model.planar and not opaque
        axes = ("x", "z") if planar else ("x", "y", "z")
        seen: set[str] = set()
        goals: list[ir.Expr] = []
        ok = legs is not None and not opaque
        for name, value in s.goals:
            goal = self.number(value, local)
            if goal is not None and not _fits(goal.type, ir.LENGTH):
                self.err(
                    value.span,
                    f"'place' puts the foot at an offset from the hip, a length (m); "
                    f"this is {describe_type(goal.type)}",
                )
                ok = False
            if name.name not in axes:
                if name.name == "y" and self.scope.model.planar:
                    self.planar_error(
                        name.span,
                        f"creature '{self.scope.model.name}' is planar: 'place' can set x "
                        "and z only, not y",
                        "y is for 3D creatures",
                    )
                else:
                    self.err(
                        name.span,
                        f"'place' sets the foot's offset from the hip along "
                        f"{' and '.join(axes)}; '{name.name}' is not one of them"
                        f"{did_you_mean(name.name, axes)}",
                    )
                ok = False
            elif name.name in seen:
                self.err(name.span, f"'{name.name}' is given twice")
                ok = False
            seen.add(name.name)
            ok = ok and goal is not None
            if goal is not None:
                goals.append(goal)
        servos: list[ir.Part | ir.Alias] = []
        for path in s.servos:
            servo = self.path(path, local)
            if servo is None or isinstance(servo, Opaque):
                ok = False
                continue
            actuator = self.actuator_of(servo)
            if actuator is None or actuator[0] != "servo":
                self.err(
                    path[-1].span,
                    f"'place ... using' names servos whose setpoints it sets; "
                    f"'{'.'.join(i.name for i in path)}' is not a servo actuator",
                )
                ok = False
                continue
            assert isinstance(servo, ir.Part | ir.Alias)
            servos.append(servo)
        if len(s.servos) != len(s.goals):
            self.err(
                s.span,
                f"'place' needs one servo per goal: {len(s.goals)} goal(s), {len(s.servos)} servo(s)",
            )
            return None
        if not ok or not isinstance(legs, ir.Legs):
            return None
        axes_given = tuple(name.name for name, _ in s.goals)
        return ir.Place(legs, axes_given, tuple(goals), tuple(servos), s.span)

    def role(self, ident: ast.Ident, local: dict[str, Value]) -> str | None:
        found = self.lookup(ident, local, report=False)
        if isinstance(found, ir.Legs) and found.role is not None:
            return found.role
        if not isinstance(found, Opaque):
            self.err(
                ident.span,
                f"'swap' exchanges two roles; '{ident.name}' is not a role"
                + did_you_mean(ident.name, self.scope.roles),
            )
        return None

    # ------------------------------------------------------------ things and members
    def lookup(
        self, ident: ast.Ident, local: dict[str, Value], report: bool = True
    ) -> Value | None:
        if ident.name in local:
            return local[ident.name]
        if ident.name in self.scope.signals:
            return self.signal(ident.name)
        found = self.scope.names.get(ident.name)
        if found is None:
            if report:
                names = [*self.scope.names, *self.scope.signals, *local]
                self.err(
                    ident.span, f"unknown name '{ident.name}'{did_you_mean(ident.name, names)}"
                )
            return None
        if isinstance(found, ir.Named) and found.kind == "record":
            return ir.Named("record", found.name, self.scope.records.get(found.name))
        return found

    def path(self, idents: tuple[ast.Ident, ...], local: dict[str, Value]) -> Value | None:
        found = self.lookup(idents[0], local)
        for ident in idents[1:]:
            if found is None:
                return None
            found = self.member(found, ident)
        return found

    def member(self, base: Value, attr: ast.Ident) -> Value | None:
        name = attr.name
        if isinstance(base, Opaque):
            return base
        if isinstance(base, ir.Legs):
            if name in ir.LEG_MEMBERS:
                return self.read(base, name, ir.LEG_MEMBERS[name], attr.span)
            return self.alias(base, attr)
        if isinstance(base, ir.Part | ir.Alias):
            kind = base.kind
            members = self.members_of(base)
            if members is None:
                return None
            if name not in members:
                word = (
                    f"a {kind} actuator"
                    if kind == "actuator"
                    else f"a {_KIND_WORDS.get(kind, kind)}"
                )
                self.err(
                    attr.span,
                    f"{word} has no {'member ' if kind != 'actuator' else ''}'{name}'; it has "
                    f"{', '.join(members)}{did_you_mean(name, members)}",
                )
                return None
            return self.read(base, name, members[name], attr.span)
        self.err(attr.span, f"a number has no member '{name}'")
        return None

    def read(self, thing: ir.Thing, name: str, dim: Dim, span: Span) -> ir.Read | None:
        if self.scope.model.planar and name in ir.SPATIAL_MEMBERS:
            self.planar_error(
                span,
                f"creature '{self.scope.model.name}' is planar: it has no '{name}'",
                "that member is for 3D creatures",
            )
            return None
        return ir.Read(thing, name, dim)

    def alias(self, legs: ir.Legs, attr: ast.Ident) -> Value | None:
        name = attr.name
        leg_names = (
            (legs.leg,) if legs.leg is not None else self.scope.roles.get(legs.role or "", ())
        )
        if not leg_names:
            return Opaque(name)  # a role bound to no legs: reported where it was declared
        first = leg_names[0]
        aliases = self.scope.aliases[first]
        if name not in aliases:
            self.err(attr.span, no_alias_message(first, legs.role, name, aliases))
            return None
        target = self.scope.names[aliases[name]]
        if legs.leg is not None:
            return target
        assert isinstance(target, ir.Part)
        alias = ir.Alias(legs, name, target.kind)
        self.alias_uses.append(AliasUse(alias, attr.span, tuple(c for c, _ in self.calls)))
        return alias

    def part_of(self, thing: ir.Part | ir.Alias) -> ir.Part:
        """The part itself, or what the alias names on the first leg of its role."""
        if isinstance(thing, ir.Part):
            return thing
        leg = thing.legs.leg or self.scope.roles[thing.legs.role or ""][0]
        target = self.scope.names[self.scope.aliases[leg][thing.alias]]
        assert isinstance(target, ir.Part)
        return target

    def actuator_of(self, thing: Value) -> tuple[str, bool] | None:
        """(kind, rotary) of an actuator, or None if ``thing`` is no actuator."""
        if not isinstance(thing, ir.Part | ir.Alias) or thing.kind != "actuator":
            return None
        actuator = next(a for a in self.scope.model.actuators if a.name == self.part_of(thing).name)
        return actuator.kind, actuator.rotary

    def members_of(self, thing: ir.Part | ir.Alias) -> dict[str, Dim] | None:
        part = self.part_of(thing)
        if part.kind == "actuator":
            kind, rotary = self.actuator_of(part) or ("force", False)
            keys = ir.ACTUATOR_MEMBERS[kind][0] + ir.ACTUATOR_MEMBERS[kind][1]
            return {k: KINDS[setting_kind(k, rotary)][0] for k in keys}
        if part.kind == "coord":
            dof = next(d for d in self.scope.model.dofs if d.name == part.name)
            hinge = dof.motion == "hinge"
            return {
                "value": ir.ANGLE if hinge else ir.LENGTH,
                "rate": ir.ANGULAR_VELOCITY if hinge else ir.VELOCITY,
            }
        return {
            "body": ir.BODY_MEMBERS,
            "contact": ir.CONTACT_MEMBERS,
            "com": ir.COM_MEMBERS,
            "path": ir.PATH_MEMBERS,
        }[part.kind]

    def signal(self, name: str) -> ir.Named | None:
        """A signal, its expression resolved once (in the controller's scope, without locals)."""
        if name in self._signals_open:
            decl = self.scope.signals[name]
            self.err(decl.name.span, f"signal '{name}' is defined in terms of itself")
            return None
        if name not in self.signal_ir:
            self._signals_open.append(name)
            calls, self.calls = self.calls, []
            try:
                self.signal_ir[name] = self.number(self.scope.signals[name].value, {})
            finally:
                self.calls = calls
                self._signals_open.pop()
        value = self.signal_ir[name]
        return None if value is None else ir.Named("signal", name, value.type)

    # ------------------------------------------------------------ expressions
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
        value = self.expr(e, local, event)
        if value is None:
            return None
        if isinstance(value, Opaque):
            return ir.Num(0.0, None)
        if isinstance(value, ir.Legs | ir.Part | ir.Alias):
            kind = _thing_kind(value)
            text = _text(e)
            self.err(
                e.span,
                f"'{text}' is a {_KIND_WORDS.get(kind, kind)}, not a number: use one of its "
                f"members, as in '{text}.{_MEMBER_EXAMPLES[kind]}'",
            )
            return None
        if want_bool and value.type != BOOL:
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
            if not math.isfinite(q.value):
                self.err(e.span, f"'{e.text}' is too large a number")
                return None
            if q.unitless:
                return ir.Num(q.value, None if q.value == 0 else ONE)
            return ir.Num(q.value, q.dim)
        if isinstance(e, ast.EName):
            return self.lookup(e.ident, local)
        if isinstance(e, ast.EAttr):
            base = self.expr(e.base, local)
            return None if base is None else self.member(base, e.attr)
        if isinstance(e, ast.EUnary):
            if e.op == "not":
                operand = self.condition(e.operand, local, event)
                return None if operand is None else ir.Unary("not", operand, BOOL)
            operand = self.number(e.operand, local)
            return None if operand is None else ir.Unary("-", operand, operand.type)
        if isinstance(e, ast.EBinary):
            return self.binary(e, local, event)
        return self.call(e, local, event)

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
        n = _constant(exponent)
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
                spans = [x.span for x in exprs]
                span = Span(
                    spans[0].file,
                    spans[0].line,
                    spans[0].col,
                    spans[-1].end_line,
                    spans[-1].end_col,
                )
                dims = " and ".join(
                    dict.fromkeys(describe_type(v.type) for v in values if v.type is not None)
                )
                self.err(span, f"{what} must have one dimension, but they are {dims}")
                return MISMATCH
        return found

    def call(self, e: ast.ECall, local: dict[str, Value], event: bool) -> ir.Expr | None:
        name = e.func.name
        if name not in BUILTIN_FUNCTIONS:
            hint = (
                " (actions are statements, not values)"
                if name in self.scope.actions
                else did_you_mean(name, BUILTIN_FUNCTIONS)
            )
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
        target = self.expr(e.args[0], local)
        if isinstance(target, Opaque):
            return ir.Num(0.0, None)
        ok = isinstance(target, ir.Legs) or (
            isinstance(target, ir.Part | ir.Alias) and target.kind == "contact"
        )
        if not ok:
            if target is not None:
                self.err(e.args[0].span, f"{name}() takes a leg, a role or a contact")
            return None
        assert isinstance(target, ir.Legs | ir.Part | ir.Alias)
        return ir.Event(name, target)

    def want(self, e: ast.ECall, args: list[ir.Expr], dims: tuple[Type, ...], what: str) -> bool:
        for arg, node in zip(args, e.args, strict=True):
            if arg.type is not None and arg.type not in dims:
                self.err(node.span, f"{e.func.name}() takes {what}, not {describe_type(arg.type)}")
                return False
        return True


Rule = Callable[[Elaborator, ast.ECall, list[ir.Expr]], Type | Mismatch]


def _trig(el: Elaborator, e: ast.ECall, args: list[ir.Expr]) -> Type | Mismatch:
    return ONE if el.want(e, args, (ir.ANGLE, ONE), "an angle") else MISMATCH


def _inverse_trig(el: Elaborator, e: ast.ECall, args: list[ir.Expr]) -> Type | Mismatch:
    return ir.ANGLE if el.want(e, args, (ONE,), "a plain number") else MISMATCH


def _plain(el: Elaborator, e: ast.ECall, args: list[ir.Expr]) -> Type | Mismatch:
    return ONE if el.want(e, args, (ONE,), "a plain number") else MISMATCH


def _atan2(el: Elaborator, e: ast.ECall, args: list[ir.Expr]) -> Type | Mismatch:
    same = el.same(args, list(e.args), "the two arguments of atan2()")
    return same if isinstance(same, Mismatch) else ir.ANGLE


def _alike(el: Elaborator, e: ast.ECall, args: list[ir.Expr]) -> Type | Mismatch:
    return el.same(args, list(e.args), f"the arguments of {e.func.name}()")


def _sqrt(el: Elaborator, e: ast.ECall, args: list[ir.Expr]) -> Type | Mismatch:
    t = args[0].type
    if not isinstance(t, tuple):
        return t
    if any(d % 2 for d in t):
        el.err(
            e.args[0].span, f"sqrt() of {describe_type(t)} has no unit: its powers are not all even"
        )
        return MISMATCH
    return (t[0] // 2, t[1] // 2, t[2] // 2, t[3] // 2)


_FUNCTION_RULES: dict[str, Rule] = {
    "sin": _trig, "cos": _trig, "tan": _trig,
    "asin": _inverse_trig, "acos": _inverse_trig, "atan": _inverse_trig, "atan2": _atan2,
    "sqrt": _sqrt, "abs": lambda el, e, a: a[0].type, "sign": lambda el, e, a: ONE,
    "exp": _plain, "log": _plain, "min": _alike, "max": _alike, "clamp": _alike,
}  # fmt: skip


# ------------------------------------------------------------------ helpers
def _combine(a: Type, b: Type, sign: int) -> Type:
    if not isinstance(a, tuple) or not isinstance(b, tuple):
        if a is None and b is None:
            return None
        # a bare 0 times anything is 0 of any dimension
        return None
    return (a[0] + sign * b[0], a[1] + sign * b[1], a[2] + sign * b[2], a[3] + sign * b[3])


def _constant(e: ir.Expr) -> float | None:
    if isinstance(e, ir.Num):
        return e.value
    if isinstance(e, ir.Unary) and e.op == "-":
        inner = _constant(e.operand)
        return None if inner is None else -inner
    if isinstance(e, ir.Binary) and e.op in ("/", "*"):
        a, b = _constant(e.left), _constant(e.right)
        if a is None or b is None or (e.op == "/" and b == 0):
            return None
        return a / b if e.op == "/" else a * b
    return None


def _fits(t: Type, want: Dim) -> bool:
    return t is None or t == want


def describe_type(t: Type) -> str:
    if t == BOOL:
        return "a condition"
    if t is None:
        return "a number of any unit"
    assert isinstance(t, tuple)
    if t == ONE:
        return "a plain number (no unit)"
    word = describe(t)
    if "(" not in word:
        return f"a quantity in {word}"
    return f"{'an' if word[0] in 'aeiou' else 'a'} {word}"


def _unit_advice(want: Dim) -> str:
    return "" if want == ONE else f"; write it with a unit of {describe(want)}"


def _cannot_set(text: str) -> str:
    return (
        f"'{text}' cannot be set; a controller sets actuator inputs: k, b, rest of a spring; "
        "kp, kv, setpoint of a servo; force of a force or torque actuator"
    )


def no_alias_message(leg: str, role: str | None, name: str, aliases: dict[str, str]) -> str:
    what = f"leg '{leg}'" + (f" (in role '{role}')" if role else "")
    members = list(ir.LEG_MEMBERS)
    return (
        f"{what} has no member '{name}'; a leg has {', '.join(members)} and its aliases"
        f"{did_you_mean(name, [*members, *aliases])}"
    )


def _thing_kind(value: ir.Thing) -> str:
    if isinstance(value, ir.Legs):
        return "role" if value.role is not None else "leg"
    return value.kind


def _what(value: Value) -> str:
    if isinstance(value, ir.Legs | ir.Part | ir.Alias):
        return f"a {_KIND_WORDS.get(_thing_kind(value), _thing_kind(value))}"
    return "a number"


def _text(e: ast.Expr) -> str:
    if isinstance(e, ast.EName):
        return e.ident.name
    if isinstance(e, ast.EAttr):
        return f"{_text(e.base)}.{e.attr.name}"
    return "this"
