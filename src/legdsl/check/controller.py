"""Check controller blocks into the controller IR (``legdsl.ir.controller``).

The declarations (inputs, parameters, signals, roles, paths, actions, the table) are read
here; every expression and statement is resolved and dimension-checked by
``legdsl.check.control_exprs``, once, and the role bindings that the table's swaps reach
are enumerated, so that lowering resolves nothing again. docs/language.md lists for
people what a name can be and which members each kind of thing has.
"""

from __future__ import annotations

import functools
from collections.abc import Collection
from dataclasses import replace

from legdsl.check.control_names import Opaque, Scope, Value
from legdsl.check.control_roles import check_aliases, reachable_bindings
from legdsl.check.control_scan import collect_records, dotted_members, unreached_recorders
from legdsl.check.control_shared import Extension, expand_includes, extend_bases, shared_parts
from legdsl.check.control_stmts import Elaborator
from legdsl.check.control_words import describe_type
from legdsl.check.derived import check_derived
from legdsl.check.local_names import builtin_message, check_local_names
from legdsl.check.paths import check_path
from legdsl.check.record_clash import tell_record_clashes, tell_unrecorded_own
from legdsl.check.record_readers import settle_by_readers, tell_unknown_unit
from legdsl.check.role_legs import role_legs
from legdsl.check.role_overlap import check_one_role_per_leg
from legdsl.check.used_controllers import UsedControllers
from legdsl.check.values import (
    MAX_NAME,
    constant_advice,
    did_you_mean,
    misspelt_unit,
    owning_creature,
    too_long,
    written_unit,
)
from legdsl.ir import controller as ir
from legdsl.ir.controller import Constant, Type
from legdsl.ir.model import Model
from legdsl.ir.paths import PathSpec
from legdsl.lang import ast
from legdsl.lang.errors import Diagnostics, Span
from legdsl.lang.units import out_of_range

# What a controller's own declarations are called in messages.
_DECLARED_KIND: dict[type, str] = {
    ast.InputDecl: "input",
    ast.ParamDecl: "parameter",
    ast.SignalDecl: "signal",
}
# Passes that settle the records' dimensions (a record's value may read records).
_RECORD_PASSES = 4


class ControllerChecker:
    def __init__(
        self,
        decl: ast.ControllerDecl,
        model: Model,
        library: dict[str, ast.ActionDef],
        parts: dict[str, ast.SharedDecl],
        diag: Diagnostics,
        broken_legs: Collection[str] = (),  # declared with a mistake reported at the creature
    ):
        self.decl = decl
        self.items = expand_includes(decl, parts, diag)
        self.model = model
        self.diag = diag
        self.actions = dict(library)
        self.roles: dict[str, tuple[str, ...]] = {}
        self.broken_legs = set(broken_legs)

    def err(self, span: Span, message: str) -> None:
        self.diag.error(span, message)

    def creature_names(self) -> dict[str, Value]:
        m = self.model
        names: dict[str, Value] = {}
        for b in m.bodies:
            names[b.name] = ir.Part("body", b.name)
        for d in m.dofs:
            names[d.name] = ir.Part("coord", d.name)
        for a in m.actuators:
            names[a.name] = ir.Part("actuator", a.name)
        for c in m.contacts:
            names[c.name] = ir.Part("contact", c.name)
        for leg in m.legs:
            names[leg.name] = ir.Legs(leg=leg.name)
        for name in self.broken_legs:  # declared with a mistake reported there: no follow-ons
            names[name] = Opaque(name)
        for name, dim in ir.BUILTIN_VALUES.items():
            names[name] = ir.Named("builtin", name, dim)
        names["com"] = ir.Part("com", "com")
        names["terrain"] = ir.Part("terrain", "terrain")  # no part may take these names
        return names

    def check(self) -> ir.Controller | None:
        d = self.decl
        names = self.creature_names()
        own: dict[str, Span] = {}

        def define(ident: ast.Ident, value: Value) -> bool:
            if ident.name in own:
                self.err(
                    ident.span,
                    f"'{ident.name}' is defined twice in controller '{d.name.name}' (first at {own[ident.name]})",
                )
                return False
            builtin = builtin_message(ident.name)  # 'com' and 'terrain' too
            if builtin is not None:
                self.err(ident.span, builtin)
                return False
            if ident.name in names:
                self.err(
                    ident.span,
                    f"'{ident.name}' is already a name of creature '{self.model.name}'; choose another name",
                )
                return False
            own[ident.name] = ident.span
            names[ident.name] = value
            return True

        inputs: list[Constant] = []
        params: list[Constant] = []
        unitless: dict[str, tuple[str, ast.Expr]] = {}
        constants: dict[str, tuple[str, ast.Expr]] = {}
        signals: dict[str, ast.SignalDecl] = {}
        tables: list[ast.TableDecl] = []
        starts: list[ast.StartDecl] = []
        owned: list[ast.Ident] = []
        paths: list[PathSpec] = []
        shadowed: list[ast.ActionDef] = []  # defined twice: both bodies are checked
        for item in self.items:
            if isinstance(item, ast.InputDecl | ast.ParamDecl):
                constant = self.constant(item.name, item.value)
                kind = "input" if isinstance(item, ast.InputDecl) else "param"
                dim = constant.dim if constant is not None else None
                if define(item.name, ir.Named(kind, item.name.name, dim)) and constant:
                    (inputs if kind == "input" else params).append(constant)
                    constants[item.name.name] = (kind, item.value)
                    if constant.dim == ir.ONE and not constant.unit:  # perhaps a unit left out
                        unitless[item.name.name] = (kind, item.value)
            elif isinstance(item, ast.SignalDecl):
                if define(item.name, Opaque(item.name.name)):
                    del names[item.name.name]  # signals are resolved lazily, by the elaborator
                    signals[item.name.name] = item
            elif isinstance(item, ast.RolesDecl):
                check_one_role_per_leg(item, [leg.name for leg in self.model.legs], self.err)
                for role in item.roles:
                    define(role.name, ir.Legs(role=role.name.name))
                leg_names = [leg.name for leg in self.model.legs]
                self.roles.update(
                    role_legs(item, self.model.name, leg_names, d, self.broken_legs, self.err)
                )
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
            elif isinstance(item, ast.OwnDecl):
                owned += item.names
            elif isinstance(item, ast.PathDecl):
                define(item.name, ir.Part("path", item.name.name))
                spec = (
                    PathSpec(item.name.name, "none")
                    if item.value is None
                    else check_path(item.name.name, item.value, self.diag)
                )
                if spec is not None:
                    paths.append(spec)

        declared = {
            item.name.name: _DECLARED_KIND[type(item)]
            for item in self.items
            if isinstance(item, ast.InputDecl | ast.ParamDecl | ast.SignalDecl)
        }
        # Only the records of what the table can reach are the controller's: a library
        # action nobody calls adds no state and cannot clash with the user's names.
        reachable = self.reachable_actions(tables)
        called = [a for n, a in self.actions.items() if n in reachable]
        records = collect_records(tables, called)
        tell_record_clashes(records, names, declared, own, called, d.name.span, self.err)
        mine = {id(item) for item in self.items if isinstance(item, ast.ActionDef)}
        check_local_names(
            d.name.name, self.model, names, signals, [r for t in tables for r in t.rows],
            [a for a in [*shadowed, *self.actions.values()] if a.name.name in reachable or id(a) in mine],
            d.span.file, self.err,
        )  # fmt: skip
        tell_unrecorded_own(owned, records, declared, d.name.name, self.err)

        if len(d.name.name) > MAX_NAME:
            self.err(d.name.span, too_long("controller", d.name.name))
        if not tables:
            self.err(
                d.name.span,
                f"controller '{d.name.name}' needs a state table: 'table {{ state NAME on EVENT: actions ... }}'",
            )
            return None
        for extra in tables[1:]:
            self.err(extra.span, "a controller has one table")
        rows = tables[0].rows
        seen_states: dict[str, ast.Row] = {}
        for row in rows:
            if row.state.name in seen_states:
                self.err(
                    row.state.span,
                    f"state '{row.state.name}' appears twice in the table (first at "
                    f"{seen_states[row.state.name].state.span}); give each state a name of its own",
                )
                continue
            seen_states[row.state.name] = row
        scope = Scope(self.model, names, self.roles, self.actions, signals, {}, d.span.file)
        scope.unitless, scope.declared = unitless, constants
        # what the table calls: a library action's 'route.ahead_heading' tells nothing here
        scope.dotted = dotted_members((self.items, tuple(called)), lets=scope.lets)
        scope.recorders = unreached_recorders(self.actions, reachable)
        elaborated = self.elaborate(scope, rows, records)
        self.check_unreached(scope, reachable, shadowed)
        if not rows:
            self.err(tables[0].span, "the table has no states")
            return None
        start = rows[0].state.name
        for s in starts[1:]:
            self.err(s.span, "'start' may be given once")
        if starts:
            if starts[0].state.name not in seen_states:
                self.err(
                    starts[0].state.span,
                    f"there is no state '{starts[0].state.name}' to start in: the table has "
                    f"{', '.join(seen_states)}"
                    + (did_you_mean(starts[0].state.name, seen_states) or "; name one of them"),
                )
            else:
                start = starts[0].state.name
        states, signal_ir = elaborated
        bindings, after = reachable_bindings(self.roles, states)
        check_aliases(scope, self.diag, self.actions, bindings, self.last_alias_uses)
        return ir.Controller(
            name=d.name.name,
            inputs=tuple(inputs),
            params=tuple(params),
            signals=signal_ir,
            records=tuple((name, scope.records.get(name)) for name in records),
            states=states,
            start=start,
            bindings=bindings,
            after_entry=tuple(sorted(after.items())),
            span=d.span,
            paths=tuple(paths),
            own=tuple(dict.fromkeys(i.name for i in owned if i.name in records)),
        )

    def elaborate(
        self, scope: Scope, rows: tuple[ast.Row, ...], records: dict[str, Span]
    ) -> tuple[tuple[ir.State, ...], tuple[ir.Signal, ...]]:
        """The states and signals in IR; passes repeat until the records' dimensions settle.

        A record's dimension is that of the values recorded into it, which may read records
        themselves, so the first passes (their mistakes discarded) only learn the records'
        dimensions; the last one reports.
        """
        for _ in range(_RECORD_PASSES):
            trial, trial_states = self.elaborate_pass(scope, rows, self.diag.trial())
            settled = self.record_types(trial, records, report=False)
            # a dimension learned is kept: a value that fails with it (the record compared
            # with a mass in its own definition) tells none, and is reported against it; one
            # that no value tells (a bare 0, the record itself) is the first its uses need
            settled = {
                n: t or scope.records.get(n) or next(iter(trial.record_uses.get(n, [])), None)
                for n, t in settled.items()
            }
            if settled == scope.records:
                break
            scope.records = settled
        # a role a swap makes a group (`one = c, two = (a, b)`) is told as one at its calls
        for binding in reachable_bindings(self.roles, trial_states)[0]:
            for role, legs in binding:
                scope.bound[role] = tuple(dict.fromkeys((*scope.bound.get(role, ()), legs)))
        settle_by_readers(
            scope, lambda d: self.elaborate_pass(scope, rows, d)[0], self.diag.sources
        )
        el, states = self.elaborate_pass(scope, rows, self.diag)
        self.record_types(el, records, report=True)
        self.last_alias_uses = el.alias_uses
        signals = tuple(
            ir.Signal(name, value, scope.signals[name].span)
            for name, value in el.signal_ir.items()
            if value is not None
        )
        return states, signals

    def elaborate_pass(
        self, scope: Scope, rows: tuple[ast.Row, ...], diag: Diagnostics
    ) -> tuple[Elaborator, tuple[ir.State, ...]]:
        el = Elaborator(scope, diag)
        states: list[ir.State] = []
        seen: set[str] = set()
        for row in rows:
            event = el.condition(row.event, {}, event=True)
            body = el.stmts(row.actions, {})
            if row.state.name in seen or event is None:
                continue
            seen.add(row.state.name)
            text = _source_text(self.diag.sources, row.event.span)
            states.append(
                ir.State(row.state.name, event, text, tuple(body), row.span, row.event.span)
            )
        for name in scope.signals:
            el.signal(name)
        return el, tuple(states)

    def record_types(
        self, el: Elaborator, records: dict[str, Span], report: bool
    ) -> dict[str, Type]:
        """Each record's dimension: that of the values recorded into it, which must agree."""
        out: dict[str, Type] = {}
        for name in records:
            found: Type = None
            for t, span in el.record_types.get(name, []):
                if t is None:
                    continue
                if found is None:
                    found = t
                elif t != found and report:
                    el.err(
                        span,
                        f"'record {name}' is given {describe_type(t)} here but {describe_type(found)} elsewhere; "
                        "a record keeps one dimension",
                    )
            out[name] = found
            if found is None and report and el.scope.records.get(name) is None:
                tell_unknown_unit(el, name)  # nor do its uses tell it
        return out

    def check_unreached(
        self, scope: Scope, reachable: set[str], shadowed: list[ast.ActionDef]
    ) -> None:
        """Actions written in this controller that its table never calls: their names are
        still checked. A file-level action, or one of a shared part, is checked only in the
        controllers that call it, which are the ones whose names it may use."""
        own = {id(item) for item in self.decl.items if isinstance(item, ast.ActionDef)}
        every = collect_records([], [*shadowed, *self.actions.values()])
        names = {**{n: ir.Named("record", n, None) for n in every}, **scope.names}
        loose = Scope(
            self.model, names, scope.roles, scope.actions, scope.signals, {}, scope.user_file
        )
        loose.dotted, loose.lets, loose.unitless = scope.dotted, scope.lets, scope.unitless
        loose.declared = scope.declared
        for action in [*shadowed, *self.actions.values()]:
            called = action.name.name in reachable and action is self.actions[action.name.name]
            if called or id(action) not in own:
                continue
            el = Elaborator(loose, self.diag)
            params: dict[str, Value] = {}
            for p in action.params:  # one listed twice is told by check_local_names
                params[p.name] = Opaque(p.name)
            el.stmts(action.body, params)

    def constant(self, name: ast.Ident, expr: ast.Expr) -> Constant | None:
        """Inputs and parameters are constants: a number with a unit, possibly negated."""
        node, sign = expr, 1.0
        while isinstance(node, ast.EUnary) and node.op == "-":
            node, sign = node.operand, -sign
        trouble = (
            out_of_range(node.text, node.quantity.value)
            if isinstance(node, ast.EQuantity)
            else None
        )
        if trouble is not None:
            self.err(node.span, trouble)
            return None
        if isinstance(node, ast.EQuantity):
            q = node.quantity
            unit = "".join(written_unit(node.text).split())
            return Constant(name.name, sign * q.value, q.dim, name.span, unit)
        misspelt = misspelt_unit(node)
        if misspelt is not None:  # '1 N*m/rdd' reads as 1 N*m divided by a name
            self.err(*misspelt)
            return None
        advice = constant_advice(expr)
        self.err(
            advice[0] if advice else expr.span,
            advice[1]
            if advice
            else "an input or parameter is a number with its unit, e.g. '1.5 m/s'; use a "
            "'signal' for an expression",
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
                elif isinstance(s, ast.EachStmt):
                    walk(s.body)

        for t in tables:
            for row in t.rows:
                walk(row.actions)
        return reached


def _source_text(sources: dict[str, str], span: Span) -> str:
    """The text a span covers, on one line (for docstrings in generated code)."""
    text = sources.get(span.file)
    if text is None:
        return ""
    lines = text.split("\n")
    if span.line == span.end_line:
        return lines[span.line - 1][span.col - 1 : span.end_col - 1]
    parts = [lines[span.line - 1][span.col - 1 :], *lines[span.line : span.end_line - 1]]
    parts.append(lines[span.end_line - 1][: span.end_col - 1])
    return " ".join(p.strip() for p in parts)


def check_controllers(
    tree: ast.SourceFile,
    models: list[Model],
    library: list[ast.ActionDef],
    shared: list[ast.SharedDecl],
    diag: Diagnostics,
    broken_legs: dict[str, set[str]] | None = None,
    used: UsedControllers | None = None,
) -> list[Model]:
    """Attach each controller of the file to its creature (``broken_legs``: per creature, the
    legs it declares with a mistake already reported, which its controllers may name)."""
    parts = shared_parts(shared, diag)
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
    attached: dict[str, list[ir.Controller]] = {m.name: [] for m in models}
    seen: dict[str, Span] = {}
    extensions: dict[int, Extension] = {}  # a derived controller's declarations and its base's
    for decl in extend_bases(tree.controllers, diag, parts, used, extensions):
        model = owning_creature(decl, "controller run", tree, models, diag)
        if model is None:
            continue
        key = f"{model.name}/{decl.name.name}"
        if key in seen:
            diag.error(
                decl.name.span,
                f"controller '{decl.name.name}' is defined twice (first at {seen[key]})",
            )
            continue
        seen[key] = decl.name.span
        broken = (broken_legs or {}).get(model.name, set())
        run = functools.partial(_run, model=model, library=lib, parts=parts, broken=broken)
        checked = check_derived(decl, extensions.get(id(decl)), diag, run)
        if checked is not None:
            attached[model.name].append(checked)
    return [replace(m, controllers=tuple(attached[m.name])) for m in models]


def _run(
    decl: ast.ControllerDecl,
    diag: Diagnostics,
    model: Model,
    library: dict[str, ast.ActionDef],
    parts: dict[str, ast.SharedDecl],
    broken: Collection[str],
) -> ir.Controller | None:
    return ControllerChecker(decl, model, library, parts, diag, broken).check()
