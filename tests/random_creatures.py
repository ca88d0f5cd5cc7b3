"""The seeded generator of random creatures (tests/lower/test_random_creatures.py and
tests/sim/test_random_rigs.py): bodies, inertias, joints, their axes and initial values."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


def num(x: float) -> str:
    return f"{x:.6g}"


def vec(v: np.ndarray, unit: str = "") -> str:
    sep = f" {unit}, " if unit else ", "
    return "(" + sep.join(num(x) for x in v) + (f" {unit})" if unit else ")")


def skewed_axis(rng: np.random.Generator, dim: int) -> np.ndarray:
    """A unit axis, a quarter of the time a coordinate axis (exactly), else any direction."""
    if rng.random() < 0.25:
        return np.eye(dim)[rng.integers(dim)]
    v = rng.normal(size=dim)
    return np.round(v / np.linalg.norm(v), 3)


def unit(v: np.ndarray) -> np.ndarray:
    return np.asarray(v, dtype=float) / np.linalg.norm(v)


def rot(axis: np.ndarray, angle: float) -> np.ndarray:
    a = unit(axis)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def turned_axes(axes: list[np.ndarray], angles: list[float]) -> list[np.ndarray]:
    """Each hinge's axis in the joint frame, turned by the hinges before it."""
    r, out = np.eye(3), []
    for axis, angle in zip(axes, angles, strict=True):
        out.append(r @ unit(axis))
        r = r @ rot(axis, angle)
    return out


def coordinate_names(joint: str, axes: list[np.ndarray]) -> list[str]:
    """docs/language.md: JOINT_x/_y/_z after an exact coordinate axis, else JOINT_1/_2/_3 by
    position; all numbered if two would share a name."""
    names = []
    for i, a in enumerate(axes):
        hits = [k for k in range(3) if np.array_equal(a, np.eye(3)[k])]
        names.append(f"{joint}_{'xyz'[hits[0]] if hits else i + 1}")
    if len(set(names)) < len(names):
        return [f"{joint}_{i + 1}" for i in range(len(axes))]
    return names


@dataclass
class Body:
    name: str
    depth: int
    length: float | None = None
    lines: list[str] = field(default_factory=list)


def inertia(rng: np.random.Generator, mass: float, size: float, planar: bool) -> str:
    if planar:
        return f"inertia {num(mass * size**2 * rng.uniform(0.05, 1.0))} kg*m^2"
    # moments of a mass spread a, b, c along the axes: each at most the sum of the others
    # now and then a thin rod or a flat plate: a spread near 0, the moments near the bound
    a, b, c = rng.uniform(0.05, 1.0, 3) * rng.choice([1.0, 1.0, 0.05], 3) * mass * size**2
    moments = np.array([b + c, a + c, a + b])
    if rng.random() < 0.5:
        return f"inertia {vec(moments)} kg*m^2"
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    tensor = q @ np.diag(moments) @ q.T
    cells = [[num(tensor[min(i, j), max(i, j)]) + " kg*m^2" for j in range(3)] for i in range(3)]
    return "inertia (" + ", ".join("(" + ", ".join(row) + ")" for row in cells) + ")"


@dataclass
class Coordinate:
    """A joint coordinate written: its name, whether it slides, its initial value (deg or m)."""

    name: str
    slide: bool
    initial: float = 0.0


def joint_block(rng: np.random.Generator, kind: str, joint: str, planar: bool,
                coordinates: list[Coordinate] | None = None) -> list[str]:  # fmt: skip
    """The axis, axes and initial values of a joint of ``kind`` (its coordinates' names);
    its coordinates are appended to ``coordinates``."""
    lines: list[str] = []
    found = coordinates if coordinates is not None else []
    if kind in ("revolute", "prismatic"):
        if (kind == "prismatic" or not planar) and rng.random() < 0.8:
            lines.append(f"axis {vec(skewed_axis(rng, 2 if planar else 3))}")
        found.append(Coordinate(joint, kind == "prismatic"))
        if rng.random() < 0.6:
            value = rng.uniform(-60, 60) if kind == "revolute" else rng.uniform(-0.1, 0.1)
            found[-1].initial = float(value)
            lines.append(f"initial {num(value)} {'deg' if kind == 'revolute' else 'm'}")
        if rng.random() < 0.4:
            rate = rng.uniform(-2, 2)
            lines.append(f"velocity {num(rate)} {'rad/s' if kind == 'revolute' else 'm/s'}")
        return lines
    if kind not in ("gimbal", "ball"):
        return lines
    n = 2 if kind == "gimbal" else 3
    while True:
        axes = [skewed_axis(rng, 3) for _ in range(n)]
        angles = list(np.radians(rng.uniform(-40, 40, n)))
        turned = turned_axes(axes, angles)
        apart = all(abs(np.dot(a, b)) < 0.94 for a, b in zip(turned, turned[1:], strict=False))
        if apart and (n == 2 or abs(np.linalg.det(np.array(turned))) > 0.3):
            break
    names = coordinate_names(joint, axes)
    found += [
        Coordinate(c, False, float(np.degrees(x))) for c, x in zip(names, angles, strict=True)
    ]
    lines.append("axes " + ", ".join(vec(a) for a in axes))
    lines.append("initial " + ", ".join(f"{c} = {num(np.degrees(x))} deg" for c, x in
                                        zip(names, angles, strict=True)))  # fmt: skip
    if rng.random() < 0.4:
        lines.append(f"velocity {names[0]} = {num(rng.uniform(-1, 1))} rad/s")
    return lines


def random_point(rng: np.random.Generator, planar: bool, scale: float) -> str:
    return vec(rng.uniform(-scale, scale, 2 if planar else 3), "m")


def body_properties(rng: np.random.Generator, body: Body, planar: bool) -> list[str]:
    """Mass (10 g to 50 kg, log-uniform), inertia, and maybe a link and a mass centre."""
    mass = float(np.exp(rng.uniform(np.log(0.01), np.log(50))))
    size = rng.uniform(0.05, 0.6)
    props = [f"mass {num(mass)} kg", inertia(rng, mass, size, planar)]
    if rng.random() < 0.7:
        body.length = float(rng.uniform(0.05, 0.8))
        props.append(f"length {num(body.length)} m")
        if rng.random() < 0.5:
            props.append(f"direction {vec(skewed_axis(rng, 2 if planar else 3))}")
    elif rng.random() < 0.3:  # no link, but a direction: a prismatic joint's default axis
        props.append(f"direction {vec(skewed_axis(rng, 2 if planar else 3))}")
    if rng.random() < 0.3 and body.length is not None:
        props.append(f"com {num(rng.uniform(0, body.length))} m")
    elif rng.random() < 0.6:
        props.append(f"com {random_point(rng, planar, rng.choice([0.2, 1.0]))}")
    return props


def root_head(rng: np.random.Generator, body: Body, planar: bool, props: list[str]) -> str:
    """A free root (its initial pose and maybe a velocity added to ``props``) or a welded one."""
    if rng.random() < 0.8:
        init = ["z = 1 m", f"x = {num(rng.uniform(-1, 1))} m"]
        turns = ("pitch",) if planar else ("roll", "pitch", "yaw")
        init += [f"{a} = {num(rng.uniform(-30, 30))} deg" for a in turns]
        props.append("initial " + ", ".join(init))
        if rng.random() < 0.5:
            linear, angular = (("x", "z"), ("pitch",)) if planar else ("xyz", ("wx", "wy", "wz"))
            rates = [f"{'' if planar else 'v'}{a} = {num(rng.uniform(-1, 1))} m/s" for a in linear]
            rates += [f"{a} = {num(rng.uniform(-1, 1))} rad/s" for a in angular]
            props.append("velocity " + ", ".join(rates))
        return f"body {body.name} free"
    at = rng.uniform(-0.5, 0.5, 2 if planar else 3)
    at[-1] = 8.0  # high enough that nothing starts under the ground
    return f"body {body.name} fixed at {vec(at, 'm')}"


def child_head(rng: np.random.Generator, body: Body, bodies: list[Body], planar: bool,
               props: list[str], coordinates: list[Coordinate] | None = None) -> str:  # fmt: skip
    """A joint to a parent at most 4 deep, of a random kind and place (its block to ``props``)."""
    kinds = ["revolute", "prismatic", "fixed"] + ([] if planar else ["gimbal", "ball"])
    weights = np.array([0.4, 0.25, 0.1] if planar else [0.3, 0.2, 0.1, 0.2, 0.2])
    candidates = [b for b in bodies if b.depth < 5]
    parent = candidates[int(rng.integers(len(candidates)))]
    body.depth = parent.depth + 1
    kind = str(rng.choice(kinds, p=weights / weights.sum()))
    joint = "j" + body.name[1:]
    where = rng.random()
    if where < 0.4 and parent.length is not None:
        at = " at tip"
    elif where < 0.8:
        at = f" at {random_point(rng, planar, 0.3)}"
    else:
        at = ""
    props += joint_block(rng, kind, joint, planar, coordinates)
    return f"body {body.name} on {parent.name} via {kind} {joint}{at}"
