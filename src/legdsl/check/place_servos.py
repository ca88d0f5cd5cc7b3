"""The servos of ``place LEG at (..) using SERVO, ..``: one per goal, each a servo on one
of the leg's own joints moving a coordinate of its own; a mistake names what would do
(the servos the leg has on its joints, or the goals and servos that would pair up)."""

from __future__ import annotations

from legdsl.check.control_names import NameResolver, Value, what_it_is
from legdsl.ir import controller as ir
from legdsl.ir.model import Actuator, Leg
from legdsl.lang import ast


class PlaceServos(NameResolver):
    """The checks of a ``place``'s servos, on the controller's ``Scope``."""

    def leg_names(self, legs: ir.Legs) -> list[str]:
        """The legs a place's leg or role stands for, under every binding the table's swaps
        reach."""
        root = legs.root()
        first = self.scope.roles.get(root.role or "", ())
        every = self.scope.bound.get(root.role or "", (first,))
        return [root.leg] if root.leg else list(dict.fromkeys(n for g in every for n in g))

    def leg_servos(self, name: str) -> list[str]:
        """The servos on the joints of leg ``name``, as declared."""
        leg = next(g for g in self.scope.model.legs if g.name == name)
        coords = {d.name for d in self.scope.model.dofs if d.joint in leg.joints}
        return [a.name for a in self.scope.model.actuators if a.kind == "servo" and a.dof in coords]

    def servo_names(self, legs: Value | None, s: ast.PlaceStmt) -> list[str] | str | None:
        """The servos on the joints of the legs ``legs`` stands for that ``s`` does not name
        yet, as it would name them (``m.hip_servo`` through an alias they all have; one leg's
        by their own names), or why there are none; None if the legs are unknown."""
        if not isinstance(legs, ir.Legs):
            return None
        names = [n for n in self.leg_names(legs) if n in self.scope.aliases]
        if not names:
            return None
        servos = {n: self.leg_servos(n) for n in names}
        bare = next((n for n in names if not servos[n]), None)
        if bare is not None:
            return self._no_servo(bare)
        first, leg_text = names[0], s.leg.name
        aliases = self.scope.aliases[first]
        shared = {
            f"{leg_text}.{alias}": target
            for alias, target in aliases.items()
            if all(self.scope.aliases[n].get(alias) in servos[n] for n in names)
        }
        if shared or len(names) == 1:
            named = {  # the servos s names, on the first leg
                aliases.get(p[-1].name) if p[0].name == leg_text else p[-1].name for p in s.servos
            }
            found = shared or {n: n for n in servos[first]}
            return list(dict.fromkeys(k for k, v in found.items() if v not in named))
        return (
            f"name a servo on the legs' joints through an alias each of them has (leg "
            f"'{first}' has {', '.join(servos[first])}: 'alias servo = {servos[first][0]}' in "
            f"leg '{first}', and so in the others, then '{leg_text}.servo')"
        )

    def not_a_servo(
        self, path: tuple[ast.Ident, ...], thing: Value, legs: Value | None, s: ast.PlaceStmt
    ) -> str:
        """What ``place ... using`` is told of a name that is no servo: what it is, and the
        servos on the leg's joints to name instead (or how to declare one)."""
        text = ".".join(i.name for i in path)
        actuator = self.actuator_of(thing)
        kind = "torque" if actuator == ("force", True) else actuator[0] if actuator else ""
        what = f"{article_of(kind)} {kind} actuator" if kind else what_it_is(thing)
        told = (
            f"'place ... using' names servos whose setpoints it sets; '{text}' is {what}, "
            "not a servo"
        )
        spare = self.servo_names(legs, s)
        if spare is None:
            return told
        if isinstance(spare, str):
            return f"{told}; {spare}"
        if not spare:
            return f"{told}; the leg has no other servo on its joints: leave it out, with a goal"
        if len(spare) == 1:
            return f"{told}; name the leg's other servo on its joints, {spare[0]}, instead"
        return f"{told}; name one of the leg's other servos on its joints ({', '.join(spare)})"

    def _no_servo(self, name: str) -> str:
        """How to give leg ``name``, which has no servo on its joints, one."""
        leg = next(g for g in self.scope.model.legs if g.name == name)
        coords = [d.name for d in self.scope.model.dofs if d.joint in leg.joints]
        if not coords:
            return f"leg '{name}' has no joint that moves, so no servo to place its foot"
        taken = {a.name for a in self.scope.model.actuators}
        servo = next(
            n for i in range(len(taken) + 1) if (n := f"{coords[0]}_servo{i or ''}") not in taken
        )
        return (
            f"leg '{name}' has no servo on its joints ({', '.join(leg.joints)}): declare one "
            f"on a coordinate of them, as in 'actuator {servo} on {coords[0]} "
            "servo(kp = ..., kv = ...)'"
        )

    def servos_per_leg(
        self, legs: ir.Legs, servo: ir.Part | ir.Alias
    ) -> list[tuple[Leg, Actuator]]:
        """Each leg a place's leg or role stands for, with the actuator the servo is there:
        under every binding the table's swaps reach (a named servo fits one of them only)."""
        found = []
        for name in self.leg_names(legs):
            if isinstance(servo, ir.Alias):
                actuator_name = self.scope.aliases[name].get(servo.alias)
            else:
                actuator_name = servo.name
            leg = next((g for g in self.scope.model.legs if g.name == name), None)
            actuator = next(
                (a for a in self.scope.model.actuators if a.name == actuator_name), None
            )
            if leg is not None and actuator is not None:
                found.append((leg, actuator))
        return found

    def servo_moves_new_coordinate(
        self,
        legs: ir.Legs,
        servo: ir.Part | ir.Alias,
        path: tuple[ast.Ident, ...],
        moved: dict[tuple[str, str], str],
    ) -> bool:
        """Each servo of a ``place`` moves a coordinate no other of its servos moves: two on
        one coordinate (a 3D leg whose `roll_servo` alias names its pitch servo) would leave
        a goal with nothing to reach it, and the solve would quietly miss it."""
        text = ".".join(i.name for i in path)
        for leg, actuator in self.servos_per_leg(legs, servo):
            before = moved.get((leg.name, actuator.dof))
            moved[(leg.name, actuator.dof)] = text
            if before is not None:
                fix = (
                    f"make the alias '{servo.alias}' of leg '{leg.name}' name a servo on "
                    "another of the leg's coordinates"
                    if isinstance(servo, ir.Alias)
                    else "name a servo on another of the leg's coordinates"
                )
                self.err(
                    path[-1].span,
                    f"'place' moves the foot of leg '{leg.name}' with '{text}' (servo "
                    f"'{actuator.name}', on coordinate '{actuator.dof}'), which '{before}' "
                    f"already moves: each goal needs a servo on its own coordinate; {fix}",
                )
                return False
        return True

    def servo_moves_foot(
        self, legs: ir.Legs, servo: ir.Part | ir.Alias, path: tuple[ast.Ident, ...]
    ) -> bool:
        """A servo of ``place`` turns one of the leg's own joints: the solve moves only those
        (one above the hip moves the hip point too, one elsewhere not the foot at all)."""
        for leg, actuator in self.servos_per_leg(legs, servo):
            name = leg.name
            joint = next(d.joint for d in self.scope.model.dofs if d.name == actuator.dof)
            if joint not in leg.joints:
                fix = (
                    f"make the alias '{servo.alias}' of leg '{name}' name a servo on one of them"
                    if isinstance(servo, ir.Alias)
                    else "name a servo on one of them"
                )
                role = legs.root().role
                swapped = bool(role) and name not in self.scope.roles.get(role or "", ())
                if swapped and not isinstance(servo, ir.Alias):
                    fix += f", or one through an alias of the role{self._servo_alias(leg, role)}"
                self.err(
                    path[-1].span,
                    f"'place' moves the foot of leg '{name}'"
                    + (f" (bound to '{role}' by a 'swap')" if swapped else "")
                    + f" with the servo '{actuator.name}', but it is on joint '{joint}', not "
                    f"one of the leg's joints ({', '.join(leg.joints)}); {fix}",
                )
                return False
        return True

    def _servo_alias(self, leg: Leg, role: str | None) -> str:
        """An alias of ``leg`` naming a servo on its joints, as the role would say it."""
        joints = {d.name for d in self.scope.model.dofs if d.joint in leg.joints}
        servos = {
            a.name for a in self.scope.model.actuators if a.kind == "servo" and a.dof in joints
        }
        alias = next((k for k, v in self.scope.aliases[leg.name].items() if v in servos), None)
        return (
            f" ('{role}.{alias}'), which follows the swap" if alias else ", which follows the swap"
        )


def article_of(word: str) -> str:
    return "an" if word[:1] in "aeiou" else "a"


def goal_count(s: ast.PlaceStmt, axes: tuple[str, ...], servo_names: list[str] | str | None) -> str:
    """``place`` pairs goals with servos, in order: what it is told when they do not pair
    up, with the statement that would (a servo for each goal, or the goals it can reach).
    ``servo_names``: the leg's other servos, as ``PlaceServos.servo_names`` has them."""
    goals = [name.name for name, _ in s.goals]
    servos = [".".join(i.name for i in path) for path in s.servos]
    leg = s.leg.name

    def written(gs: list[str], ss: list[str]) -> str:
        at = ", ".join(f"{g} = ..." for g in gs)
        return f"'place {leg} at ({at}) using {', '.join(ss)}'"

    def many(n: int, word: str, names: list[str]) -> str:
        return f"{n} {word}{'' if n == 1 else 's'} ({', '.join(names)})"

    told = (
        f"'place' needs one servo per goal, in the goals' order: "
        f"{many(len(goals), 'goal', goals)} and {many(len(servos), 'servo', servos)}"
    )
    if len(servos) < len(goals):
        missing = goals[len(servos) :]
        out = f"leave out {'the goal' if len(missing) == 1 else 'the goals'} {', '.join(missing)}"
        if servos:
            out += f", {written(goals[: len(servos)], servos)}"
        spare = servo_names if isinstance(servo_names, list) else ["SERVO"] * len(missing)
        if len(spare) < len(missing):
            other = f"only {', '.join(spare)} for" if spare else "no other servo for"
            return f"{told}; the leg has {other} {', '.join(missing)} on its joints: {out}"
        fix = f"name a servo for {' and '.join(missing)} too, {written(goals, servos + spare[: len(missing)])}"
        return f"{told}; {fix}, or {out}" if servos else f"{told}; {fix}"
    extra = servos[len(goals) :]
    free = [a for a in axes if a not in goals][: len(extra)]
    fix = ""
    if len(free) == len(extra):
        fix = f"give each servo a goal, {written(goals + free, servos)}, or "
    fix += f"leave out {', '.join(extra)}, {written(goals, servos[: len(goals)])}"
    if len(free) < len(extra):
        fix += f" (a place sets at most {len(axes)} goals, {', '.join(axes)})"
    return f"{told}; {fix}"
