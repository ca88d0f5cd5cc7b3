"""Check controller blocks: every name they use must resolve.

What a name in a controller expression can be, and which members (``.x``)
each kind of thing has, is listed here once; docs/language.md repeats it for
people. The meaning of the expressions (their lowering to code) comes later
in the pipeline; this stage guarantees that they refer to real things.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, replace

from legdsl.check.values import ValueChecker, did_you_mean
from legdsl.ir.controller import Constant
from legdsl.ir.model import Controller, Model
from legdsl.ir.paths import DEFAULT_LOOKAHEAD, SHAPES, PathSpec, square_corners
from legdsl.ir.paths import MEMBERS as PATH_MEMBERS
from legdsl.lang import ast
from legdsl.lang.errors import Diagnostics, Span

LEG_MEMBERS = (
    "length", "rate", "touching", "stance_time", "flight_time",
    "foot_x", "foot_y", "foot_z", "foot_vx", "foot_vy", "foot_vz", "hip_x", "hip_y", "hip_z",
)  # fmt: skip
BODY_MEMBERS = (
    "x", "y", "z", "vx", "vy", "vz", "roll", "pitch", "yaw", "roll_rate", "pitch_rate", "yaw_rate",
)  # fmt: skip
CONTACT_MEMBERS = ("x", "y", "z", "vx", "vy", "vz", "touching")
COM_MEMBERS = ("x", "y", "z", "vx", "vy", "vz")
COORD_MEMBERS = ("value", "rate")
ACTUATOR_MEMBERS = {
    "spring": (("k", "b", "rest"), ("force",)),
    "servo": (("kp", "kv", "setpoint"), ("force",)),
    "force": (("force",), ()),
}  # kind -> (settable, read-only)

BUILTIN_VALUES = ("time", "time_in_state", "pi", "g", "total_mass")
# What a controller's own declarations are called in messages.
_DECLARED_KIND: dict[type, str] = {
    ast.InputDecl: "input",
    ast.ParamDecl: "parameter",
    ast.SignalDecl: "signal",
}
# name -> number of arguments (None: any number, at least one)
BUILTIN_FUNCTIONS: dict[str, int | None] = {
    "sin": 1, "cos": 1, "tan": 1, "asin": 1, "acos": 1, "atan": 1, "atan2": 2,
    "sqrt": 1, "abs": 1, "exp": 1, "log": 1, "sign": 1,
    "min": None, "max": None, "clamp": 3, "select": 3,
    "liftoff": 1, "touchdown": 1,
}  # fmt: skip
EVENT_FUNCTIONS = ("liftoff", "touchdown")


@dataclass(frozen=True)
class Ref:
    """What a name or member refers to, as far as checking needs to know."""

    kind: str  # leg, role, body, contact, coord, actuator, com, value, unknown
    detail: str = ""  # actuator kind, or the leg/role name
    settable: bool = False


class ControllerChecker:
    def __init__(
        self,
        decl: ast.ControllerDecl,
        model: Model,
        library: dict[str, ast.ActionDef],
        diag: Diagnostics,
    ):
        self.decl = decl
        self.model = model
        self.diag = diag
        self.actions = dict(library)
        self.global_refs: dict[str, Ref] = {}
        self.leg_aliases = {leg.name: dict(leg.aliases) for leg in model.legs}
        self.roles: dict[str, tuple[str, ...]] = {}

    def err(self, span: Span, message: str) -> None:
        self.diag.error(span, message)

    # ---------------------------------------------------------- scope
    def creature_refs(self) -> dict[str, Ref]:
        m = self.model
        refs: dict[str, Ref] = {}
        for b in m.bodies:
            refs[b.name] = Ref("body", b.name)
        for j in m.joints:
            for d in j.dofs:
                refs[d.name] = Ref("coord", d.name)
        for a in m.actuators:
            refs[a.name] = Ref("actuator", a.kind)
        for c in m.contacts:
            refs[c.name] = Ref("contact", c.name)
        for leg in m.legs:
            refs[leg.name] = Ref("leg", leg.name)
        for name in BUILTIN_VALUES:
            refs[name] = Ref("value")
        refs["com"] = Ref("com")
        return refs

    def check(self) -> Controller | None:
        d = self.decl
        refs = self.creature_refs()
        own: dict[str, Span] = {}

        def define(ident: ast.Ident, ref: Ref) -> None:
            if ident.name in own:
                self.err(
                    ident.span,
                    f"'{ident.name}' is defined twice in controller '{d.name.name}' (first at {own[ident.name]})",
                )
                return
            if ident.name in refs and ident.name not in own:
                self.err(
                    ident.span,
                    f"'{ident.name}' is already a name of creature '{self.model.name}'; choose another name",
                )
                return
            own[ident.name] = ident.span
            refs[ident.name] = ref

        inputs: list[Constant] = []
        params: list[Constant] = []
        signals: list[ast.SignalDecl] = []
        tables: list[ast.TableDecl] = []
        starts: list[ast.StartDecl] = []
        paths: list[PathSpec] = []
        shadowed: list[ast.ActionDef] = []  # defined twice: both bodies are checked
        for item in d.items:
            if isinstance(item, ast.InputDecl | ast.ParamDecl):
                define(item.name, Ref("value"))
                constant = self.constant(item.name, item.value)
                if constant is not None:
                    (inputs if isinstance(item, ast.InputDecl) else params).append(constant)
            elif isinstance(item, ast.SignalDecl):
                define(item.name, Ref("value"))
                signals.append(item)
            elif isinstance(item, ast.RolesDecl):
                for role in item.roles:
                    define(role.name, Ref("role", role.name.name))
                    legs = []
                    for leg in role.legs:
                        if leg.name not in self.leg_aliases:
                            self.err(
                                leg.span,
                                f"unknown leg '{leg.name}'; roles are bound to legs declared with 'leg NAME {{ ... }}'{did_you_mean(leg.name, self.leg_aliases)}",
                            )
                        else:
                            legs.append(leg.name)
                    self.roles[role.name.name] = tuple(legs)
            elif isinstance(item, ast.ActionDef):
                if item.name.name in self.actions and self.actions[item.name.name] is not item:
                    prior = self.actions[item.name.name]
                    if prior.span.file == item.span.file:
                        self.err(
                            item.name.span,
                            f"action '{item.name.name}' is defined twice (first at {prior.name.span})",
                        )
                        shadowed.append(prior)
                self.actions[item.name.name] = item
            elif isinstance(item, ast.TableDecl):
                tables.append(item)
            elif isinstance(item, ast.StartDecl):
                starts.append(item)
            elif isinstance(item, ast.PathDecl):
                define(item.name, Ref("path", item.name.name))
                spec = (
                    PathSpec(item.name.name, "none")
                    if item.value is None
                    else check_path(item.name.name, item.value, self.diag)
                )
                if spec is not None:
                    paths.append(spec)

        declared = {
            item.name.name: _DECLARED_KIND[type(item)]
            for item in d.items
            if isinstance(item, ast.InputDecl | ast.ParamDecl | ast.SignalDecl)
        }
        # Only the records of what the table can reach are the controller's: a library
        # action nobody calls adds no state and cannot clash with the user's names.
        reachable = self.reachable_actions(tables)
        records = self.collect_records(
            tables, [a for n, a in self.actions.items() if n in reachable]
        )
        for name, span in records.items():
            if name not in refs:
                refs[name] = Ref("value")
            elif name in declared:  # two values under one name: the record's was never read
                self.err(
                    span,
                    f"'record {name}' would hide the {declared[name]} '{name}'; choose another name for the record",
                )
            elif refs[name].kind != "value" or name in BUILTIN_VALUES:
                self.err(
                    span,
                    f"'record {name}' would hide the {refs[name].kind} '{name}'; choose another name",
                )
        self.global_refs = refs

        for sig in signals:
            self.number(sig.value, refs, {})
        # Actions the table never calls are still checked, seeing every action's records.
        every = self.collect_records([], [*shadowed, *self.actions.values()])
        unreached = {**{n: Ref("value") for n in every}, **refs}
        for action in [*shadowed, *self.actions.values()]:
            called = action.name.name in reachable and action is self.actions[action.name.name]
            self.action_body(action, refs if called else unreached)

        if not tables:
            self.err(
                d.name.span,
                f"controller '{d.name.name}' needs a state table: 'table {{ state NAME on EVENT: actions ... }}'",
            )
            return None
        for extra in tables[1:]:
            self.err(extra.span, "a controller has one table")
        rows = tables[0].rows
        states: dict[str, ast.Row] = {}
        for row in rows:
            if row.state.name in states:
                self.err(
                    row.state.span,
                    f"state '{row.state.name}' appears twice in the table (first at {states[row.state.name].state.span})",
                )
                continue
            states[row.state.name] = row
        for row in rows:
            self.number(row.event, refs, {}, event=True)
            self.stmts(row.actions, refs, {})
        if not rows:
            self.err(tables[0].span, "the table has no states")
            return None
        start = rows[0].state.name
        for s in starts[1:]:
            self.err(s.span, "'start' may be given once")
        if starts:
            if starts[0].state.name not in states:
                self.err(
                    starts[0].state.span,
                    f"unknown state '{starts[0].state.name}'; the table has {', '.join(states)}{did_you_mean(starts[0].state.name, states)}",
                )
            else:
                start = starts[0].state.name
        used_actions = tuple(sorted(self.actions.values(), key=lambda a: a.name.name))
        return Controller(
            name=d.name.name,
            inputs=tuple(inputs),
            params=tuple(params),
            signals=tuple(signals),
            roles=tuple(self.roles.items()),
            start=start,
            states=tuple(states),
            actions=used_actions,
            rows=rows,
            records=tuple(records),
            span=d.span,
            paths=tuple(paths),
        )

    def constant(self, name: ast.Ident, expr: ast.Expr) -> Constant | None:
        """Inputs and parameters are constants: a number with a unit, possibly negated."""
        node, sign = expr, 1.0
        while isinstance(node, ast.EUnary) and node.op == "-":
            node, sign = node.operand, -sign
        if isinstance(node, ast.EQuantity) and not math.isfinite(node.quantity.value):
            self.err(node.span, f"'{node.text}' is too large a number")
            return None
        if isinstance(node, ast.EQuantity):
            q = node.quantity
            return Constant(name.name, sign * q.value, q.dim, name.span)
        self.err(
            expr.span,
            "an input or parameter is a number with its unit, e.g. '1.5 m/s'; use a 'signal' for an expression",
        )
        return None

    def reachable_actions(self, tables: list[ast.TableDecl]) -> set[str]:
        """The actions the table calls, directly or through other actions."""
        reached: set[str] = set()

        def walk(stmts: tuple[ast.Stmt, ...]) -> None:
            for s in stmts:
                if isinstance(s, ast.InvokeStmt) and s.action.name not in reached:
                    action = self.actions.get(s.action.name)
                    if action is not None:
                        reached.add(s.action.name)
                        walk(action.body)

        for t in tables:
            for row in t.rows:
                walk(row.actions)
        return reached

    def collect_records(
        self, tables: list[ast.TableDecl], actions: Iterable[ast.ActionDef]
    ) -> dict[str, Span]:
        """The names recorded in the table's rows and in these actions' bodies."""
        found: dict[str, Span] = {}

        def walk(stmts: tuple[ast.Stmt, ...]) -> None:
            for s in stmts:
                if isinstance(s, ast.RecordStmt):
                    found.setdefault(s.name.name, s.name.span)

        for t in tables:
            for row in t.rows:
                walk(row.actions)
        for action in actions:
            walk(action.body)
        return found

    def action_body(self, action: ast.ActionDef, refs: dict[str, Ref]) -> None:
        local: dict[str, Ref] = {}
        for p in action.params:
            if p.name in local:
                self.err(p.span, f"parameter '{p.name}' is listed twice")
            local[p.name] = Ref("unknown")
        self.stmts(action.body, refs, local)

    # ---------------------------------------------------------- statements

    def stmts(
        self, stmts: tuple[ast.Stmt, ...], refs: dict[str, Ref], local: dict[str, Ref]
    ) -> None:
        local = dict(local)
        for s in stmts:
            if isinstance(s, ast.AssignStmt):
                self.number(s.value, refs, local)
                ref = self.path(s.target, refs, local)
                if ref is not None and ref.kind != "unknown" and not ref.settable:
                    last = s.target[-1]
                    self.err(
                        last.span,
                        f"'{'.'.join(t.name for t in s.target)}' cannot be set; a controller sets actuator inputs: k, b, rest of a spring; kp, kv, setpoint of a servo; force of a force or torque actuator",
                    )
            elif isinstance(s, ast.SwapStmt):
                for ident in (s.first, s.second):
                    ref = local.get(ident.name) or refs.get(ident.name)
                    if ref is None or ref.kind not in ("role", "unknown"):
                        self.err(
                            ident.span,
                            f"'swap' exchanges two roles; '{ident.name}' is not a role"
                            + did_you_mean(ident.name, self.roles),
                        )
            elif isinstance(s, ast.RecordStmt):
                self.number(s.value, refs, local)
            elif isinstance(s, ast.LetStmt):
                self.number(s.value, refs, local)
                local[s.name.name] = Ref("value")
            elif isinstance(s, ast.InvokeStmt):
                for a in s.args:
                    self.expr(a, refs, local)
                action = self.actions.get(s.action.name)
                if action is None:
                    self.err(
                        s.action.span,
                        f"unknown action '{s.action.name}'; define it with 'action {s.action.name}(...) {{ ... }}' or 'use' a library that has it{did_you_mean(s.action.name, self.actions)}",
                    )
                elif len(action.params) != len(s.args):
                    self.err(
                        s.span,
                        f"action '{s.action.name}' takes {len(action.params)} argument(s), got {len(s.args)}",
                    )
            elif isinstance(s, ast.PlaceStmt):
                self.place(s, refs, local)

    def place(self, s: ast.PlaceStmt, refs: dict[str, Ref], local: dict[str, Ref]) -> None:
        """``place LEG at (x = .., z = ..) using SERVO, ..``: a leg, known axes, one servo per goal."""
        leg = local.get(s.leg.name) or refs.get(s.leg.name)
        if leg is None:
            self.unknown_name(s.leg, refs, local)
        elif leg.kind not in ("leg", "role", "unknown"):
            self.err(
                s.leg.span,
                f"'place' moves the foot of a leg or role; '{s.leg.name}' is a {leg.kind}",
            )
        # Inside an action the leg is a parameter and the action may serve 3D creatures too;
        # a 'y' that reaches a planar creature is reported where it is lowered.
        in_action = leg is not None and leg.kind == "unknown"
        axes = ("x", "z") if self.model.planar and not in_action else ("x", "y", "z")
        seen: set[str] = set()
        for name, value in s.goals:
            self.number(value, refs, local)
            if name.name not in axes:
                self.err(
                    name.span,
                    f"'place' sets the foot's offset from the hip along {' and '.join(axes)}; "
                    f"'{name.name}' is not one of them{did_you_mean(name.name, axes)}",
                )
            elif name.name in seen:
                self.err(name.span, f"'{name.name}' is given twice")
            seen.add(name.name)
        for path in s.servos:
            ref = self.path(path, refs, local)
            if ref is not None and ref.kind not in ("unknown",) and ref.detail != "servo":
                self.err(
                    path[-1].span,
                    f"'place ... using' names servos whose setpoints it sets; "
                    f"'{'.'.join(i.name for i in path)}' is not a servo actuator",
                )
        if len(s.servos) != len(s.goals):
            self.err(
                s.span,
                f"'place' needs one servo per goal: {len(s.goals)} goal(s), {len(s.servos)} servo(s)",
            )

    def path(
        self, idents: tuple[ast.Ident, ...], refs: dict[str, Ref], local: dict[str, Ref]
    ) -> Ref | None:
        first = idents[0]
        ref = local.get(first.name) or refs.get(first.name)
        if ref is None:
            self.unknown_name(first, refs, local)
            return None
        for ident in idents[1:]:
            ref = self.member(ref, ident)
            if ref is None:
                return None
        return ref

    # ---------------------------------------------------------- expressions
    def unknown_name(self, ident: ast.Ident, refs: dict[str, Ref], local: dict[str, Ref]) -> None:
        self.err(
            ident.span, f"unknown name '{ident.name}'{did_you_mean(ident.name, [*refs, *local])}"
        )

    def number(
        self, e: ast.Expr, refs: dict[str, Ref], local: dict[str, Ref], event: bool = False
    ) -> Ref | None:
        """An expression used as a number: a body, leg, path... is not one, its members are."""
        ref = self.expr(e, refs, local, event)
        if ref is not None and ref.kind in _NOT_NUMBERS:
            kind = _KIND_WORDS.get(ref.kind, ref.kind)
            text = _text(e)
            self.err(
                e.span,
                f"'{text}' is a {kind}, not a number: use one of its members, "
                f"as in '{text}.{_MEMBER_EXAMPLES[ref.kind]}'",
            )
            return None
        return ref

    def expr(
        self, e: ast.Expr, refs: dict[str, Ref], local: dict[str, Ref], event: bool = False
    ) -> Ref | None:
        if isinstance(e, ast.EQuantity):
            if not math.isfinite(e.quantity.value):
                self.err(e.span, f"'{e.text}' is too large a number")
            return Ref("value")
        if isinstance(e, ast.EName):
            ref = local.get(e.ident.name) or refs.get(e.ident.name)
            if ref is None:
                self.unknown_name(e.ident, refs, local)
            return ref
        if isinstance(e, ast.EAttr):
            base = self.expr(e.base, refs, local)
            return self.member(base, e.attr) if base is not None else None
        if isinstance(e, ast.EUnary):
            self.number(e.operand, refs, local, event)
            return Ref("value")
        if isinstance(e, ast.EBinary):
            self.number(e.left, refs, local, event)
            self.number(e.right, refs, local, event)
            return Ref("value")
        # a call
        name = e.func.name
        if name not in BUILTIN_FUNCTIONS:
            hint = (
                " (actions are statements, not values)"
                if name in self.actions
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
        if name in EVENT_FUNCTIONS:
            if not event:
                self.err(e.func.span, f"{name}() is an event: it belongs after 'on' in a table row")
            for a in e.args:
                ref = self.expr(a, refs, local)
                if ref is not None and ref.kind not in ("leg", "role", "contact", "unknown"):
                    self.err(a.span, f"{name}() takes a leg, a role or a contact")
            return Ref("value")
        for a in e.args:
            self.number(a, refs, local, event)
        return Ref("value")

    def member(self, base: Ref, attr: ast.Ident) -> Ref | None:
        name = attr.name
        if base.kind == "unknown":
            return Ref("unknown")
        if base.kind in ("leg", "role"):
            legs = (base.detail,) if base.kind == "leg" else self.roles.get(base.detail, ())
            if name in LEG_MEMBERS:
                return Ref("value")
            targets = []
            for leg in legs:
                aliases = self.leg_aliases.get(leg, {})
                if name not in aliases:
                    choices = [*LEG_MEMBERS, *aliases]
                    what = f"leg '{leg}'" + (
                        f" (in role '{base.detail}')" if base.kind == "role" else ""
                    )
                    self.err(
                        attr.span,
                        f"{what} has no member '{name}'; a leg has {', '.join(LEG_MEMBERS)} and its aliases{did_you_mean(name, choices)}",
                    )
                    return None
                targets.append(aliases[name])
            if not targets:
                return Ref("unknown")
            return self.global_refs.get(targets[0], Ref("unknown"))
        table = {
            "path": PATH_MEMBERS,
            "body": BODY_MEMBERS,
            "contact": CONTACT_MEMBERS,
            "com": COM_MEMBERS,
            "coord": COORD_MEMBERS,
        }
        if base.kind in table:
            if name not in table[base.kind]:
                self.err(
                    attr.span,
                    f"a {_KIND_WORDS.get(base.kind, base.kind)} has no member '{name}'; it has {', '.join(table[base.kind])}{did_you_mean(name, table[base.kind])}",
                )
                return None
            return Ref("value")
        if base.kind == "actuator":
            settable, readable = ACTUATOR_MEMBERS[base.detail]
            if name in settable:
                return Ref("value", settable=True)
            if name in readable:
                return Ref("value")
            self.err(
                attr.span,
                f"a {base.detail} actuator has no '{name}'; it has {', '.join(settable + readable)}{did_you_mean(name, settable + readable)}",
            )
            return None
        self.err(attr.span, f"a number has no member '{name}'")
        return None


_KIND_WORDS = {"coord": "joint coordinate", "path": "path", "com": "centre of mass"}
_NOT_NUMBERS = ("body", "leg", "role", "contact", "com", "coord", "actuator", "path")
_MEMBER_EXAMPLES = {
    "body": "z", "leg": "length", "role": "length", "contact": "z", "com": "vx",
    "coord": "value", "actuator": "force", "path": "lateral",
}  # fmt: skip


def _text(e: ast.Expr) -> str:
    if isinstance(e, ast.EName):
        return e.ident.name
    if isinstance(e, ast.EAttr):
        return f"{_text(e.base)}.{e.attr.name}"
    return "this"


_PATH_ARGS = {
    "circle": ("center", "radius", "turn", "lookahead"),
    "square": ("corner", "side", "turn", "lookahead"),
    "polyline": ("lookahead",),
    "polygon": ("lookahead",),
}
_PATH_EXAMPLES = {
    "circle": "circle(center = (0, 5) m, radius = 5 m, turn = left)",
    "square": "square(corner = (0, 0) m, side = 8 m, turn = left)",
}
_PATH_EXAMPLE = (
    "circle(center = (0, 5) m, radius = 5 m, turn = left), polyline((0, 0) m, (10, 0) m, ...), "
    "polygon(...) or square(corner = (0, 0) m, side = 8 m, turn = left)"
)


def check_path(name: str, value: ast.Value, diag: Diagnostics) -> PathSpec | None:
    """``circle(...)``, ``polyline(...)``, ``polygon(...)`` or ``square(...)``, in metres."""
    values = ValueChecker(diag)
    if not isinstance(value, ast.Call):
        diag.error(value.span, f"a path is one of {_PATH_EXAMPLE}")
        return None
    shape = value.func.name
    if shape not in SHAPES:
        diag.error(
            value.func.span,
            f"unknown path shape '{shape}'; a path is one of {_PATH_EXAMPLE}{did_you_mean(shape, SHAPES)}",
        )
        return None
    allowed = _PATH_ARGS[shape]
    ok = True
    given: dict[str, ast.Arg] = {}
    points: list[tuple[float, float]] = []
    for arg in value.args:
        if arg.keyword is None:
            if shape not in ("polyline", "polygon"):
                diag.error(
                    arg.span,
                    f"{shape}() takes {', '.join(k + ' = ...' for k in allowed)}, not a positional argument",
                )
                ok = False
                continue
            p = values.vector(arg.value, "length", 2, "a point of the path")
            if p is None:
                ok = False
            else:
                points.append((p[0], p[1]))
            continue
        key = arg.keyword.name
        if key not in allowed:
            diag.error(
                arg.keyword.span,
                f"{shape}() takes {', '.join(k + ' = ...' for k in allowed)}, not '{key}'"
                + did_you_mean(key, allowed),
            )
            ok = False
        elif key in given:
            diag.error(arg.keyword.span, f"'{key}' is given twice")
            ok = False
        else:
            given[key] = arg
    if not ok:
        return None

    def length(key: str) -> float | None:
        v = values.scalar(given[key].value, "length", f"'{key}'")
        if v is not None and v <= 0:
            diag.error(given[key].value.span, f"'{key}' must be positive, got {v:g} m")
            return None
        return v

    lookahead = DEFAULT_LOOKAHEAD
    if "lookahead" in given:
        look = length("lookahead")
        if look is None:
            return None
        lookahead = look
    if shape in ("polyline", "polygon"):
        least = 2 if shape == "polyline" else 3
        if len(points) < least:
            diag.error(
                value.span,
                f"a {shape} needs at least {least} points, got {len(points)}: write {shape}((0, 0) m, (10, 0) m{', (10, 10) m' if least == 3 else ''})",
            )
            return None
        return PathSpec(name, shape, tuple(points), closed=shape == "polygon", lookahead=lookahead)
    place, size = ("center", "radius") if shape == "circle" else ("corner", "side")
    for key in (place, size):
        if key not in given:
            diag.error(value.span, f"{shape}() needs '{key} = ...', as in {_PATH_EXAMPLES[shape]}")
            return None
    where = values.vector(given[place].value, "length", 2, f"the {place}")
    extent = length(size)
    turn = 1
    if "turn" in given:
        word = given["turn"].value
        if not isinstance(word, ast.NameValue) or word.ident.name not in ("left", "right"):
            diag.error(word.span, "'turn' is left (counter-clockwise) or right (clockwise)")
            return None
        turn = 1 if word.ident.name == "left" else -1
    if where is None or extent is None:
        return None
    center = (where[0], where[1])
    if shape == "circle":
        return PathSpec(
            name, "circle", center=center, radius=extent, turn=turn, lookahead=lookahead
        )
    return PathSpec(
        name, "square", square_corners(center, extent, turn), closed=True, lookahead=lookahead
    )


def check_controllers(
    tree: ast.SourceFile, models: list[Model], library: list[ast.ActionDef], diag: Diagnostics
) -> list[Model]:
    """Attach each controller of the file to its creature."""
    by_name = {m.name: m for m in models}
    lib: dict[str, ast.ActionDef] = {}
    for a in library:
        prior = lib.get(a.name.name)
        if prior is not None and prior.span.file == a.span.file:
            diag.error(
                a.name.span,
                f"action '{a.name.name}' is defined twice (first at {prior.name.span})",
            )
            continue
        lib[a.name.name] = a
    attached: dict[str, list[Controller]] = {m.name: [] for m in models}
    seen: dict[str, Span] = {}
    for decl in tree.controllers:
        if decl.creature is not None:
            model = by_name.get(decl.creature.name)
            if model is None:
                if tree.creatures and decl.creature.name not in {
                    c.name.name for c in tree.creatures
                }:
                    diag.error(
                        decl.creature.span,
                        f"unknown creature '{decl.creature.name}'{did_you_mean(decl.creature.name, by_name)}",
                    )
                continue
        elif len(models) == 1:
            model = models[0]
        else:
            if models:
                diag.error(
                    decl.name.span,
                    "this file has several creatures: say which one, as in 'controller run for biped { ... }'",
                )
            continue
        key = f"{model.name}/{decl.name.name}"
        if key in seen:
            diag.error(
                decl.name.span,
                f"controller '{decl.name.name}' is defined twice (first at {seen[key]})",
            )
            continue
        seen[key] = decl.name.span
        checked = ControllerChecker(decl, model, lib, diag).check()
        if checked is not None:
            attached[model.name].append(checked)
    return [replace(m, controllers=tuple(attached[m.name])) for m in models]
