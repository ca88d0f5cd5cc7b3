"""The syntax tree of a .leg file: frozen dataclasses, each with its source span.

The tree mirrors what was written; meaning (which property a body accepts,
what a name refers to) is given by the checker, which turns it into the model
IR of ``legdsl.ir.model``.

Long: one small frozen dataclass per construct of the grammar, in the grammar's order, so
that the file reads as the grammar's mirror; split, it would be harder to check against it.
"""

from __future__ import annotations

from dataclasses import dataclass

from legdsl.lang.errors import Diagnostic, Span
from legdsl.lang.units import Quantity


@dataclass(frozen=True)
class Ident:
    name: str
    span: Span


# ------------------------------------------------------------------ values
@dataclass(frozen=True)
class Number:
    quantity: Quantity
    text: str
    span: Span


@dataclass(frozen=True)
class NameValue:
    ident: Ident

    @property
    def span(self) -> Span:
        return self.ident.span


@dataclass(frozen=True)
class Neg:
    value: Value
    span: Span


@dataclass(frozen=True)
class Vector:
    items: tuple[Value, ...]
    unit: str | None
    unit_span: Span | None
    span: Span


@dataclass(frozen=True)
class Arg:
    keyword: Ident | None
    value: Value
    span: Span


@dataclass(frozen=True)
class Call:
    func: Ident
    args: tuple[Arg, ...]
    span: Span


@dataclass(frozen=True)
class String:
    text: str
    span: Span


Value = Number | NameValue | Neg | Vector | Call | String


# --------------------------------------------------------------- properties
@dataclass(frozen=True)
class Assign:
    target: Ident
    value: Value
    span: Span


@dataclass(frozen=True)
class Prop:
    """``key value``; the value is one of the forms below."""

    key: Ident
    value: One | Range | Many | Assigns
    span: Span


@dataclass(frozen=True)
class One:
    value: Value
    span: Span


@dataclass(frozen=True)
class Range:
    low: Value
    high: Value
    span: Span


@dataclass(frozen=True)
class Many:
    values: tuple[Value, ...]
    span: Span


@dataclass(frozen=True)
class Assigns:
    items: tuple[Assign, ...]
    span: Span


# ----------------------------------------------------------------- creature
@dataclass(frozen=True)
class AttachFree:
    span: Span


@dataclass(frozen=True)
class AttachFixed:
    at: Value | None
    span: Span


@dataclass(frozen=True)
class AttachJoint:
    parent: Ident
    kind: Ident
    joint: Ident
    at: Value | None
    span: Span


@dataclass(frozen=True)
class BodyDecl:
    name: Ident
    attach: AttachFree | AttachFixed | AttachJoint
    props: tuple[Prop, ...]
    span: Span


@dataclass(frozen=True)
class ActuatorDecl:
    name: Ident
    coordinate: Ident
    kind: Ident
    args: tuple[Arg, ...]
    span: Span


@dataclass(frozen=True)
class ContactDecl:
    name: Ident
    body: Ident
    at: Value | None
    span: Span


@dataclass(frozen=True)
class LegDecl:
    name: Ident
    props: tuple[Prop, ...]
    span: Span


@dataclass(frozen=True)
class BlockDecl:
    name: Ident
    props: tuple[Prop, ...]
    span: Span


@dataclass(frozen=True)
class Flag:
    """``planar`` or ``spatial``."""

    name: str
    span: Span


TemplateItem = BodyDecl | ActuatorDecl | ContactDecl | LegDecl


@dataclass(frozen=True)
class TemplateDecl:
    """``template NAME(P, ...) { ... }``: a part of the tree written once (``check.templates``)."""

    name: Ident
    params: tuple[Ident, ...]
    items: tuple[TemplateItem, ...]
    span: Span


@dataclass(frozen=True)
class InstanceDecl:
    """``instance NAME = TEMPLATE(P = value, ...) [mirror PLANE]``."""

    name: Ident
    template: Ident
    args: tuple[Assign, ...]
    mirror: Ident | None
    span: Span


CreatureItem = (
    Flag | BodyDecl | ActuatorDecl | ContactDecl | LegDecl | BlockDecl | Prop | TemplateDecl
    | InstanceDecl
)  # fmt: skip


@dataclass(frozen=True)
class CreatureDecl:
    name: Ident
    items: tuple[CreatureItem, ...]
    span: Span


# ---------------------------------------------------------------- controller
@dataclass(frozen=True)
class EQuantity:
    quantity: Quantity
    text: str
    span: Span


@dataclass(frozen=True)
class EName:
    ident: Ident

    @property
    def span(self) -> Span:
        return self.ident.span


@dataclass(frozen=True)
class EAttr:
    base: Expr
    attr: Ident
    span: Span


@dataclass(frozen=True)
class ECall:
    func: Ident
    args: tuple[Expr, ...]
    span: Span


@dataclass(frozen=True)
class EUnary:
    op: str  # "-" or "not"
    operand: Expr
    span: Span


@dataclass(frozen=True)
class EBinary:
    op: str  # + - * / ^ < > <= >= == != and or
    left: Expr
    right: Expr
    span: Span


Expr = EQuantity | EName | EAttr | ECall | EUnary | EBinary


@dataclass(frozen=True)
class AssignStmt:
    target: tuple[Ident, ...]
    value: Expr
    span: Span


@dataclass(frozen=True)
class SwapStmt:
    first: Ident
    second: Ident
    span: Span


@dataclass(frozen=True)
class RecordStmt:
    name: Ident
    value: Expr
    span: Span


@dataclass(frozen=True)
class LetStmt:
    name: Ident
    value: Expr
    span: Span


@dataclass(frozen=True)
class InvokeStmt:
    action: Ident
    args: tuple[Expr, ...]
    span: Span


@dataclass(frozen=True)
class PlaceStmt:
    """``place LEG at (x = ..., z = ...) using SERVO, ...``: set servo setpoints so the foot lands there."""

    leg: Ident
    goals: tuple[tuple[Ident, Expr], ...]
    servos: tuple[tuple[Ident, ...], ...]
    span: Span


@dataclass(frozen=True)
class EachStmt:
    """``each LEG in ROLE { ... }``: the statements once per member of ROLE, LEG standing for it."""

    var: Ident
    group: Ident
    body: tuple[Stmt, ...]
    span: Span


Stmt = AssignStmt | SwapStmt | RecordStmt | LetStmt | InvokeStmt | PlaceStmt | EachStmt


@dataclass(frozen=True)
class InputDecl:
    name: Ident
    value: Expr
    span: Span


@dataclass(frozen=True)
class ParamDecl:
    name: Ident
    value: Expr
    span: Span


@dataclass(frozen=True)
class SignalDecl:
    name: Ident
    value: Expr
    span: Span


@dataclass(frozen=True)
class RoleDecl:
    name: Ident
    legs: tuple[Ident, ...]
    span: Span


@dataclass(frozen=True)
class RolesDecl:
    roles: tuple[RoleDecl, ...]
    span: Span


@dataclass(frozen=True)
class PathDecl:
    """``path NAME = SHAPE(...)``: the shape is a creature-style value, checked later."""

    name: Ident
    value: Value | None  # None: ``path NAME`` alone, given on the command line
    span: Span


@dataclass(frozen=True)
class StartDecl:
    state: Ident
    span: Span


@dataclass(frozen=True)
class ActionDef:
    name: Ident
    params: tuple[Ident, ...]
    body: tuple[Stmt, ...]
    span: Span


@dataclass(frozen=True)
class AmbiguousAction(ActionDef):
    """An action that two used files, the same number of 'use's away, both define: neither
    is nearer, so neither wins (an error where it is called)."""

    files: tuple[str, ...] = ()
    distance: int = 1


@dataclass(frozen=True)
class Row:
    state: Ident
    event: Expr
    actions: tuple[Stmt, ...]
    span: Span


@dataclass(frozen=True)
class TableDecl:
    rows: tuple[Row, ...]
    span: Span


@dataclass(frozen=True)
class IncludeDecl:
    """``include gains, posture``: shared parts whose declarations the controller takes."""

    names: tuple[Ident, ...]
    span: Span


@dataclass(frozen=True)
class OwnDecl:
    """``own pitch_trim, speed_trim``: records a controller taking over from another starts at
    0, not at the other's values (``legdsl.sim.switching``)."""

    names: tuple[Ident, ...]
    span: Span


ControllerItem = (
    InputDecl
    | ParamDecl
    | SignalDecl
    | RolesDecl
    | StartDecl
    | ActionDef
    | TableDecl
    | PathDecl
    | IncludeDecl
    | OwnDecl
)
SharedItem = ControllerItem


@dataclass(frozen=True)
class SharedDecl:
    """``shared NAME { ... }``: a controller's items (declarations, actions, roles, a table,
    includes of other parts) for several controllers."""

    name: Ident
    items: tuple[SharedItem, ...]
    span: Span


@dataclass(frozen=True)
class AmbiguousShared(SharedDecl):
    """A shared part that two used files, the same number of 'use's away, both define:
    neither wins (an error where it is included)."""

    files: tuple[str, ...] = ()
    distance: int = 1


@dataclass(frozen=True)
class ControllerDecl:
    name: Ident
    creature: Ident | None
    items: tuple[ControllerItem, ...]
    span: Span
    base: Ident | None = None  # ``extends BASE``: resolved by the checker (check.control_shared)


@dataclass(frozen=True)
class SceneSet:
    """``set NAME = VALUE`` in a scene (an input, a parameter or ACTUATOR.KEY), or
    ``at T set NAME = VALUE`` (an input changed at time T)."""

    target: tuple[Ident, ...]
    value: Value
    at: Value | None
    span: Span


@dataclass(frozen=True)
class SceneSwitch:
    """``at T switch CONTROLLER`` in a scene."""

    controller: Ident
    at: Value | None
    span: Span


@dataclass(frozen=True)
class SceneController:
    """``controller NAME`` in a scene: the controller the run starts with."""

    name: Ident
    span: Span


@dataclass(frozen=True)
class SceneTime:
    """``time T`` in a scene: how long the run lasts."""

    value: Value
    span: Span


@dataclass(frozen=True)
class GaitBand:
    """``CONTROLLER [from V] [to V]`` in a scene's ``gait by speed { ... }``."""

    controller: Ident
    low: Value | None
    high: Value | None
    span: Span


@dataclass(frozen=True)
class SceneGaits:
    """``gait by INPUT { ... }``: the controller chosen by an input's command."""

    input: Ident
    bands: tuple[GaitBand, ...]
    span: Span


SceneItem = SceneSet | SceneSwitch | SceneController | SceneTime | SceneGaits


@dataclass(frozen=True)
class SceneDecl:
    """``scene NAME [for CREATURE] { ... }``: a whole run written in the file (``legdsl run
    FILE --scene NAME``)."""

    name: Ident
    creature: Ident | None
    items: tuple[SceneItem, ...]
    span: Span


@dataclass(frozen=True)
class UseDecl:
    target: str
    span: Span


@dataclass(frozen=True)
class SourceFile:
    path: str
    creatures: tuple[CreatureDecl, ...]
    controllers: tuple[ControllerDecl, ...]
    actions: tuple[ActionDef, ...]
    uses: tuple[UseDecl, ...]
    span: Span
    shared: tuple[SharedDecl, ...] = ()
    scenes: tuple[SceneDecl, ...] = ()
    # Mistakes the parser read past (a misspelt unit), for the checker to report with its own.
    pending: tuple[Diagnostic, ...] = ()
