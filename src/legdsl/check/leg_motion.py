"""Which leg argument of an action call a dimension mistake in the action's body comes from,
when the action reads one of the leg's actuators as the other motion than it is.

An action written for a telescoping leg reads its ``spring`` as sliding (a force along
the leg, its rest a length); a leg whose spring is on a knee or ankle has a rotary one (a
torque, its rest an angle), and the body then fails in dimensions deep inside the action.
When no numeric argument is at fault (control_args), the body is checked again, silently,
with the actuators one alias of a leg argument names read as the other motion (and, for
a rotary one, the call's angles as lengths: a rest or stroke written for the knee; for a
sliding one, the action written for a rotary spring, one length at a time as an angle); if that
removes the mistake, it is told at the leg argument: what the action assumes, what the
leg has, and what to do.
"""

from __future__ import annotations

from collections.abc import Callable

from legdsl.check.control_args import ArgumentProbe, retyped
from legdsl.check.control_names import MotionBlame, Value
from legdsl.check.values import stdlib_name
from legdsl.ir import controller as ir
from legdsl.lang import ast
from legdsl.lang.errors import Span

_SLIDING = "a force along its joint, as a telescoping leg's"
_ROTARY = "a torque, on a hinge such as a knee or ankle"
_EXAMPLE = (
    " (docs/controllers.md lists the library's actions for one; docs/biped.md, \"A biped with "
    'knees", uses them)'
)


def _retyped(args: list[Value], rotary: bool) -> list[list[Value]]:
    """The call's arguments as the leg's motion would have them: for a rotary spring (the
    action written for a sliding one) every angle a length at once (a rest of -40 deg, a
    stroke of 0.1 rad, a gain in rad/m: the radians of any dimension turned to metres); for a
    sliding spring (the action written for a rotary one) one length at a time an angle (the
    rest, not the thigh's and shank's lengths beside it)."""
    if rotary:
        return [[_moved(v, 3, 1) for v in args]]
    return [
        [_moved(v, 1, 3) if k == i else v for k, v in enumerate(args)]
        for i, value in enumerate(args)
        if isinstance(value, ir.Expr) and isinstance(value.type, tuple) and value.type[1]
    ]


def _moved(value: Value, source: int, target: int) -> Value:
    """``value`` with its radians turned to metres (``target`` 1) or its metres to radians
    (``target`` 3); a value without the ``source`` one unchanged."""
    if not (isinstance(value, ir.Expr) and isinstance(value.type, tuple) and value.type[source]):
        return value
    kg, m, s, rad = value.type
    moved = m + rad  # the exponent both take together
    return retyped(value, (kg, moved, s, 0) if target == 1 else (kg, 0, s, moved))


class LegMotionProbe(ArgumentProbe):
    """Mixin for ``Elaborator.invoke``: a leg argument whose actuator is of the other motion."""

    motion_told: set[Span]  # where told_motion said it: an outer call does not tell it again

    def told_motion(
        self,
        s: ast.InvokeStmt,
        action: ast.ActionDef,
        given: list[Value],
        check: Callable[[list[Value]], object],
        key: tuple[Span, str, str],
        failed: list[Span],
    ) -> bool:
        """Whether the call's mistakes (found at ``failed``) come from a leg argument of the
        other motion; if so it is told at the argument. A call written in the standard
        library leaves it to the user's call that passes the leg on."""
        if stdlib_name(s.span.file) is not None or self.motion_told.intersection(failed):
            return False
        if key not in self.scope.motion_blames:  # the passes that settle records repeat calls
            self.scope.motion_blames[key] = self.motion_blame(given, check, failed)
        blame = self.scope.motion_blames[key]
        if blame is None:
            return False
        self.report_motion(s, action, given, blame)
        self.settle_flipped(given, check, blame)
        return True

    def motion_blame(
        self, args: list[Value], check: Callable[[list[Value]], object], failed: list[Span]
    ) -> MotionBlame | None:
        """The one (leg argument, alias) whose actuators, read as the other motion, remove
        the first of the mistakes found (at ``failed``) and make none where there was none:
        a reading that moves the mistake elsewhere (a torque now written to a force, which
        stops the body before its real mistake) does not explain it."""
        used_at, before = failed[0], set(failed)
        self.motions_read = {}
        self._trial(args, check, frozenset())
        read = dict(self.motions_read)
        for retyped_too in (False, True):  # a spring alone before one with its rest retyped
            found: dict[frozenset[str], MotionBlame] = {}  # by the actuators read as the other
            for i, value in enumerate(args):
                legs = self._legs_of(value)
                for alias, target in self.scope.aliases[legs[0]].items() if legs else ():
                    if target not in read:
                        continue  # not an actuator the action reads
                    flip = frozenset(self.scope.aliases[leg].get(alias, "") for leg in legs)
                    if flip in found:
                        continue  # the same leg given twice (a leg and a role): told at the first
                    for trial in _retyped(args, read[target]) if retyped_too else [args]:
                        spans = self._trial(trial, check, flip)
                        if used_at not in spans and before.issuperset(spans):
                            found[flip] = MotionBlame(i, alias, target, read[target])
                            break
            if found:
                return next(iter(found.values())) if len(found) == 1 else None
        return None

    def _legs_of(self, value: Value) -> tuple[str, ...]:
        """The legs a leg or role argument stands for (the role's initial binding)."""
        if not isinstance(value, ir.Legs) or value.of is not None:
            return ()
        if value.leg is not None:
            return (value.leg,)
        return self.scope.roles.get(value.role or "", ())

    def _trial(
        self, args: list[Value], check: Callable[[list[Value]], object], flip: frozenset[str]
    ) -> list[Span]:
        """Where the call's mistakes are with the actuators ``flip`` read as the other motion."""
        first = len(self.error_spans)
        saved = self.snapshot()
        self.probing, self.flipped_motion = True, flip
        try:
            with self.captured():
                check(list(args))
        finally:
            self.flipped_motion = frozenset()
            self.restore(saved)
        return self.error_spans[first:]

    def settle_flipped(
        self, args: list[Value], check: Callable[[list[Value]], object], blame: MotionBlame
    ) -> None:
        """Check the body as if the leg were of the motion it assumes (records get their
        types), its mistakes dropped: they follow from the one told at the argument."""
        legs = self._legs_of(args[blame.index])
        self.flipped_motion = frozenset(
            self.scope.aliases[leg].get(blame.alias, "") for leg in legs
        )
        probing, self.probing = self.probing, True  # no probing of the calls within
        try:
            with self.captured():
                check(list(args))
        finally:
            self.flipped_motion, self.probing = frozenset(), probing

    def report_motion(
        self, s: ast.InvokeStmt, action: ast.ActionDef, given: list[Value], blame: MotionBlame
    ) -> None:
        """At the leg argument: the motion the action assumes, the leg's, and what to do."""
        value = given[blame.index]
        assert isinstance(value, ir.Legs)  # motion_blame tries legs and roles only
        who = f"leg '{self._legs_of(value)[0]}'"
        if value.role is not None:
            who += f" (role '{value.role}')"
        want, have = ("sliding", "rotary") if blame.rotary else ("rotary", "sliding")
        want_how, have_how = (_SLIDING, _ROTARY) if blame.rotary else (_ROTARY, _SLIDING)
        alias = f"'{blame.alias}'"
        self.blamed += 1
        self.motion_told.add(s.args[blame.index].span)
        self.err(
            s.args[blame.index].span,
            f"action '{action.name.name}' is written for a leg whose {alias} is {want} "
            f"({want_how}), but the {alias} of {who}, '{blame.actuator}', is {have} "
            f"({have_how}); write the action for a {have} {alias}"
            f"{_EXAMPLE if blame.rotary else ''} or give the leg a {want} {alias}",
        )
