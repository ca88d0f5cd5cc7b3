"""Random control laws for the shipped hopper and biped, drawn here so that every test runs the
same law for the same seed (tests/codegen/test_random_laws.py on both backends,
tests/pipeline/test_random_batches.py as batches, tests/pipeline/test_random_scaling.py scaled):
``law_text(seed)`` is the creature with a random unit-correct controller ``rand``.

Each law is unit-correct by construction: every subtree is generated for a dimension, and only
compatible ones are combined."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from conftest import CREATURES

Dim = tuple[int, int, int, int]  # powers of kg, m, s, rad

PLAIN: Dim = (0, 0, 0, 0)
LENGTH: Dim = (0, 1, 0, 0)
SPEED: Dim = (0, 1, -1, 0)
ANGLE: Dim = (0, 0, 0, 1)
SPIN: Dim = (0, 0, -1, 1)
TIME: Dim = (0, 0, 1, 0)
FORCE: Dim = (1, 1, -2, 0)
TORQUE: Dim = (1, 2, -2, 0)
STIFF: Dim = (1, 0, -2, 0)
DAMP: Dim = (1, 0, -1, 0)
ASTIFF: Dim = (1, 2, -2, -1)
ADAMP: Dim = (1, 2, -1, -1)
MASS: Dim = (1, 0, 0, 0)
ACCEL: Dim = (0, 1, -2, 0)
DIMS = [PLAIN, LENGTH, SPEED, ANGLE, SPIN, TIME, FORCE, TORQUE, STIFF, DAMP, ASTIFF, ADAMP]
DIMS += [MASS, ACCEL]

# What a value of each dimension is near, for numbers that keep a run going for a while.
SCALE = {LENGTH: 0.3, SPEED: 1.0, ANGLE: 0.3, SPIN: 2.0, TIME: 0.2, FORCE: 100.0}
SCALE |= {TORQUE: 20.0, STIFF: 3000.0, DAMP: 20.0, ASTIFF: 150.0, ADAMP: 6.0, MASS: 10.0}
SCALE |= {ACCEL: 9.81}


def _add(a: Dim, b: Dim, sign: int = 1) -> Dim:
    return (a[0] + sign * b[0], a[1] + sign * b[1], a[2] + sign * b[2], a[3] + sign * b[3])


def _scaled(a: Dim, n: int) -> Dim:
    return (a[0] * n, a[1] * n, a[2] * n, a[3] * n)


def unit(d: Dim) -> str:
    """The .leg spelling of a dimension's SI unit ('' for a plain number)."""
    parts = [
        f"{s}^{p}" if p != 1 else s for s, p in zip(("kg", "m", "s", "rad"), d, strict=True) if p
    ]
    return "*".join(parts)


@dataclass
class Creature:
    """What a controller of a shipped creature may read and set, by dimension."""

    name: str
    leaves: dict[Dim, list[str]]
    settable: list[tuple[str, Dim]]
    feet: list[str]  # legs, roles and contacts: touchdown/liftoff
    roles: str
    constants: dict[Dim, list[str]]  # the model's, folded into the code
    legs: list[str]  # legs and roles an action is given
    spatial: bool = False


def _leg_leaves(leg: str, spatial: bool) -> dict[Dim, list[str]]:
    ys = ("x", "y", "z") if spatial else ("x", "z")
    return {
        LENGTH: [f"{leg}.length"] + [f"{leg}.{w}_{a}" for w in ("foot", "hip") for a in ys],
        SPEED: [f"{leg}.rate"] + [f"{leg}.foot_v{a}" for a in ys],
        TIME: [f"{leg}.stance_time", f"{leg}.flight_time"],
        PLAIN: [f"{leg}.touching", f"{leg}.feet_down"],
    }


def _merge(*parts: dict[Dim, list[str]]) -> dict[Dim, list[str]]:
    out: dict[Dim, list[str]] = {}
    for part in parts:
        for d, names in part.items():
            out.setdefault(d, []).extend(names)
    return out


# The actuator inputs a law sets, directly or through a leg's or role's alias.
HOPPER_SETS = [("leg_spring.rest", LENGTH), ("active.spring.rest", LENGTH), ("leg_spring.k", STIFF),
               ("main.spring.b", DAMP), ("hip_servo.setpoint", ANGLE),
               ("active.hip_servo.kp", ASTIFF), ("hip_servo.kv", ADAMP),
               ("hip_motor.force", TORQUE)]  # fmt: skip
BIPED_SETS = [("active.spring.rest", LENGTH), ("leg_r_spring.rest", LENGTH),
              ("idle.spring.k", STIFF), ("leg_l_spring.b", DAMP),
              ("active.hip_servo.setpoint", ANGLE), ("hip_r_roll.setpoint", ANGLE),
              ("idle.yaw_servo.kp", ASTIFF), ("hip_l_pitch.kv", ADAMP),
              ("active.hip_motor.force", TORQUE), ("hip_r_roll_motor.force", TORQUE)]  # fmt: skip

HOPPER = Creature(
    "hopper",
    _merge(
        _leg_leaves("main", False),
        _leg_leaves("active", False),
        {
            LENGTH: ["com.x", "com.z", "body.z", "thigh.x", "toe.z", "leg.value"],
            SPEED: ["com.vx", "com.vz", "body.vx", "toe.vx", "leg.rate"],
            ANGLE: ["body.pitch", "thigh.pitch", "hip.value", "hip_servo.setpoint"],
            SPIN: ["body.pitch_rate", "hip.rate", "shank.pitch_rate"],
            TIME: ["time", "time_in_state"],
            PLAIN: ["toe.touching"],
            FORCE: ["leg_spring.force", "active.spring.force"],
            TORQUE: ["hip_servo.force", "hip_motor.force"],
            STIFF: ["leg_spring.k"],
            DAMP: ["leg_spring.b"],
            ASTIFF: ["hip_servo.kp"],
            ADAMP: ["active.hip_servo.kv"],
        },
        {LENGTH: ["leg_spring.rest"]},
    ),
    HOPPER_SETS,
    ["main", "active", "toe"],
    "roles active = main",
    {
        LENGTH: ["thigh.length", "hip.at_x", "active.hip_at_z", "shank.com_x"],
        PLAIN: ["pi"],
        MASS: ["total_mass", "shank.mass"],
        ACCEL: ["g"],
    },
    ["main", "active"],
)

BIPED = Creature(
    "biped",
    _merge(
        _leg_leaves("left", True),
        _leg_leaves("active", True),
        _leg_leaves("idle", True),
        {
            LENGTH: ["com.x", "com.y", "com.z", "trunk.z", "toe_r.y", "leg_l.value"],
            SPEED: ["com.vx", "com.vy", "com.vz", "trunk.vy", "toe_l.vz", "leg_r.rate"],
            ANGLE: ["trunk.pitch", "trunk.roll", "trunk.yaw", "hip_l_x.value", "hip_r_z.value"],
            SPIN: ["trunk.pitch_rate", "trunk.roll_rate", "trunk.yaw_rate", "hip_l_y.rate"],
            TIME: ["time", "time_in_state"],
            PLAIN: ["toe_l.touching"],
            FORCE: ["leg_l_spring.force", "idle.spring.force"],
            TORQUE: ["hip_r_pitch.force", "active.roll_servo.force"],
            STIFF: ["leg_r_spring.k"],
            DAMP: ["active.spring.b"],
            ASTIFF: ["hip_l_yaw.kp"],
            ADAMP: ["idle.hip_servo.kv"],
        },
    ),
    BIPED_SETS,
    ["left", "active", "idle", "toe_r"],
    "roles active = left, idle = right",
    {
        LENGTH: ["thigh_l.length", "hip_r_y.at_y", "idle.hip_at_y", "shank_r.com_z"],
        PLAIN: ["pi"],
        MASS: ["total_mass", "trunk.mass"],
        ACCEL: ["g"],
    },
    ["left", "right", "active", "idle"],
    spatial=True,
)

# What an action's leg parameter `l` sets: aliases every leg of both creatures has.
THROUGH_LEG = [("l.spring.rest", LENGTH), ("l.spring.k", STIFF), ("l.hip_servo.setpoint", ANGLE)]
THROUGH_LEG += [("l.hip_servo.kv", ADAMP), ("l.hip_motor.force", TORQUE)]


def creature_text(name: str) -> str:
    """The `creature NAME { ... }` block of a shipped file, without its controllers."""
    text = (CREATURES / f"{name}.leg").read_text()
    start = text.index(f"creature {name} {{")
    depth = 0
    for end in range(start, len(text)):
        depth += {"{": 1, "}": -1}.get(text[end], 0)
        if depth == 0 and text[end] == "}":
            return text[start : end + 1]
    raise AssertionError(f"{name}.leg: unbalanced braces")


@dataclass
class Law:
    """A random controller for ``creature``, built from ``rng``'s draws."""

    rng: np.random.Generator
    creature: Creature
    names: dict[Dim, list[str]] = field(default_factory=dict)  # inputs, params, signals...
    lets: dict[Dim, list[str]] = field(default_factory=dict)
    counter: int = 0
    action: tuple[str, Dim] | None = None  # a(l, x): its name and x's dimension

    def pick(self, options: list[str]) -> str:
        return options[int(self.rng.integers(len(options)))]

    def chance(self, p: float) -> bool:
        return bool(self.rng.random() < p)

    def fresh(self, prefix: str) -> str:
        self.counter += 1
        return f"{prefix}{self.counter}"

    def number(self, d: Dim, positive: bool = False) -> str:
        """A number with ``d``'s unit, near the dimension's scale, never 0."""
        value = SCALE.get(d, 1.0) * float(self.rng.choice([0.1, 0.5, 1.0, 1.5, 2.0, 3.0, 0.25]))
        if d == TIME:
            # half a 2 ms control tick more: a whole number of ticks is a tie at that tick
            # (`time_in_state > 0.02 s` fires at the tenth or the eleventh by the last bit),
            # which two runs of the same law scaled apart break differently (docs/scaling.md)
            value += 0.001
        if not positive and self.chance(0.3):
            value = -value
        return _num(value, d)

    def sensor(self, d: Dim) -> str | None:
        """A name of dimension ``d`` that changes as the creature moves, if there is one."""
        options = self.creature.leaves.get(d, []) + self.names.get(d, []) + self.lets.get(d, [])
        return self.pick(options) if options else None

    def moving(self, d: Dim) -> str:
        """A value of ``d`` that is not a constant (a sensor, or a number times one)."""
        name = self.sensor(d)
        if name is not None and self.chance(0.8):
            return name
        plain = self.pick(
            ["(com.z / 1 m)", "(com.z / 1 m)", "(1 + time / 1 s)", "(com.vx / 1 m*s^-1)"]
        )
        return f"({self.number(d)} * {plain})" if d != PLAIN else plain

    def leaf(self, d: Dim) -> tuple[str, bool]:
        if self.chance(0.3):
            constants = self.creature.constants.get(d, [])
            if constants and self.chance(0.3):
                return self.pick(constants), True
            return ("0" if self.chance(0.05) else self.number(d)), True
        return self.moving(d), False

    def unsafe(self, arg: tuple[str, bool], d: Dim, guard: str = "") -> str:
        """``arg`` for a function with a domain: a constant one gets a moving term, so the
        checker (which refuses a constant outside the domain) leaves it to the run. Mostly
        kept inside the domain (``guard``: "positive", or "unit" for -1 to 1), so that most
        runs go on; the others stop on a domain error, alike on both backends."""
        text, const = arg
        text = f"({text} + {self.moving(d)})" if const else text
        if guard == "positive" and self.chance(0.75):
            return f"(abs({text}) + {self.number(d, positive=True)})"
        if guard == "unit" and self.chance(0.75):
            return f"clamp({text}, -1, 1)"
        return text

    def expr(self, d: Dim, depth: int) -> tuple[str, bool]:
        if depth <= 0 or self.chance(0.25):
            return self.leaf(d)
        e = depth - 1
        kind = self.pick(
            ["add", "add", "mul", "div", "neg", "abs", "minmax", "clamp", "select", "sqrt", "pow"]
            + (["plainfn"] * 4 + ["ratio"] * 2 if d == PLAIN else [])
            + (["invtrig"] * 3 if d == ANGLE else [])
        )
        if kind == "add":
            (a, ca), (b, cb) = self.expr(d, e), self.expr(d, e)
            op = self.pick(["+", "-"]) if a != b else "+"  # x - x: 0, never a divisor
            return f"({a} {op} {b})", ca and cb
        if kind in ("mul", "div"):
            other = self.pick(DIMS) if self.chance(0.6) else PLAIN
            if kind == "mul":
                (a, ca), (b, cb) = self.expr(other, e), self.expr(_add(d, other, -1), e)
                return f"({a} * {b})", ca and cb
            (a, ca), den = self.expr(_add(d, other), e), self.expr(other, e)
            return f"({a} / {self.unsafe(den, other, 'positive')})", False
        if kind == "neg":
            a, ca = self.expr(d, e)
            return f"({self.pick(['-', '+'])}{a})", ca
        if kind == "abs":
            a, ca = self.expr(d, e)
            return f"abs({a})", ca
        if kind == "minmax":
            args = [self.expr(d, e) for _ in range(int(self.rng.integers(1, 4)))]
            name = self.pick(["min", "max"])
            return f"{name}({', '.join(a for a, _ in args)})", all(c for _, c in args)
        if kind == "clamp":
            args = [self.expr(d, e) for _ in range(3)]
            return f"clamp({', '.join(a for a, _ in args)})", all(c for _, c in args)
        if kind == "select":
            (a, ca), (b, cb) = self.expr(d, e), self.expr(d, e)
            return f"select({self.cond(e)}, {a}, {b})", False
        if kind == "sqrt":
            arg = self.unsafe(self.expr(_scaled(d, 2), e), _scaled(d, 2), "positive")
            return f"sqrt({arg})", False
        if kind == "pow":
            if d == PLAIN:
                n = self.pick(["2", "3", "-1", "0.5", "1.5", "-0.5", "2.5", "0", "1"])
                base = self.expr(PLAIN, e)
                guard = "" if n in ("0", "1", "2", "3") else "positive"
                return f"({self.unsafe(base, PLAIN, guard)} ^ {n})", False
            powers = [n for n in (2, 3, -1, -2) if all(p % n == 0 for p in d)]
            if powers and self.chance(0.6):
                n = powers[int(self.rng.integers(len(powers)))]
                base_dim = (d[0] // n, d[1] // n, d[2] // n, d[3] // n)
                base = self.unsafe(self.expr(base_dim, e), base_dim, "positive" * (n < 0))
                return f"({base} ^ {n})", False
            base = self.unsafe(self.expr(_scaled(d, 2), e), _scaled(d, 2), "positive")
            return f"({base} ^ 0.5)", False
        if kind == "ratio":
            other = self.pick(DIMS)
            a, ca = self.expr(other, e)
            return f"({a} / {self.number(other, positive=True)})", ca
        if kind == "plainfn":
            name = self.pick(["sin", "cos", "tan", "exp", "log", "sign", "atan_ratio"])
            if name in ("sin", "cos", "tan"):
                arg_dim = self.pick([ANGLE, PLAIN])
                return f"{name}({self.unsafe(self.expr(arg_dim, e), arg_dim)})", False
            if name == "sign":
                return f"sign({self.expr(self.pick(DIMS), e)[0]})", False
            if name == "atan_ratio":
                return f"(atan({self.expr(PLAIN, e)[0]}) / 1 rad)", False
            guard = "positive" if name == "log" else ""
            return f"{name}({self.unsafe(self.expr(PLAIN, e), PLAIN, guard)})", False
        # an angle from a plain number or two values of one dimension
        name = self.pick(["asin", "acos", "atan", "atan2"])
        if name == "atan2":
            other = self.pick(DIMS)
            (a, _), (b, _) = self.expr(other, e), self.expr(other, e)
            return f"atan2({a}, {b})", False
        guard = "" if name == "atan" else "unit"
        return f"{name}({self.unsafe(self.expr(PLAIN, e), PLAIN, guard)})", False

    def compare(self, depth: int) -> str:
        d = self.pick(DIMS)
        op = self.pick(["<", ">", "<=", ">=", "==", "!="])
        return f"({self.expr(d, depth)[0]} {op} {self.expr(d, depth)[0]})"

    def cond(self, depth: int, event: bool = False) -> str:
        if event and self.chance(0.4):
            first = f"{self.pick(['touchdown', 'liftoff'])}({self.pick(self.creature.feet)})"
            return first if self.chance(0.7) else f"({first} and {self.cond(0)})"
        roll = self.rng.random()
        if depth <= 0 or roll < 0.6:
            return self.compare(min(depth, 2))
        if roll < 0.85:
            op = self.pick(["and", "or"])
            return f"({self.cond(depth - 1)} {op} {self.cond(depth - 1)})"
        return f"(not {self.cond(depth - 1)})"

    def statement(
        self,
        records: dict[str, Dim],
        must_record: list[str],
        settable: list[tuple[str, Dim]] | None = None,
    ) -> str:
        roll = self.rng.random()
        depth = int(self.rng.integers(1, 5))
        if settable is None and self.action and not must_record and self.chance(0.15):
            name, d = self.action
            return f"{name}({self.pick(self.creature.legs)}, {self.expr(d, depth - 1)[0]})"
        if settable is None and self.creature.spatial and not must_record and self.chance(0.1):
            return "swap active idle"  # entering the state, before the rest of the row
        if must_record or (records and roll < 0.2):
            name = must_record.pop() if must_record else self.pick(list(records))
            value = self.expr(records[name], depth)[0]
            if self.chance(0.3):  # integrate, reading the old value
                value = f"{name} + {value}"
            return f"record {name} = {value}"
        if roll < 0.45:
            d = self.pick(DIMS)
            name = self.fresh("l")
            text = f"let {name} = {self.expr(d, depth)[0]}"
            self.lets.setdefault(d, []).append(name)
            return text
        settable = settable or self.creature.settable
        target, d = settable[int(self.rng.integers(len(settable)))]
        value, const = self.expr(d, depth)
        if const and d in (STIFF, DAMP, ASTIFF, ADAMP):  # a constant below 0 is refused by the
            value = f"abs({value})"  # checker (seed 810012: 'l.spring.k = -300 kg*s^-2')
        if self.chance(0.5):  # a setting that keeps the creature in one piece a while
            low = SCALE.get(d, 1.0) * (0 if d in (STIFF, DAMP, ASTIFF, ADAMP) else -0.5)
            high = SCALE.get(d, 1.0) * 1.5
            value = f"clamp({value}, {_num(low, d)}, {_num(high, d)})"
        return f"{target} = {value}"

    def controller(self) -> str:
        lines = [f"controller rand for {self.creature.name} {{"]
        for kind in ("input", "param"):
            for _ in range(int(self.rng.integers(0, 4))):
                d, name = self.pick(DIMS), self.fresh(kind[0])
                lines.append(f"  {kind} {name} = {self.number(d)}")
                self.names.setdefault(d, []).append(name)
                if kind == "input" and self.chance(0.5):
                    self.names.setdefault(_add(d, TIME), []).append(f"integral({name})")
        records = {self.fresh("r"): self.pick(DIMS) for _ in range(int(self.rng.integers(0, 4)))}
        for name, d in records.items():  # read anywhere, also before the row that records it
            self.names.setdefault(d, []).append(name)
        for _ in range(int(self.rng.integers(0, 4))):
            d, name = self.pick(DIMS), self.fresh("s")
            lines.append(f"  signal {name} = {self.expr(d, int(self.rng.integers(1, 4)))[0]}")
            self.names.setdefault(d, []).append(name)
        if self.chance(0.5):
            lines.append(self.action_text())
        lines += [f"  {self.creature.roles}", "  table {"]
        states = int(self.rng.integers(1, 5))
        unrecorded = list(records)
        for i in range(states):
            self.lets = {}
            event = self.cond(2, event=True)
            if self.chance(0.3):  # a way on that comes for sure
                event = f"({event} or time_in_state > {self.number(TIME, positive=True)})"
            must = (
                [unrecorded.pop()] if unrecorded and (i == states - 1 or self.chance(0.5)) else []
            )
            while unrecorded and i == states - 1:
                must.append(unrecorded.pop())
            body = []
            for _ in range(int(self.rng.integers(0, 5)) + len(must)):
                body.append(self.statement(records, must))
            lines.append(f"    state S{i} on {event}: " + "; ".join(body))
        lines += ["  }", "}"]
        return "\n".join(lines) + "\n"

    def action_text(self) -> str:
        """``action aN(l, x) { ... }``: statements on a leg parameter and a number of a random
        dimension, inlined at each call with what it is given."""
        name, d = self.fresh("a"), self.pick(DIMS)
        self.lets = _merge(_leg_leaves("l", self.creature.spatial), {d: ["x"]})
        body = [self.statement({}, [], THROUGH_LEG) for _ in range(int(self.rng.integers(1, 4)))]
        self.action = (name, d)
        return f"  action {name}(l, x) {{ " + "; ".join(body) + " }"


def _num(value: float, d: Dim) -> str:
    text = np.format_float_positional(value, precision=3, trim="-")
    return f"{text} {unit(d)}".rstrip()


def law_text(seed: int, attempt: int = 0) -> str:
    rng = np.random.default_rng([seed, attempt] if attempt else seed)
    creature = HOPPER if rng.random() < 0.6 else BIPED
    return creature_text(creature.name) + "\n\n" + Law(rng, creature).controller()
