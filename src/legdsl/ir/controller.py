"""The controller IR: a controller's declarations and state table with every name resolved.

The checker (``legdsl.check.controller``) builds it; lowering (``legdsl.lower.control``)
reads it and resolves nothing a second time. What it holds:

* every name is a node saying what it is: an input, a parameter, a record, a signal, a
  part of the creature (``Part``), the legs of a role or of one leg (``Legs``), an alias on
  those legs (``Alias``), or a member read from one of them (``Read``);
* every number-valued node carries its dimension (``legdsl.lang.units.Dim``), checked;
  conditions have the type ``BOOL``;
* named actions are inlined where they are called (``Do``), with their parameters
  replaced by the arguments, and ``let`` values substituted where they are used, so that
  a statement means the same thing under every role binding;
* the role bindings that the table's swaps can reach are enumerated here, once.

What members each kind of part has, and their dimensions, is listed here too: it is the
vocabulary that the checker resolves against and that lowering turns into sensors.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field

from legdsl.ir.paths import PathSpec
from legdsl.lang.errors import NOWHERE, Span
from legdsl.lang.units import DIMENSIONLESS, KINDS, Dim

BOOL = "bool"  # the type of a condition
# A node's type: a dimension, BOOL, or None for a value that fits any dimension (a bare 0,
# or an uncalled action's parameter).
Type = Dim | str | None

# What each built-in function of a control law computes on numbers, as the generated code does
# (Python's math; the sign, min and max of a NaN are NaN): the checker folds constants with it,
# and a control law that failed at run time is explained with it.
FUNCTION_VALUES: dict[str, Callable[..., float]] = {
    "sin": math.sin, "cos": math.cos, "tan": math.tan, "asin": math.asin, "acos": math.acos,
    "atan": math.atan, "atan2": math.atan2, "sqrt": math.sqrt, "abs": abs, "exp": math.exp,
    "log": math.log,
    "sign": lambda x: 0.0 if x == 0 else math.copysign(1.0, x) if x == x else math.nan,
    "min": lambda *a: math.nan if any(x != x for x in a) else min(a),
    "max": lambda *a: math.nan if any(x != x for x in a) else max(a),
    "clamp": lambda x, lo, hi: min(max(x, lo), hi),
}  # fmt: skip

LENGTH = KINDS["length"][0]
VELOCITY = KINDS["velocity"][0]
ANGLE = KINDS["angle"][0]
ANGULAR_VELOCITY = KINDS["angular velocity"][0]
TIME = KINDS["time"][0]
ONE = DIMENSIONLESS

LEG_MEMBERS: dict[str, Dim] = {
    "length": LENGTH, "rate": VELOCITY, "touching": ONE, "stance_time": TIME,
    "flight_time": TIME, "foot_x": LENGTH, "foot_y": LENGTH, "foot_z": LENGTH,
    "foot_vx": VELOCITY, "foot_vy": VELOCITY, "foot_vz": VELOCITY,
    "hip_x": LENGTH, "hip_y": LENGTH, "hip_z": LENGTH, "feet_down": ONE,
}  # fmt: skip
BODY_MEMBERS: dict[str, Dim] = {
    "x": LENGTH, "y": LENGTH, "z": LENGTH, "vx": VELOCITY, "vy": VELOCITY, "vz": VELOCITY,
    "roll": ANGLE, "pitch": ANGLE, "yaw": ANGLE, "roll_rate": ANGULAR_VELOCITY,
    "pitch_rate": ANGULAR_VELOCITY, "yaw_rate": ANGULAR_VELOCITY,
}  # fmt: skip
CONTACT_MEMBERS: dict[str, Dim] = {
    "x": LENGTH, "y": LENGTH, "z": LENGTH, "vx": VELOCITY, "vy": VELOCITY, "vz": VELOCITY,
    "touching": ONE,
}  # fmt: skip
COM_MEMBERS: dict[str, Dim] = {
    "x": LENGTH, "y": LENGTH, "z": LENGTH, "vx": VELOCITY, "vy": VELOCITY, "vz": VELOCITY,
}  # fmt: skip
PATH_MEMBERS: dict[str, Dim] = {
    "lateral": LENGTH, "heading": ANGLE, "progress": LENGTH, "length": LENGTH, "x": LENGTH,
    "y": LENGTH, "ahead_x": LENGTH, "ahead_y": LENGTH, "ahead_heading": ANGLE, "given": ONE,
}  # fmt: skip
# The terrain ahead of the centre of mass along the heading (``legdsl.sim.terrain_ahead``).
TERRAIN_MEMBERS: dict[str, Dim] = {
    "ahead_distance": LENGTH, "ahead_height": LENGTH, "ahead_depth": LENGTH,
    "ahead_given": ONE, "height": LENGTH,
}  # fmt: skip
# The model's own geometry and mass properties, read as constants (``thigh.length``): a
# controller never restates what the creature says. Body frame, or the parent body's frame
# for a joint's location (``at``, as the .leg file writes it).
BODY_CONSTANTS: dict[str, Dim] = {
    "length": LENGTH, "mass": KINDS["mass"][0], "com_x": LENGTH, "com_y": LENGTH, "com_z": LENGTH,
}  # fmt: skip
COORD_CONSTANTS: dict[str, Dim] = {"at_x": LENGTH, "at_y": LENGTH, "at_z": LENGTH}
LEG_CONSTANTS: dict[str, Dim] = {"hip_at_x": LENGTH, "hip_at_y": LENGTH, "hip_at_z": LENGTH}
# A kind of part -> its constants: only a body's `length` is its length (a path's `length`
# is a reading of the path, as a leg's is of the leg).
CONSTANTS: dict[str, dict[str, Dim]] = {"body": BODY_CONSTANTS, "coord": COORD_CONSTANTS}
# Members that only a 3D creature has: out of the sagittal plane, or turning out of it.
SPATIAL_MEMBERS = frozenset(
    {"y", "vy", "roll", "yaw", "roll_rate", "yaw_rate", "foot_y", "foot_vy", "hip_y",
     "com_y", "at_y", "hip_at_y"}
)  # fmt: skip
# A coordinate's members: its value and rate, in m or rad by the joint's motion.
COORD_MEMBERS = ("value", "rate")
# An actuator kind -> (settable, read-only) members; dimensions come from
# ``legdsl.ir.model.setting_kind`` (they depend on the joint: linear or rotary).
ACTUATOR_MEMBERS: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = {
    "spring": (("k", "b", "rest"), ("force",)),
    "servo": (("kp", "kv", "setpoint"), ("force",)),
    "force": (("force",), ()),
}
# Names every controller sees, with their dimensions.
BUILTIN_VALUES: dict[str, Dim] = {
    "time": TIME,
    "time_in_state": TIME,
    "pi": ONE,
    "g": KINDS["acceleration"][0],
    "total_mass": KINDS["mass"][0],
}


@dataclass(frozen=True)
class Constant:
    """An input or parameter: its default value in SI units and its dimension."""

    name: str
    value: float
    dim: Dim
    span: Span
    # the unit its default was written in ('deg/m'), which --set advice keeps; spelling, like
    # the span, so left out of fingerprints (the generated code does not depend on it)
    unit: str = field(default="", metadata={"spelling": True})


# ------------------------------------------------------------------ what names stand for
@dataclass(frozen=True)
class Legs:
    """The legs of a role (bound anew by each binding) or of one named leg; or, inside
    ``each VAR in GROUP { ... }``, the one member of ``of`` that the statements are at
    (``each`` names the loop, unique in the controller)."""

    role: str | None = None
    leg: str | None = None
    each: str | None = None
    of: Legs | None = None

    def root(self) -> Legs:
        """The role or leg whose members these are (itself, outside ``each``)."""
        return self if self.of is None else self.of.root()


@dataclass(frozen=True)
class Part:
    """A named part of the creature: a body, contact, coord (a joint coordinate) or actuator,
    the centre of mass (``com``), the terrain ahead (``terrain``), or a path to follow."""

    kind: str
    name: str


@dataclass(frozen=True)
class Alias:
    """A leg's own name for one of its parts, read through a role or leg: one part per leg."""

    legs: Legs
    alias: str
    kind: str  # what the alias names on every leg it can stand for: body, actuator, ...


Thing = Legs | Part | Alias


# ------------------------------------------------------------------ expressions
@dataclass(frozen=True)
class Num:
    value: float
    type: Type


@dataclass(frozen=True)
class Named:
    """An input, parameter, record or signal, or a built-in value (``time``, ``pi``, ``g``...)."""

    kind: str  # input, param, record, signal, builtin; opaque: a name only checked, never lowered
    name: str
    type: Type


@dataclass(frozen=True)
class Read:
    """A member of a thing, as a number: ``active.length``, ``trunk.pitch``, ``com.vx``."""

    thing: Thing
    member: str
    type: Type


@dataclass(frozen=True)
class Unary:
    op: str  # "-" or "not"
    operand: Expr
    type: Type


@dataclass(frozen=True)
class Binary:
    op: str  # + - * / ^ < > <= >= == != and or
    left: Expr
    right: Expr
    type: Type


@dataclass(frozen=True)
class Call:
    """A built-in function (``sin``, ``min``, ``select``...)."""

    func: str
    args: tuple[Expr, ...]
    type: Type


@dataclass(frozen=True)
class Event:
    """``touchdown(X)`` (any of X's feet touches) or ``liftoff(X)`` (none does)."""

    kind: str
    thing: Thing
    type: Type = BOOL


Expr = Num | Named | Read | Unary | Binary | Call | Event


# ------------------------------------------------------------------ statements
@dataclass(frozen=True)
class Assign:
    """``thing.key = value`` on an actuator (or the same alias on each leg of a role)."""

    actuator: Part | Alias
    key: str
    value: Expr
    span: Span


@dataclass(frozen=True)
class Record:
    name: str
    value: Expr
    span: Span


@dataclass(frozen=True)
class Swap:
    first: str  # roles
    second: str
    span: Span


@dataclass(frozen=True)
class Place:
    """A kinematic solve: the servos' setpoints that put each foot of ``legs`` at ``goals``
    (offsets from its own hip along ``axes``)."""

    legs: Legs
    axes: tuple[str, ...]
    goals: tuple[Expr, ...]
    servos: tuple[Part | Alias, ...]
    span: Span


@dataclass(frozen=True)
class Do:
    """A named action, inlined where it was called."""

    action: str
    body: tuple[Stmt, ...]
    span: Span


@dataclass(frozen=True)
class Each:
    """``each VAR in GROUP { ... }``: ``body`` once for each leg of ``group``, where
    ``Legs(each=var)`` stands for that leg (its own members, aliases and hip)."""

    var: str
    group: Legs
    body: tuple[Stmt, ...]
    span: Span


Stmt = Assign | Record | Swap | Place | Do | Each


def flat(body: tuple[Stmt, ...] | list[Stmt]) -> list[Stmt]:
    """Statements with inlined actions and nested ``each`` blocks opened (each block itself
    before its statements)."""
    out: list[Stmt] = []
    for s in body:
        out.append(s)
        if isinstance(s, Do | Each):
            out += flat(s.body)
    return out


def leaves(e: object) -> Iterator[object]:
    """The leaves of an expression (numbers, names, reads, events), left to right; anything
    not an operator or a call is its own leaf."""
    if isinstance(e, Unary):
        yield from leaves(e.operand)
    elif isinstance(e, Binary):
        yield from leaves(e.left)
        yield from leaves(e.right)
    elif isinstance(e, Call):
        for a in e.args:
            yield from leaves(a)
    else:
        yield e


Binding = tuple[tuple[str, tuple[str, ...]], ...]  # role -> legs, sorted by role


@dataclass(frozen=True)
class State:
    name: str
    event: Expr
    event_text: str  # the event as written, for comments in generated code
    body: tuple[Stmt, ...]
    span: Span
    # the event expression's own, which generated code's comments name (the row's is its
    # 'state' keyword); spelling, like the span, so left out of fingerprints
    event_span: Span = field(default=NOWHERE, metadata={"spelling": True})


@dataclass(frozen=True)
class Signal:
    name: str
    value: Expr
    span: Span


@dataclass(frozen=True)
class Controller:
    """A checked controller, every name resolved and every value's dimension known."""

    name: str
    inputs: tuple[Constant, ...]
    params: tuple[Constant, ...]
    signals: tuple[Signal, ...]
    records: tuple[tuple[str, Type], ...]
    states: tuple[State, ...]
    start: str
    # Every role binding the table's swaps reach, the initial one first, and for each
    # (binding while waiting, state index) the binding once that state's swaps are done.
    bindings: tuple[Binding, ...]
    after_entry: tuple[tuple[tuple[int, int], int], ...]
    span: Span
    # paths to follow (``path NAME = ...``); the runtime evaluates them, so they are not
    # part of the generated code (nor of its fingerprint)
    paths: tuple[PathSpec, ...] = ()
    # records a controller taking over from another starts at 0 (``own``); the runtime's, like
    # the paths, so not part of the generated code's fingerprint
    own: tuple[str, ...] = ()

    @property
    def state_names(self) -> tuple[str, ...]:
        return tuple(s.name for s in self.states)

    @property
    def record_names(self) -> tuple[str, ...]:
        return tuple(name for name, _ in self.records)

    def signal(self, name: str) -> Signal:
        return next(s for s in self.signals if s.name == name)
