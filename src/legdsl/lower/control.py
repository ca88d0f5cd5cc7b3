"""Lower a checked controller to sympy: per role binding and per state, what to compute.

Roles (``active``, ``idle``) are names bound to legs or groups of legs and
exchanged by ``swap``. Every binding that the table's swaps can reach is
enumerated here, and each state's code is specialised for each binding, so
the generated module never looks a role up at run time: it only keeps the
index of the current binding.

Semantics of a table row ``state S on EVENT: statements``:

* the machine advances through the rows in order; in state i it tests only
  the event of row i+1 (the last row is followed by the first), as in
  Figure 4 of the paper;
* on entering a state, its ``swap`` statements run first (so the row's other
  statements see the new binding), then its ``record`` statements, once;
* every control tick while the state is active, its ``let`` and assignment
  statements run in order; an actuator keeps the last value it was given.

Named actions are inlined with their parameters replaced by the arguments.
Reading a member of a group of legs averages it over the group (``touching``
is true if any foot touches); writing it writes every leg of the group.
``touchdown(X)`` holds when any of X's feet touches and ``liftoff(X)`` when
none does: as events they are tested only while the machine waits for them.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import sympy
from sympy import Expr, Symbol

from legdsl.check.controller import BUILTIN_FUNCTIONS, LEG_MEMBERS
from legdsl.ir.model import Controller, Model
from legdsl.lang import ast
from legdsl.lang.errors import InternalError, LegError

Binding = tuple[tuple[str, tuple[str, ...]], ...]  # role -> legs, sorted by role


def sensor_symbol(key: str) -> Symbol:
    """``leg.main.length`` -> the symbol ``leg_main_length`` (names in generated code)."""
    return Symbol(key.replace(".", "_"))


@dataclass(frozen=True)
class Legs:
    """A role, a leg or an action parameter bound to one of those: the legs it stands for."""

    legs: tuple[str, ...]


@dataclass(frozen=True)
class Thing:
    """A named part of the creature (body, contact, coord, actuator or com), or a path."""

    kind: str
    name: str


@dataclass(frozen=True)
class Group:
    """The same alias on several legs: reading averages, writing writes all."""

    things: tuple[Thing, ...]


@dataclass(frozen=True)
class Setting:
    actuator: str
    key: str
    value: Expr


@dataclass(frozen=True)
class Place:
    """A kinematic solve: the servos' setpoints such that the leg's foot sits at ``goals`` from its hip."""

    leg: str
    axes: tuple[str, ...]
    goals: tuple[Expr, ...]
    servos: tuple[str, ...]


@dataclass(frozen=True)
class StateBody:
    """What one state does under one binding: once on entry (records), and every tick (settings, places)."""

    records: tuple[tuple[str, Expr], ...]
    settings: tuple[Setting, ...]
    places: tuple[Place, ...] = ()


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


class _Env:
    """Names visible while lowering one row under one binding."""

    def __init__(self, binding: dict[str, tuple[str, ...]], local: dict[str, object] | None = None):
        self.binding = binding
        self.local: dict[str, object] = dict(local or {})


class Lowerer:
    def __init__(self, model: Model, controller: Controller):
        self.model = model
        self.ctl = controller
        self.actions = {a.name.name: a for a in controller.actions}
        self.legs = {leg.name: leg for leg in model.legs}
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
        self.inputs = {c.name for c in controller.inputs}
        self.params = {c.name for c in controller.params}
        self.signals = {s.name.name: s.value for s in controller.signals}
        self.paths = {p.name for p in controller.paths}
        self.sensors: set[str] = set()

    # ------------------------------------------------------------ bindings
    def bindings(self) -> tuple[tuple[Binding, ...], dict[tuple[int, int], int]]:
        """Every role binding reachable through the table's swaps, the initial one first."""
        start = tuple(sorted(self.ctl.roles))
        found: list[Binding] = [start]
        after: dict[tuple[int, int], int] = {}
        i = 0
        while i < len(found):
            for s, row in enumerate(self.ctl.rows):
                binding = dict(found[i])
                for a, b in self._swaps(row.actions, _Env(binding)):
                    binding[a], binding[b] = binding[b], binding[a]
                key = tuple(sorted(binding.items()))
                if key not in found:
                    found.append(key)
                after[(i, s)] = found.index(key)
            i += 1
        return tuple(found), after

    def _swaps(self, stmts: Iterable[ast.Stmt], env: _Env) -> list[tuple[str, str]]:
        out: list[tuple[str, str]] = []
        for s in stmts:
            if isinstance(s, ast.SwapStmt):
                out.append((self._role_name(s.first, env), self._role_name(s.second, env)))
            elif isinstance(s, ast.LetStmt):
                # an action may pass its own `let` on to another action
                env.local[s.name.name] = self.ref(s.value, env)
            elif isinstance(s, ast.InvokeStmt):
                action = self.actions[s.action.name]
                inner = _Env(env.binding, self._bind_params(action, s, env))
                out += self._swaps(action.body, inner)
        return out

    def _role_name(self, ident: ast.Ident, env: _Env) -> str:
        bound = env.local.get(ident.name)
        if isinstance(bound, _RoleName):
            return bound.role
        if ident.name in env.binding:
            return ident.name
        raise InternalError(f"swap of {ident.name}, which is not a role")

    # ------------------------------------------------------------ rows
    def lower(self) -> LoweredController:
        bindings, after = self.bindings()
        events: dict[tuple[int, int], sympy.Basic] = {}
        bodies: dict[tuple[int, int], StateBody] = {}
        for b, binding in enumerate(bindings):
            for s, row in enumerate(self.ctl.rows):
                events[(b, s)] = self.boolean(row.event, _Env(dict(binding)))
                records: list[tuple[str, Expr]] = []
                settings: list[Setting] = []
                places: list[Place] = []
                self.statements(row.actions, _Env(dict(binding)), records, settings, places)
                bodies[(b, s)] = StateBody(tuple(records), tuple(settings), tuple(places))
        return LoweredController(
            name=self.ctl.name,
            creature=self.model.name,
            states=self.ctl.states,
            start=self.ctl.states.index(self.ctl.start),
            bindings=bindings,
            events=events,
            after_entry=after,
            bodies=bodies,
            inputs=tuple((c.name, c.value) for c in self.ctl.inputs),
            params=tuple((c.name, c.value) for c in self.ctl.params),
            records=self.ctl.records,
            sensors=tuple(sorted(self.sensors)),
        )

    def statements(
        self,
        stmts: Iterable[ast.Stmt],
        env: _Env,
        records: list[tuple[str, Expr]],
        settings: list[Setting],
        places: list[Place],
    ) -> None:
        for s in stmts:
            if isinstance(s, ast.SwapStmt):
                continue  # done on entry, before anything else (see bindings())
            if isinstance(s, ast.LetStmt):
                env.local[s.name.name] = self.value(s.value, env)
            elif isinstance(s, ast.RecordStmt):
                records.append((s.name.name, self.value(s.value, env)))
            elif isinstance(s, ast.AssignStmt):
                value = self.value(s.value, env)
                for thing, key in self.targets(s.target, env):
                    settings.append(Setting(thing.name, key, value))
            elif isinstance(s, ast.InvokeStmt):
                action = self.actions[s.action.name]
                inner = _Env(env.binding, self._bind_params(action, s, env))
                self.statements(action.body, inner, records, settings, places)
            elif isinstance(s, ast.PlaceStmt):
                places.extend(self.place(s, env))

    def place(self, s: ast.PlaceStmt, env: _Env) -> list[Place]:
        """One solve per leg of the role (each foot placed from its own hip)."""
        legs = self.name(s.leg, env)
        if not isinstance(legs, Legs):
            raise InternalError(f"place of {s.leg.name}")
        axes = tuple(name.name for name, _ in s.goals)
        if self.model.planar and "y" in axes:
            raise LegError.at(
                s.span,
                f"creature '{self.model.name}' is planar: 'place' can set x and z only, not y "
                "(this action is for 3D creatures)",
            )
        goals = tuple(self.value(value, env) for _, value in s.goals)
        per_leg: list[list[str]] = [[] for _ in legs.legs]
        for path in s.servos:
            for k, (thing, _) in enumerate(
                self.targets((*path, ast.Ident("setpoint", path[-1].span)), env)
            ):
                per_leg[k].append(thing.name)
        return [
            Place(leg, axes, goals, tuple(servos))
            for leg, servos in zip(legs.legs, per_leg, strict=True)
        ]

    def _bind_params(
        self, action: ast.ActionDef, call: ast.InvokeStmt, env: _Env
    ) -> dict[str, object]:
        bound: dict[str, object] = {}
        for param, arg in zip(action.params, call.args, strict=True):
            if isinstance(arg, ast.EName) and arg.ident.name in env.binding:
                bound[param.name] = _RoleName(arg.ident.name)
            elif isinstance(arg, ast.EName) and isinstance(
                env.local.get(arg.ident.name), _RoleName
            ):
                bound[param.name] = env.local[arg.ident.name]
            else:
                bound[param.name] = self.ref(arg, env)
        return bound

    def targets(self, path: tuple[ast.Ident, ...], env: _Env) -> list[tuple[Thing, str]]:
        base: object = self.name(path[0], env)
        for ident in path[1:-1]:
            base = self.member(base, ident.name)
        last = path[-1].name
        things = base.things if isinstance(base, Group) else (base,)
        out = []
        for thing in things:
            if not (isinstance(thing, Thing) and thing.kind == "actuator"):
                raise InternalError(f"assignment to {'.'.join(i.name for i in path)}")
            out.append((thing, last))
        return out

    # ------------------------------------------------------------ expressions
    def value(self, e: ast.Expr, env: _Env) -> Expr:
        result = self.ref(e, env)
        if isinstance(result, Expr):
            return result
        raise InternalError(f"{e} is not a number")

    def boolean(self, e: ast.Expr, env: _Env) -> sympy.Basic:
        result = self.ref(e, env)
        if isinstance(result, sympy.Basic):
            return result
        raise InternalError(f"{e} is not a condition")

    def ref(self, e: ast.Expr, env: _Env) -> object:
        if isinstance(e, ast.EQuantity):
            return sympy.Float(e.quantity.value)
        if isinstance(e, ast.EName):
            return self.name(e.ident, env)
        if isinstance(e, ast.EAttr):
            return self.member(self.ref(e.base, env), e.attr.name)
        if isinstance(e, ast.EUnary):
            operand = self.ref(e.operand, env)
            return -operand if e.op == "-" else sympy.Not(operand)  # type: ignore[operator]
        if isinstance(e, ast.EBinary):
            return _BINARY[e.op](self.ref(e.left, env), self.ref(e.right, env))
        return self.call(e, env)

    def name(self, ident: ast.Ident, env: _Env) -> object:
        n = ident.name
        if n in env.local:
            bound = env.local[n]
            return Legs(env.binding[bound.role]) if isinstance(bound, _RoleName) else bound
        if n in env.binding:
            return Legs(env.binding[n])
        if n in self.legs:
            return Legs((n,))
        if n in self.signals:
            return self.ref(self.signals[n], _Env(env.binding))
        if n in self.paths:
            return Thing("path", n)
        if n in self.inputs:
            return Symbol(f"input_{n}")
        if n in self.params:
            return Symbol(f"param_{n}")
        if n in self.ctl.records:
            return Symbol(f"record_{n}")
        if n in ("time", "time_in_state"):
            if n == "time":
                self.sensors.add("time")
            return Symbol(n)
        if n == "pi":
            return sympy.pi
        if n == "g":
            return sympy.Float(-self.model.gravity[2])
        if n == "total_mass":
            return sympy.Float(self.model.total_mass)
        if n == "com":
            return Thing("com", "com")
        if n in self.kinds:
            return Thing(self.kinds[n], n)
        raise InternalError(f"unresolved name {n}")

    def member(self, base: object, name: str) -> object:
        if isinstance(base, Legs):
            if name in LEG_MEMBERS:
                values = [self.sense(f"leg.{leg}.{name}") for leg in base.legs]
                if name == "touching":
                    return sympy.Max(*values) if len(values) > 1 else values[0]
                return sympy.Add(*values) / len(values)
            things = tuple(
                Thing(self.kinds[self.aliases[leg][name]], self.aliases[leg][name])
                for leg in base.legs
            )
            return things[0] if len(things) == 1 else Group(things)
        if isinstance(base, Group):
            parts = [self.member(t, name) for t in base.things]
            if all(isinstance(p, Expr) for p in parts):
                return sympy.Add(*parts) / len(parts)
            return Group(tuple(p for p in parts if isinstance(p, Thing)))
        if isinstance(base, Thing):
            if base.kind == "com":
                return self.sense(f"com.{name}")
            if base.kind == "actuator":
                return self.sense(f"act.{base.name}.{name}")
            return self.sense(f"{base.kind}.{base.name}.{name}")
        raise InternalError(f"member {name} of {base!r}")

    def sense(self, key: str) -> Symbol:
        self.sensors.add(key)
        return sensor_symbol(key)

    def call(self, e: ast.ECall, env: _Env) -> object:
        name = e.func.name
        if name in ("liftoff", "touchdown"):
            target = self.ref(e.args[0], env)
            flags = self._flags(target)
            if name == "touchdown":
                return sympy.Or(*[f > 0.5 for f in flags])
            return sympy.And(*[f < 0.5 for f in flags])
        if name == "select":
            condition = self.boolean(e.args[0], env)
            return sympy.Piecewise(
                (self.value(e.args[1], env), condition), (self.value(e.args[2], env), True)
            )
        args = [self.value(a, env) for a in e.args]
        if name not in _FUNCTIONS or name not in BUILTIN_FUNCTIONS:
            raise InternalError(f"function {name}")
        return _FUNCTIONS[name](*args)

    def _flags(self, target: object) -> list[Symbol]:
        if isinstance(target, Legs):
            return [self.sense(f"leg.{leg}.touching") for leg in target.legs]
        if isinstance(target, Thing) and target.kind == "contact":
            return [self.sense(f"contact.{target.name}.touching")]
        raise InternalError(f"touchdown/liftoff of {target!r}")


@dataclass(frozen=True)
class _RoleName:
    """An action parameter that was given a role: swaps inside the action exchange that role."""

    role: str


_BINARY = {
    "+": lambda a, b: a + b,
    "-": lambda a, b: a - b,
    "*": lambda a, b: a * b,
    "/": lambda a, b: a / b,
    "^": lambda a, b: a**b,
    "<": lambda a, b: sympy.StrictLessThan(a, b),
    ">": lambda a, b: sympy.StrictGreaterThan(a, b),
    "<=": lambda a, b: sympy.LessThan(a, b),
    ">=": lambda a, b: sympy.GreaterThan(a, b),
    "==": lambda a, b: sympy.Eq(a, b),
    "!=": lambda a, b: sympy.Ne(a, b),
    "and": lambda a, b: sympy.And(a, b),
    "or": lambda a, b: sympy.Or(a, b),
}

_FUNCTIONS = {
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
    "select": lambda c, a, b: sympy.Piecewise((a, c), (b, True)),
}


def lower_controller(model: Model, controller: Controller) -> LoweredController:
    return Lowerer(model, controller).lower()
