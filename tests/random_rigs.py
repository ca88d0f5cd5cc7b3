"""The random rigs of tests/sim/test_random_rigs.py, drawn here so that other tests
(tests/export/test_random_rig_exports.py) run the same rig for the same seed: a rig's text,
the rig placed on its ground (a welded root lowered, a free root's drop), and an actuator
refused as too stiff for the step set as the refusal advises."""

from __future__ import annotations

import math
import re
from pathlib import Path

import mujoco
import numpy as np
from mjhelpers import index_maps, load_mjcf, set_state
from random_creatures import (
    Body,
    Coordinate,
    body_properties,
    child_head,
    joint_block,
    num,
    random_point,
    root_head,
    vec,
)
from runtime_helpers import legdsl_in_process

from legdsl.check.source import check_file
from legdsl.sim.contact import GroundContact

WELDED_Z = 8.0  # where a welded root is written before it is lowered to the ground


def _units(c: Coordinate) -> tuple[str, str, str, str]:
    """Stiffness, damping, position and force units of a coordinate's actuators."""
    return ("N/m", "N*s/m", "m", "N") if c.slide else ("N*m/rad", "N*m*s/rad", "deg", "N*m")


def _near(rng: np.random.Generator, c: Coordinate) -> str:
    """A value near the coordinate's initial one, in its unit."""
    return num(c.initial + (rng.uniform(-0.05, 0.05) if c.slide else rng.uniform(-30, 30)))


def actuator_line(rng: np.random.Generator, name: str, c: Coordinate) -> str:
    k, b, x, f = _units(c)
    stiff = rng.uniform(1e2, 5e3) if c.slide else rng.uniform(1, 300)
    kind = str(rng.choice(["spring", "servo", "force", "torque"]))
    args = []
    if kind in ("spring", "servo"):
        gain, damping, where = ("k", "b", "rest") if kind == "spring" else ("kp", "kv", "setpoint")
        args.append(f"{gain} = {num(stiff)} {k}")
        if rng.random() < 0.7:
            args.append(f"{damping} = {num(stiff * rng.uniform(0.001, 0.1))} {b}")
        if rng.random() < 0.6:
            args.append(f"{where} = {_near(rng, c)} {x}")
    if rng.random() < 0.4:
        args.append(f"max = {num(rng.uniform(0.5, 50))} {f}")
    return f"  actuator {name} on {c.name} {kind}({', '.join(args)})"


def limit_lines(rng: np.random.Generator, coords: list[Coordinate]) -> list[str]:
    """Limits around each coordinate's initial value (now and then tight), maybe a stop."""
    if not coords or rng.random() < 0.5:
        return []
    pairs = []
    for c in coords:
        below, above = rng.uniform(0.005, 0.1, 2) if c.slide else rng.uniform(2, 60, 2)
        unit = "m" if c.slide else "deg"
        pairs.append((f"{num(c.initial - below)} {unit}", f"{num(c.initial + above)} {unit}"))
    if len(pairs) == 1:
        lines = [f"limits {pairs[0][0]} to {pairs[0][1]}"]
    else:
        lines = ["limits " + ", ".join(f"({lo}, {hi})" for lo, hi in pairs)]
    if rng.random() < 0.6:
        k, b, _, _ = _units(coords[0])
        stiff = rng.uniform(1e3, 1e5) if coords[0].slide else rng.uniform(10, 2e3)
        damping = f", b = {num(stiff * rng.uniform(0.001, 0.05))} {b}" if rng.random() < 0.7 else ""
        lines.append(f"stop k = {num(stiff)} {k}{damping}")
    return lines


def _template(rng: np.random.Generator, parents: list[Body], planar: bool) -> list[str]:
    """A limb of 1 to 3 bodies hung from a generated body, with a toe, actuators and limits,
    and 1 to 3 instances of it, each mirrored or not."""
    parent = parents[int(rng.integers(len(parents)))]
    kinds = ["revolute", "prismatic"] + ([] if planar else ["gimbal", "ball"])
    lines, actuators, above = ["  template limb(S, AT) {"], [], parent
    chain: list[Body] = []
    for i in range(int(rng.integers(1, 4))):
        body = Body(f"{'uml'[i]}_S", 0)
        props = body_properties(rng, body, planar)
        kind = str(rng.choice(kinds))
        coords: list[Coordinate] = []
        props += joint_block(rng, kind, f"j{'uml'[i]}_S", planar, coords)
        props += limit_lines(rng, coords)
        at = " at AT" if i == 0 else (" at tip" if above.length is not None else "")
        head = f"body {body.name} on {above.name} via {kind} j{'uml'[i]}_S{at}"
        lines += [f"    {head} {{", *(f"      {p}" for p in props), "    }"]
        actuators += [
            "  " + actuator_line(rng, f"a_{c.name}", c) for c in coords if rng.random() < 0.7
        ]
        chain.append(body)
        above = body
    toe = " at tip" if above.length is not None else f" at {random_point(rng, planar, 0.2)}"
    lines += [f"    contact toe_S on {above.name}{toe}", *actuators, "  }"]
    mirrors = ["", " mirror frontal"] + ([] if planar else [" mirror sagittal"])
    for name in "abc"[: int(rng.integers(1, 4))]:
        at = vec(rng.uniform(-0.3, 0.3, 2 if planar else 3), "m")
        lines.append(f"  instance {name} = limb(S = {name}, AT = {at}){rng.choice(mirrors)}")
    return lines


def _ground(rng: np.random.Generator, planar: bool) -> list[str]:
    """A linear or paw-pad normal of random stiffness, torsion in 3D, friction, terrain."""
    k = rng.uniform(1e3, 2e4)
    if rng.random() < 0.5:
        normal = f"normal spring(k = {num(k)} N/m, b = {num(k * rng.uniform(0, 0.05))} N*s/m)"
    else:
        thick = f"thickness = {num(rng.uniform(0.5, 3))} cm"
        normal = f"normal pad(k = {num(k / 20)} N, {thick}, b = {num(k / 100)} N*s/m)"
    tk = rng.uniform(5e2, 1e4)
    lines = ["  ground {", f"    {normal}"]
    lines.append(
        f"    tangent spring(k = {num(tk)} N/m, b = {num(tk * rng.uniform(0, 0.05))} N*s/m)"
    )
    if not planar and rng.random() < 0.5:
        lines.append(f"    torsion spring(k = {num(rng.uniform(1, 20))} N*m/rad)")
    friction = rng.random()
    if friction < 0.3:
        lines.append("    friction none")
    elif friction < 0.7:
        lines.append(f"    friction {num(rng.uniform(0.1, 1.2))}")
    terrain = rng.random()
    if terrain < 0.2:
        lines.append(f"    terrain slope(angle = {num(rng.uniform(-25, 25))} deg)")
    elif terrain < 0.5:
        lines.append(f"    terrain step(x = {num(rng.uniform(-0.5, 0.5))} m, "
                     f"height = {num(rng.uniform(0.01, 0.1))} m)")  # fmt: skip
    elif terrain < 0.7:
        x0 = rng.uniform(-1, 0.3)
        box = f"x0 = {num(x0)} m, x1 = {num(x0 + rng.uniform(0.1, 1))} m"
        if not planar:
            y0 = rng.uniform(-1, 0.3)
            box += f", y0 = {num(y0)} m, y1 = {num(y0 + rng.uniform(0.1, 1))} m"
        lines.append(f"    terrain box({box}, height = {num(rng.uniform(0.01, 0.08))} m)")
    return [*lines, "  }", "}"]


def rig_text(seed: int) -> str:
    """A random valid rig, the same for the same seed (a welded root still at WELDED_Z)."""
    rng = np.random.default_rng([seed, 7])
    planar = bool(rng.random() < 0.35)
    bodies: list[Body] = []
    body_lines, actuators = [], []
    for i in range(int(rng.integers(1, 6))):
        body = Body(f"b{i}", 0)
        props = body_properties(rng, body, planar)
        coords: list[Coordinate] = []
        if i == 0:
            head = root_head(rng, body, planar, props)
        else:
            head = child_head(rng, body, bodies, planar, props, coords)
            props += limit_lines(rng, coords)
        actuators += [actuator_line(rng, f"act_{c.name}", c) for c in coords if rng.random() < 0.6]
        body_lines += [f"  {head} {{", *(f"    {p}" for p in props), "  }"]
        bodies.append(body)
    lines = [f"creature rig{seed} {{", "  planar" if planar else "  spatial"]
    lines.append(f"  gravity {num(rng.uniform(1, 20))} m/s^2")
    lines += body_lines
    if rng.random() < 0.8:
        lines += _template(rng, bodies, planar)
    for k in range(int(rng.integers(1, 4))):
        body = bodies[int(rng.integers(len(bodies)))]
        where = " at tip" if body.length is not None and rng.random() < 0.6 else ""
        where = where or (f" at {random_point(rng, planar, 0.3)}" if rng.random() < 0.7 else "")
        lines.append(f"  contact c{k} on {body.name}{where}")
    lines += actuators
    lines += _ground(rng, planar)
    return "\n".join(lines) + "\n"


def _lowest_contact(source: Path) -> float:
    """The lowest contact's height above the ground under it, at the initial pose (MuJoCo's
    kinematics of the exported model: nothing is compiled)."""
    model = check_file(source)[0]
    mj = load_mjcf(model)
    data = mujoco.MjData(mj)
    set_state(mj, data, index_maps(model, mj), model.q0, model.v0)
    mujoco.mj_kinematics(mj, data)
    names = tuple(c.name for c in model.contacts)
    assert model.ground is not None
    ground = GroundContact(model.ground, names, model.planar)
    heights = [data.site(n).xpos[2] - ground.height(*data.site(n).xpos[:2]) for n in names]
    return float(min(heights))


def placed_rig(seed: int, folder: Path, lift: bool = False) -> tuple[Path, float | None]:
    """The rig written to ``folder``: a welded root lowered so that its lowest contact starts
    1 to 20 mm above the ground; and the drop of a free root (with ``lift``, for a command
    without ``--drop``, such as a sweep: written as its initial height instead, and None)."""
    rng = np.random.default_rng([seed, 8])
    text = rig_text(seed)
    source = folder / f"rig{seed}.leg"
    source.write_text(text)
    if " free {" in text:
        drop = float(rng.uniform(0.001, 0.05))
        if not lift:
            return source, drop
        assert "initial z = 1 m," in text  # random_creatures.root_head
        height = f"initial z = {num(1.0 + drop - _lowest_contact(source))} m,"
        source.write_text(text.replace("initial z = 1 m,", height, 1))
        return source, None
    lower = _lowest_contact(source) - rng.uniform(0.001, 0.02)
    welded = re.search(r"fixed at \(([^)]*), ([-\d.e]+) m\)", text)
    assert welded is not None and float(welded.group(2)) == WELDED_Z
    head = f"fixed at ({welded.group(1)}, {num(WELDED_Z - lower)} m)"
    source.write_text(text.replace(welded.group(0), head))
    return source, None


ADVICE = re.compile(
    r":(\d+):\d+: error: actuator '\w+' is too (?:stiff|damped) for the integration step: "
    r"(\w+) = [^;]*; use \2 below ([\d.e+-]+) "
)


def follow_advice(source: Path, message: str) -> None:
    """Each actuator setting refused as too stiff or damped for the step set to half the
    bound the refusal gives (which must be given, on the actuator's line; for a template's
    line, the least of its instances')."""
    lines = source.read_text().split("\n")
    found = ADVICE.findall(message)
    assert found, f"a refusal that is not about stiffness: {message}"
    lowest: dict[tuple[int, str], float] = {}  # a template's line: its instances' least
    for line, setting, bound in found:
        key = (int(line) - 1, setting)
        lowest[key] = min(float(bound), lowest.get(key, math.inf))
    for (row, setting), bound in lowest.items():
        written = f"{setting} = {num(bound / 2)}"
        lines[row], hits = re.subn(rf"\b{setting} = [-\d.e+]+", written, lines[row])
        assert hits == 1, f"no '{setting}' on line {row + 1}: {lines[row]}"
    source.write_text("\n".join(lines))


def rig_shown(seed: int, folder: Path) -> str:
    """The rig as last written to ``folder`` (the advice followed), else as drawn."""
    written = folder / f"rig{seed}.leg"
    return written.read_text() if written.exists() else rig_text(seed)


def recorded_rig(seed: int, where: Path, duration: float, record_rate: float) -> tuple[Path, int]:
    """``legdsl run`` of the placed rig into ``where``/run (modules in ``where``/generated) on
    the Python backend, with the default fall rules or none (drawn as test_random_rigs.py
    draws them), an actuator refused as too stiff set as advised: the rig and the exit status
    (0 ok, 3 diverged, 4 fell)."""
    source, drop = placed_rig(seed, where)
    falls = np.random.default_rng([seed, 9]).random() < 0.5
    argv = ["run", str(source), "--time", str(duration), "--backend", "python"]
    argv += ["--record-rate", str(record_rate), "--out", str(where / "run")]
    argv += ["--generated", str(where / "generated")]
    argv += [] if drop is None else ["--drop", repr(drop)]
    argv += [] if falls else ["--fall-height", "0", "--fall-tilt", "180"]
    said = ""
    for _ in range(4):
        status, said = legdsl_in_process(argv)
        if status != 2:
            break
        follow_advice(source, said)  # an actuator too stiff for the step
    assert status in (0, 3, 4), f"legdsl run: {status}: {said}"
    return source, status
