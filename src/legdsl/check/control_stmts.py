"""Controller statements into the IR: assignments, records, swaps, kinematic solves, and
named actions inlined at each call with their parameters bound to the arguments.

The top layer of the controller checker (on ``control_exprs`` and ``control_names``):
``Elaborator.stmts`` turns a table row's statements into IR statements.
"""

from __future__ import annotations

from legdsl.check.control_depth import MAX_ACTION_DEPTH
from legdsl.check.control_exprs import ExprChecker, fits, gram_for_gravity, unit_advice
from legdsl.check.control_names import Opaque, Value, what_it_is
from legdsl.check.control_words import describe_type, expression_text
from legdsl.check.declared_unit import declared_unit
from legdsl.check.group_torque import one_spring_per_group, whole_torque_per_member
from legdsl.check.hip_holds import misaimed_bodies
from legdsl.check.leg_motion import LegMotionProbe
from legdsl.check.place_servos import PlaceServos, goal_count
from legdsl.check.plain_declared import plain_declared
from legdsl.check.values import defined_by_both, did_you_mean, stdlib_actions
from legdsl.ir import controller as ir
from legdsl.ir.model import NON_NEGATIVE, setting_kind
from legdsl.lang import ast
from legdsl.lang.units import KINDS


class Elaborator(ExprChecker, LegMotionProbe, PlaceServos):
    """Turns a controller's syntax into IR nodes under one ``Scope``; mistakes go to ``diag``."""

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
                self.untyped_write(s, value)
                if value is not None:
                    self.record_types.setdefault(s.name.name, []).append((value.type, s.span))
                    out.append(ir.Record(s.name.name, value, s.span))
            elif isinstance(s, ast.SwapStmt):
                roles = [self.role(ident, local) for ident in (s.first, s.second)]
                if s.first.name == s.second.name and roles[0] is not None:
                    self.err(
                        s.second.span,
                        f"'swap {s.first.name} {s.second.name}' exchanges a role with itself, "
                        "which does nothing; name the two roles to exchange",
                    )
                elif roles[0] is not None and roles[1] is not None:
                    out.append(ir.Swap(roles[0], roles[1], s.span))
            elif isinstance(s, ast.InvokeStmt):
                done = self.invoke(s, local)
                if done is not None:
                    out.append(done)
            elif isinstance(s, ast.PlaceStmt):
                place = self.place(s, local)
                if place is not None:
                    out.append(place)
            elif isinstance(s, ast.EachStmt):
                each = self.each(s, local)
                if each is not None:
                    out.append(each)
        return out

    def untyped_write(self, s: ast.RecordStmt, value: ir.Expr | None) -> None:
        """Keeps a record's write whose value tells no unit (a bare 0, the record itself),
        or None for one that failed, its mistake told (``record_readers.tell_unknown_unit``)."""
        if value is not None and value.type is not None:
            return
        failed = value is None or any(
            isinstance(x, ir.Named) and x.kind == "opaque" for x in ir.leaves(value)
        )
        writes = self.untyped_records.setdefault(s.name.name, [])
        writes.append(None if failed or value is None else (s, value, tuple(self.calls)))
        leaves = ir.leaves(value) if value is not None else ()
        own = [x for x in leaves if isinstance(x, ir.Named) and x.name == s.name.name]
        self.self_reads[s.name.name] = self.self_reads.get(s.name.name, 0) + len(own)

    def each(self, s: ast.EachStmt, local: dict[str, Value]) -> ir.Each | None:
        """``each LEG in GROUP { ... }``: the body checked once, LEG standing for a member of
        GROUP (a role, a leg, or a member itself); lowering repeats it for each member."""
        group = self.lookup(s.group, local)
        if isinstance(group, Opaque):
            self.stmts(s.body, {**local, s.var.name: group})
            return None
        if group is None:
            return None
        if not isinstance(group, ir.Legs):
            self.err(
                s.group.span,
                f"'each' goes through the legs of a role or leg; '{s.group.name}' is "
                f"{what_it_is(group)}",
            )
            return None
        self.each_count += 1
        member = ir.Legs(each=f"{s.var.name}#{self.each_count}", of=group)
        body = self.stmts(s.body, {**local, s.var.name: member})
        for inner in ir.flat(body):
            if isinstance(inner, ir.Record | ir.Swap):
                word = "record" if isinstance(inner, ir.Record) else "swap"
                self.err(
                    inner.span,
                    f"'{word}' inside 'each' would run once per leg of '{s.group.name}'; "
                    f"write it outside the 'each' block",
                )
        assert member.each is not None
        return ir.Each(member.each, group, tuple(body), s.span)

    def assign(self, s: ast.AssignStmt, local: dict[str, Value]) -> list[ir.Stmt]:
        value = self.number(s.value, local)
        head = s.target[0]
        if len(s.target) == 2 and not self._named(head.name, local):
            self.err(head.span, self.not_an_actuator(head.name, local))
            return []
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
            model = self.scope.model
            moving = {j.name for j in model.joints} | {d.name for d in model.dofs}
            if len(s.target) == 2 and head.name in moving and head.name not in local:
                self.err(head.span, self.not_an_actuator(head.name, local))
            else:
                self.err(key.span, _cannot_set(text))
            return []
        assert isinstance(target, ir.Part | ir.Alias)  # actuator_of found an actuator
        kind, rotary = actuator
        settable = ir.ACTUATOR_MEMBERS[kind][0]
        if key.name not in settable:
            readable = ir.ACTUATOR_MEMBERS[kind][1]
            self.err(
                key.span,
                _cannot_set(text)
                if key.name in readable
                else self.no_actuator_member(target, key.name, list(settable + readable)),
            )
            return []
        want = KINDS[setting_kind(key.name, rotary)][0]
        if value is None:
            return []
        self.record_use(value, want)
        told = plain_declared(self.scope.unitless, [value], want)
        if told is not None and not fits(value.type, want):
            self.err(*told)  # the unit left out where it is declared
            return []
        told = declared_unit(self.scope.declared, [value], s.value.span, f"'{text}'", want)
        if told is not None and not fits(value.type, want):
            self.err(*told)  # an input or parameter declared in another unit
            return []
        if not fits(value.type, want):
            self.err(
                s.value.span,
                f"'{text}' is {describe_type(want)}, but the value is {describe_type(value.type)}"
                f"{gram_for_gravity([s.value]) or unit_advice(want)}",
            )
            return []
        if key.name in NON_NEGATIVE and (self.constant_value(value) or 0.0) < 0:
            self.err(
                s.value.span,
                f"'{key.name}' must not be negative, here as in the actuator's line (a negative "
                f"{'stiffness' if key.name in ('k', 'kp') else 'damping'} feeds energy in and "
                "the run diverges); give 0 or more",
            )
            return []
        assert isinstance(target, ir.Part | ir.Alias)
        return [ir.Assign(target, key.name, value, s.span)]

    def _named(self, name: str, local: dict[str, Value]) -> bool:
        """Whether ``name`` names anything here (``lookup`` would find it)."""
        return name in local or name in self.scope.signals or name in self.scope.names

    def not_an_actuator(self, name: str, local: dict[str, Value]) -> str:
        """An unknown name whose setting a statement sets (``ha.kp = ...``): only an actuator's
        can be, so only actuators are suggested; a joint or coordinate of that name is told
        with the actuators on it (or the way to declare one)."""
        model = self.scope.model
        actuators = [a.name for a in model.actuators]
        joint = next((j for j in model.joints if j.name == name), None)
        coords = [d.name for d in joint.dofs] if joint is not None else []
        coords += [d.name for d in model.dofs if d.name == name]
        if coords:
            on = [f"{a.name} (on {a.dof})" for a in model.actuators if a.dof in coords]
            what = "joint" if joint is not None else "coordinate"
            if on:
                return (
                    f"'{name}' is a {what}, and a statement sets an actuator's settings: the "
                    f"actuators on it are {', '.join(on)}; set one of those, as in "
                    f"'{on[0].split(' ')[0]}.kp = ...'"
                )
            return (
                f"'{name}' is a {what} that no actuator drives, and a statement sets an "
                f"actuator's settings: declare one in the creature, as in 'actuator "
                f"{coords[0]}_servo on {coords[0]} servo(kp = ...)', and set it"
            )
        advice = did_you_mean(name, [*actuators, *local])
        shown = ", ".join(actuators[:8]) + (", ..." if len(actuators) > 8 else "")
        known = f"its actuators: {shown}" if actuators else "it has no actuators"
        return (
            f"unknown actuator '{name}': a statement sets an actuator's settings, and creature "
            f"'{model.name}' has no actuator '{name}' ({known}){advice}"
        )

    def invoke(self, s: ast.InvokeStmt, local: dict[str, Value]) -> ir.Do | None:
        action = self.scope.actions.get(s.action.name)
        self.given_to = s  # an unknown name given to it is told as what the action reads
        args = [self.expr(a, local) for a in s.args]
        self.given_to = None
        if action is None:
            self.err(
                s.action.span,
                f"unknown action '{s.action.name}'; define it with 'action {s.action.name}(...) "
                f"{{ ... }}' or 'use' a library that has it"
                f"{library_advice(s.action.name) or did_you_mean(s.action.name, self.scope.actions)}",
            )
            return None
        if isinstance(action, ast.AmbiguousAction):
            what = f"action '{s.action.name}'"
            self.err(s.action.span, defined_by_both(what, action.files, action.distance))
            return None
        if len(s.args) != len(action.params):
            n, params = len(action.params), ", ".join(p.name for p in action.params)
            self.err(
                s.span,
                f"action '{s.action.name}' takes {n} argument{'' if n == 1 else 's'}, got "
                f"{len(s.args)}: write {s.action.name}({params})",
            )
            return None
        if any(a is action for _, a in self.calls):
            self.err(s.action.span, f"action '{s.action.name}' calls itself")
            return None
        if len(self.calls) >= MAX_ACTION_DEPTH:
            outermost = self.calls[0][0]  # the row's call, where the chain can be cut
            self.err(
                outermost.span,
                f"'{outermost.action.name}' calls actions more than {MAX_ACTION_DEPTH} deep, each "
                f"from within the one before ('{s.action.name}' is {len(self.calls) + 1} "
                "deep); write some of their statements out in the action that calls them, or "
                "call them one after another",
            )
            return None
        given = [
            v if v is not None else Opaque(expression_text(a))
            for a, v in zip(s.args, args, strict=True)
        ]

        def check(values: list[Value]) -> list[ir.Stmt]:
            bound = {param.name: value for param, value in zip(action.params, values, strict=True)}
            self.calls.append((s, action))
            try:
                return self.stmts(action.body, bound)
            finally:
                self.calls.pop()

        if self.probing:  # an outer call's argument is being tried: no blame within
            return ir.Do(s.action.name, tuple(check(given)), s.span)
        saved, first = self.snapshot(), len(self.error_spans)
        with self.captured() as found:
            body = check(given)
        if not found.items:
            self.misaimed(s, given, tuple(body))
            return ir.Do(s.action.name, tuple(body), s.span)
        checked, failed = self.snapshot(), self.error_spans[first:]
        self.restore(saved)  # each trial starts where this call did
        key = (s.span, repr(given), repr(sorted(self.scope.records.items())))
        if key not in self.scope.blames:  # the passes that settle records repeat each call
            self.scope.blames[key] = self.blame(given, check, self.error_spans[first])
        blame = self.scope.blames[key]
        if blame is None:
            if self.told_motion(s, action, given, check, key, failed):
                return None  # a leg of the other motion: said at it, the rest dropped
            self.restore(checked)
            self.diag.items += found.items
            return ir.Do(s.action.name, tuple(body), s.span)
        # the argument is at fault: said at it, and the body checked as if it were right
        self.report_blame(s, action, blame)
        self.corrected(given, blame)
        check(given)
        return None

    def misaimed(self, s: ast.InvokeStmt, given: list[Value], body: tuple[ir.Stmt, ...]) -> None:
        """A body argument that a hip the call drives cannot hold (hip_holds), or a group
        role given to a one-leg torque or spring energy (group_torque), told once."""
        if s.span.file != self.scope.user_file:
            return
        call = (s, given, body)
        told = [
            *misaimed_bodies(self.scope, *call),
            *whole_torque_per_member(self.scope, *call),
            *one_spring_per_group(self.scope, *call),
        ]
        for span, message in told:
            if (span, message) not in self._reported_at_call:
                self._reported_at_call.add((span, message))
                self.err(span, message)

    def place(self, s: ast.PlaceStmt, local: dict[str, Value]) -> ir.Place | None:
        """``place LEG at (x = .., z = ..) using SERVO, ..``: a leg, known axes, one servo per goal."""
        legs = self.lookup(s.leg, local)
        opaque = isinstance(legs, Opaque)
        if legs is not None and not opaque and not isinstance(legs, ir.Legs):
            self.err(
                s.leg.span,
                f"'place' moves the foot of a leg or role; '{s.leg.name}' is {what_it_is(legs)}",
            )
            legs = None
        planar = self.scope.model.planar and not opaque
        axes = ("x", "z") if planar else ("x", "y", "z")
        seen: set[str] = set()
        goals: list[ir.Expr] = []
        ok = legs is not None and not opaque
        for name, value in s.goals:
            goal = self.number(value, local)
            if goal is not None:
                self.record_use(goal, ir.LENGTH)
            if goal is not None and not fits(goal.type, ir.LENGTH):
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
        moved: dict[tuple[str, str], str] = {}  # (leg, coordinate) -> the servo that moves it
        for path in s.servos:
            servo = self.path(path, local)
            if servo is None or isinstance(servo, Opaque):
                ok = False
                continue
            actuator = self.actuator_of(servo)
            if actuator is None or actuator[0] != "servo":
                self.err(path[-1].span, self.not_a_servo(path, servo, legs, s))
                ok = False
                continue
            assert isinstance(servo, ir.Part | ir.Alias)
            if isinstance(legs, ir.Legs) and not self.servo_moves_foot(legs, servo, path):
                ok = False
                continue
            if isinstance(legs, ir.Legs) and not self.servo_moves_new_coordinate(
                legs, servo, path, moved
            ):
                ok = False
                continue
            servos.append(servo)
        if len(s.servos) != len(s.goals):
            self.err(s.span, goal_count(s, axes, self.servo_names(legs, s)))
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


def _cannot_set(text: str) -> str:
    return (
        f"'{text}' cannot be set; a controller sets actuator inputs: k, b, rest of a spring; "
        "kp, kv, setpoint of a servo; force of a force or torque actuator"
    )


def library_advice(name: str) -> str:
    """For an unknown action the standard library has: which library, and the line to add."""
    library = stdlib_actions().get(name)
    return (
        f": the standard library {library} has it (add the line 'use {library}')" if library else ""
    )
