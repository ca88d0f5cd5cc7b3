"""Names in a controller: what each stands for, and the members of each kind of thing.

The first layer of the controller checker (``control_exprs`` builds on it, then
``control_stmts``): a name is looked up once, in the action's parameters and ``let``
locals, then the controller's and the creature's names, and becomes an IR node; a member
(``active.length``, ``trunk.pitch``, ``active.spring.rest``) is checked against what the
thing has (``legdsl.ir.controller`` lists it) and gets its dimension. Errors inside an
action from another file are reported at the user's call.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from legdsl.check.always_zero import ZeroTest
from legdsl.check.control_scan import given
from legdsl.check.control_words import PLANAR_COUNTERPARTS, SPATIAL_ALIASES, no_alias_message
from legdsl.check.named_by_use import told_by_members
from legdsl.check.unit_hints import number_member
from legdsl.check.values import TRUTHS, article, did_you_mean, place_of, stdlib_name
from legdsl.ir import controller as ir
from legdsl.ir.constants import body_constant, coord_constant, leg_constant
from legdsl.ir.controller import Type
from legdsl.ir.model import Model, setting_kind
from legdsl.lang import ast
from legdsl.lang.errors import Diagnostics, Span
from legdsl.lang.units import KINDS, UNITS, Dim

KIND_WORDS = {"coord": "joint coordinate", "path": "path", "com": "centre of mass",
              "terrain": "terrain ahead"}  # fmt: skip
MEMBER_EXAMPLES = {
    "body": "z", "leg": "length", "role": "length", "contact": "z", "com": "vx",
    "coord": "value", "actuator": "force", "path": "lateral", "terrain": "ahead_distance",
}  # fmt: skip


class Mismatch:
    """Dimensions that do not agree (already reported)."""


MISMATCH = Mismatch()

# A signal is resolved once the signals it names are (``control_depth.signals_used``), so a
# chain of them is checked by recursion, some four calls a signal (a chain of 240 plain
# ones checks): one longer than this is refused where it starts, well before Python's
# recursion limit. (Written out, one of sums is deeper than ``MAX_WRITTEN_DEPTH`` by then.)
MAX_SIGNAL_CHAIN = 100


@dataclass(frozen=True)
class Opaque:
    """A parameter of an action that no table calls: its names are checked, not its meaning."""

    name: str


Value = ir.Expr | ir.Thing | Opaque
UntypedWrite = tuple[ast.RecordStmt, ir.Expr, tuple[tuple[ast.InvokeStmt, ast.ActionDef], ...]]


@dataclass(frozen=True)
class Blame:
    """The argument at fault: its position, the dimensions that would fit, where it is used."""

    index: int
    given: ir.Expr
    fits: tuple[Dim, ...]
    used_at: Span
    # the actuators read, whether they are rotary, and what would fit were they the other motion
    otherwise: tuple[tuple[str, ...], bool, tuple[Dim, ...]] | None = None
    swapped: int | None = None  # the argument given in its place, and it in that one's


@dataclass(frozen=True)
class MotionBlame:
    """A leg argument at fault (leg_motion): the action reads its ``alias``, the actuator
    ``actuator``, as the other motion (rotary or sliding) than it is."""

    index: int
    alias: str
    actuator: str
    rotary: bool


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
    # a call's argument at fault (control_args), by the call, its arguments and the records
    blames: dict[tuple[Span, str, str], Blame | None] = field(init=False, default_factory=dict)
    # a call's leg argument whose actuator is of the other motion (leg_motion), the same way
    motion_blames: dict[tuple[Span, str, str], MotionBlame | None] = field(
        init=False, default_factory=dict
    )
    # name -> the members read of it (``route.lateral``), to tell what an unknown name is
    dotted: dict[str, set[str]] = field(default_factory=dict)
    # record -> the actions the table never calls that record it: an action reading it
    # (``trim_step_side``'s ``lifted``) needs one of them called with it
    recorders: dict[str, tuple[str, ...]] = field(default_factory=dict)
    lets: dict[str, Span] = field(default_factory=dict)  # every 'let NAME', where first given
    # input or parameter declared as a plain number -> its kind and value (plain_declared)
    unitless: dict[str, tuple[str, ast.Expr]] = field(default_factory=dict)
    declared: dict[str, tuple[str, ast.Expr]] = field(default_factory=dict)  # all (declared_unit)
    # role -> each group of legs the table's swaps bind it to, the initial one first
    bound: dict[str, tuple[tuple[str, ...], ...]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.aliases = {leg.name: dict(leg.aliases) for leg in self.model.legs}


@dataclass(frozen=True)
class AliasUse:
    """A role's alias, to be checked on every leg the role is bound to once bindings are known."""

    alias: ir.Alias
    span: Span
    context: tuple[ast.InvokeStmt, ...]


class NameResolver:
    """Resolves names and members under one ``Scope``; mistakes go to ``diag``."""

    def __init__(self, scope: Scope, diag: Diagnostics):
        self.scope = scope
        self.diag = diag
        self.calls: list[tuple[ast.InvokeStmt, ast.ActionDef]] = []
        self.given_to: ast.InvokeStmt | None = None  # the call whose arguments are checked
        self.alias_uses: list[AliasUse] = []
        self.record_types: dict[str, list[tuple[Type, Span]]] = {}
        # record -> its writes that tell no unit: the statement, its value and the calls it
        # is reached through; None for one that failed (record_readers.tell_unknown_unit)
        self.untyped_records: dict[str, list[UntypedWrite | None]] = {}
        self.record_uses: dict[str, list[Dim]] = {}  # record of no known unit -> units used as
        # record -> how often it is read, and read in its own writes that tell no unit
        self.record_reads: dict[str, int] = {}
        self.self_reads: dict[str, int] = {}
        self.signal_ir: dict[str, ir.Expr | None] = {}
        self._signals_open: list[str] = []
        self._depths: dict[int, tuple[ir.Expr, int]] = {}  # control_depth.written_depth's memo
        self._sizes: dict[int, tuple[ir.Expr, int]] = {}  # control_depth.written_size's memo
        self._constants: dict[int, tuple[ir.Expr, float | None]] = {}  # constant_value's memo
        self.zeros = ZeroTest()  # divisors that are 0 in every state
        self.within_expression = False  # checking a statement's expression (ExprChecker)
        self._planar_sites: set[Span] = set()
        self._reported_at_call: set[tuple[Span, str]] = set()
        self.each_count = 0  # names each `each` block, in the order they are checked
        self.error_spans: list[Span] = []  # where each mistake was found, before any move
        # control_args (all of them) and leg_motion (one leg's): actuators read as the other
        # motion than they are (rotary as sliding, sliding as rotary)
        self.flipped_motion: frozenset[str] = frozenset()
        self.motions_read: dict[str, bool] = {}  # actuator -> rotary, as read
        self.motion_told: set[Span] = set()

    # ------------------------------------------------------------ errors
    def err(self, span: Span, message: str) -> None:
        """Report at ``span``, or, inside an action from another file, at the user's call."""
        self.error_spans.append(span)
        site = self._user_site()
        if site is None or span.file == self.scope.user_file:
            self.diag.error(span, message)
            return
        if (site.span, message) in self._reported_at_call:
            return  # one library action reading the same wrong thing in several places
        self._reported_at_call.add((site.span, message))
        action = self.calls[-1][1]
        # the calls between, written in the user's other files: the mistake may be one of them
        after = next(i for i, (c, _) in enumerate(self.calls) if c is site) + 1
        between = [c for c, _ in self.calls[after:] if stdlib_name(c.span.file) is None]
        via = "".join(f", called at {place_of(c.span)}" for c in reversed(between))
        self.diag.error(
            site.span,
            f"{message} (in action '{action.name.name}', {place_of(span)}{via}, called here)",
        )

    def planar_error(self, span: Span, message: str, hint: str) -> None:
        """A 3D-only thing in a planar creature: once per call of a library action (a 3D
        action reads many), else where it is written."""
        site = self._user_site()
        if site is not None:
            if site.span in self._planar_sites:
                return
            self._planar_sites.add(site.span)
            action = self.calls[-1][1].name.name
            hint = f"action '{action}' is for 3D creatures"
            if action in PLANAR_COUNTERPARTS:
                hint += f"; a planar creature's is '{PLANAR_COUNTERPARTS[action]}'"
        self.err(span, f"{message} ({hint})")

    def _user_site(self) -> ast.InvokeStmt | None:
        """The call in the user's file that leads into another file's action, if any."""
        if not self.calls or self.calls[-1][1].span.file == self.scope.user_file:
            return None
        return next(
            (c for c, _ in reversed(self.calls) if c.span.file == self.scope.user_file),
            self.calls[0][0],
        )

    # ------------------------------------------------------------ things and members
    def lookup(
        self, ident: ast.Ident, local: dict[str, Value], report: bool = True, read: str = ""
    ) -> Value | None:
        """What ``ident`` names (``read``: the member read of it here, if any)."""
        if ident.name in local:
            return local[ident.name]
        if ident.name in self.scope.signals:
            return self.signal(ident.name)
        found = self.scope.names.get(ident.name)
        if found is None:
            if report:
                self.err(ident.span, self.unknown_name(ident.name, local, read))
            return None
        if isinstance(found, ir.Named) and found.kind == "record":
            self.record_reads[found.name] = self.record_reads.get(found.name, 0) + 1
            return ir.Named("record", found.name, self.scope.records.get(found.name))
        return found

    def unknown_name(self, name: str, local: dict[str, Value], read: str = "") -> str:
        """An unknown name, with the declaration its use asks for: a path's members ask for
        'path NAME', a body's or a contact's for one of the creature, anything else for a param.
        ``read``: the member read of it here, quoted if it is a path's."""
        let = self.scope.lets.get(name)
        if let is not None and let.file == self.scope.user_file:  # of another row or action
            return (
                f"unknown name '{name}': the 'let {name}' at {let} holds "
                "only in its own row or action, after it; give it again here, or make it a "
                f"'signal {name} = ...' of the controller (computed every tick)"
            )
        recorders = self.scope.recorders.get(name)
        if recorders:  # a param of that name would pass and never change
            by = " or ".join(f"'{a}'" for a in recorders)
            return (
                f"unknown name '{name}': it is recorded by action {by}, which the table never "
                "calls: call one of them too, in the same state (a 'param' of this name would "
                "never change)"
            )
        names = [*self.scope.names, *self.scope.signals, *local]
        passed = given(self.scope.actions, self.given_to, name)
        paths = [
            n for n, v in self.scope.names.items() if isinstance(v, ir.Part) and v.kind == "path"
        ]
        told = told_by_members(
            self.scope.model, name, self.scope.dotted.get(name, set()), passed, read, paths
        )
        if told is not None:
            return told
        if name in UNITS and name not in names:  # '1 rad / m', '2*cm': a unit read as a name
            return (
                f"'{name}' is a unit, not a name: a unit follows its number with no operator "
                f"or space inside it, as in '1 rad/{name}' or '2 {name}'"
            )
        if name in TRUTHS and name not in names:  # 'and True', as Python writes it
            return (
                f"legdsl has no '{name}': a condition is a comparison, as in 'trunk.z > 2 m', "
                "and a switch is a number, as in 'param on = 1'"
            )
        advice = did_you_mean(name, names) or (
            ": not a part of the creature, nor an input, parameter, signal, role, path "
            f"or record of the controller; declare it, as in 'param {name} = ...'"
        )
        return f"unknown name '{name}'{advice}"

    def path(self, idents: tuple[ast.Ident, ...], local: dict[str, Value]) -> Value | None:
        found = self.lookup(idents[0], local)
        if len(idents) > 1 and self._number_given(idents[0], found):
            self._number_for_a_member(idents)
            return None
        for ident in idents[1:]:
            if found is None:
                return None
            found = self.member(found, ident)
        return found

    def _number_given(self, ident: ast.Ident, found: Value | None) -> bool:
        """Whether ``ident`` is a parameter of the action being checked that its call gave a
        number (``relax(3 m, 0 m)``, whose ``leg.spring`` was told "a number has no member
        'spring'", as if the action were wrong)."""
        if not self.calls or found is None:
            return False
        if isinstance(found, Opaque | ir.Legs | ir.Part | ir.Alias):
            return False
        return ident.name in (p.name for p in self.calls[-1][1].params)

    def _number_for_a_member(self, idents: tuple[ast.Ident, ...]) -> None:
        """Told at the argument where the call is the user's, else at the user's call."""
        call, action = self.calls[-1]
        n = [p.name for p in action.params].index(idents[0].name)
        read = ".".join(i.name for i in idents[:2])
        message = (
            f"action '{action.name.name}' reads '{read}' ({place_of(idents[1].span)}), a member "
            f"of its parameter '{idents[0].name}', and {'this argument' if n < len(call.args) else 'it'}"
            " is a number, which has no members: give a leg, a part or a role"
        )
        if call.span.file == self.scope.user_file and n < len(call.args):
            at = call.args[n].span
            if (at, message) not in self._reported_at_call:  # read twice in the action
                self._reported_at_call.add((at, message))
                self.error_spans.append(idents[1].span)
                self.diag.error(at, message)
        else:
            self.err(idents[1].span, message)

    def member(self, base: Value, attr: ast.Ident) -> Value | None:
        name = attr.name
        if isinstance(base, Opaque):
            return base
        if isinstance(base, ir.Legs):
            if name in ir.LEG_MEMBERS:
                return self.read(base, name, ir.LEG_MEMBERS[name], attr.span)
            if name in ir.LEG_CONSTANTS:
                read = self.read(base, name, ir.LEG_CONSTANTS[name], attr.span)
                if read is None or base.leg is None:
                    return read  # a role's legs are known per binding, when it is lowered
                return ir.Num(leg_constant(self.scope.model, base.leg, name), read.type)
            return self.alias(base, attr)
        if isinstance(base, ir.Part | ir.Alias):
            kind = base.kind
            members = self.members_of(base)
            if members is None:
                return None
            if name not in members:
                if kind == "actuator":
                    self.err(attr.span, self.no_actuator_member(base, name, list(members)))
                    return None
                self.err(
                    attr.span,
                    f"a {KIND_WORDS.get(kind, kind)} has no member '{name}'; it has "
                    f"{', '.join(members)}{did_you_mean(name, members)}",
                )
                return None
            read = self.read(base, name, members[name], attr.span)
            if read is None or isinstance(base, ir.Alias) or name not in ir.CONSTANTS.get(kind, {}):
                return read
            return self.constant(base, name, read.type, attr.span)
        self.err(attr.span, number_member(name))
        return None

    def no_actuator_member(self, base: ir.Part | ir.Alias, name: str, members: list[str]) -> str:
        """An actuator lacks ``name``; through a leg's alias (a library action's
        ``leg.spring.k``) the fix is the alias, naming an actuator of a kind that has it."""
        kind, rotary = self.actuator_of(base) or ("force", False)
        if kind == "force" and rotary:
            kind = "torque"  # as the file declares it: torque(...)
        if name == "torque" and "force" in members:  # the member is 'force' on a hinge too
            return (
                f"a {kind} actuator's command is its 'force'"
                f"{' (a torque, in N*m, on a revolute joint)' if rotary else ''}: write '.force' "
                "in place of '.torque'"
            )
        if isinstance(base, ir.Alias):
            kinds = [k for k, (set_, read) in ir.ACTUATOR_MEMBERS.items() if name in set_ + read]
            wanted = " or ".join(f"a {k}" for k in kinds) if kinds else "another"
            return (
                f"'{base.alias}' names '{self.part_of(base).name}', a {kind} actuator, which has "
                f"no '{name}' (it has {', '.join(members)}); make the leg's alias "
                f"'{base.alias}' name {wanted} actuator"
            )
        return (
            f"a {kind} actuator has no '{name}'; it has "
            f"{', '.join(members)}{did_you_mean(name, members)}"
        )

    def read(self, thing: ir.Thing, name: str, dim: Dim, span: Span) -> ir.Read | None:
        if self.scope.model.planar and name in ir.SPATIAL_MEMBERS:
            self.planar_error(
                span,
                f"creature '{self.scope.model.name}' is planar: it has no '{name}'",
                "that member is for 3D creatures",
            )
            return None
        return ir.Read(thing, name, dim)

    def constant(self, part: ir.Part, name: str, dim: Type, span: Span) -> ir.Num | None:
        """A constant of the model, as the number the .leg file gives it."""
        if part.kind == "coord":
            return ir.Num(coord_constant(self.scope.model, part.name, name), dim)
        value = body_constant(self.scope.model, part.name, name)
        if value is None:
            if f"{part.name}.length" not in self.diag.unknown:
                self.err(span, f"body '{part.name}' has no length: give it one with 'length ... m'")
            return None
        return ir.Num(value, dim)

    def alias(self, legs: ir.Legs, attr: ast.Ident) -> Value | None:
        name = attr.name
        root = legs.root()
        leg_names = (
            (root.leg,) if root.leg is not None else self.scope.roles.get(root.role or "", ())
        )
        if not leg_names:
            return Opaque(name)  # a role bound to no legs: reported where it was declared
        first = leg_names[0]
        aliases = self.scope.aliases[first]
        if name not in aliases:
            if self.scope.model.planar and name in SPATIAL_ALIASES:
                self.planar_error(
                    attr.span,
                    f"creature '{self.scope.model.name}' is planar: its legs have no '{name}'",
                    "that alias is the standard library's for a 3D hip",
                )
                return None
            planar = self.scope.model.planar
            self.err(attr.span, no_alias_message(first, root.role, name, aliases, planar))
            return None
        target = self.scope.names[aliases[name]]
        if root.leg is not None:
            return target  # one leg, or a member of one leg: the part itself
        assert isinstance(target, ir.Part)
        alias = ir.Alias(legs, name, target.kind)
        self.alias_uses.append(AliasUse(alias, attr.span, tuple(c for c, _ in self.calls)))
        return alias

    def part_of(self, thing: ir.Part | ir.Alias) -> ir.Part:
        """The part itself, or what the alias names on the first leg of its role."""
        if isinstance(thing, ir.Part):
            return thing
        root = thing.legs.root()
        leg = root.leg or self.scope.roles[root.role or ""][0]
        target = self.scope.names[self.scope.aliases[leg][thing.alias]]
        assert isinstance(target, ir.Part)
        return target

    def actuator_of(self, thing: Value) -> tuple[str, bool] | None:
        """(kind, rotary) of an actuator, or None if ``thing`` is no actuator."""
        if not isinstance(thing, ir.Part | ir.Alias) or thing.kind != "actuator":
            return None
        actuator = next(a for a in self.scope.model.actuators if a.name == self.part_of(thing).name)
        self.motions_read[actuator.name] = actuator.rotary
        return actuator.kind, actuator.rotary != (actuator.name in self.flipped_motion)

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
                **ir.COORD_CONSTANTS,
            }
        return {
            "body": {**ir.BODY_MEMBERS, **ir.BODY_CONSTANTS},
            "contact": ir.CONTACT_MEMBERS,
            "com": ir.COM_MEMBERS,
            "path": ir.PATH_MEMBERS,
            "terrain": ir.TERRAIN_MEMBERS,
        }[part.kind]

    def signal(self, name: str) -> ir.Named | None:
        """A signal, its expression resolved once (in the controller's scope, without locals)."""
        if name in self._signals_open:
            decl = self.scope.signals[name]
            self.err(decl.name.span, f"signal '{name}' is defined in terms of itself")
            return None
        open_ = self._signals_open
        if name not in self.signal_ir and len(open_) >= MAX_SIGNAL_CHAIN:
            self.err(
                self.scope.signals[open_[0]].name.span,
                f"signal '{open_[0]}' is written with a chain of more than {MAX_SIGNAL_CHAIN} "
                f"signals, each with the next ({' -> '.join(open_[:3])} -> ... -> {name}): too "
                "deep to compute as one expression; compute it in fewer steps",
            )
            self.signal_ir[name] = None
        if name not in self.signal_ir:
            self._signals_open.append(name)
            calls, self.calls = self.calls, []
            within, self.within_expression = self.within_expression, False  # a statement's own
            try:
                self.signal_ir[name] = self.number(self.scope.signals[name].value, {})
            finally:
                self.calls = calls
                self.within_expression = within
                self._signals_open.pop()
        value = self.signal_ir[name]
        return None if value is None else ir.Named("signal", name, value.type)

    def number(self, e: ast.Expr, local: dict[str, Value]) -> ir.Expr | None:
        """An expression used as a number (``control_exprs`` defines it)."""
        raise NotImplementedError


def thing_kind(value: ir.Thing) -> str:
    if isinstance(value, ir.Legs):
        return "role" if value.role is not None else "leg"  # a member of a role is one leg
    return value.kind


def what_it_is(value: Value) -> str:
    if isinstance(value, ir.Legs | ir.Part | ir.Alias):
        return f"{article(word := KIND_WORDS.get(thing_kind(value), thing_kind(value)))} {word}"
    return "a number"
