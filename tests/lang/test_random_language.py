"""Random language: seeded .leg files drawing the parts of the language the random creatures
and laws (tests/sim/test_random_rigs.py, tests/codegen/test_random_laws.py) leave out:
templates with several instances (mirrored or not) holding `leg` blocks, legs of several
soles, controllers that `extends` another, `include` shared parts, call top-level actions,
`use` the standard library or a file beside them, group roles (virtual legs) with `each`,
`place`, `swap`, `record` and `own`, paths, the terrain ahead, and scenes with switches or
a gait chosen by speed; and (tests/random_language_use.py) a chain of `use`s, a file used
from two paths, a used file's shared part holding roles and a table, and a controller that
`extends` a used file's controller of its own name. Roles of groups of different sizes may
swap (`roles active = a, idle = (b, c)`): each state's code is made for each binding.

Most files are valid: each must run (``legdsl run``, in this process) for a fraction of a
second alike on the Python and C backends, trajectory.npz byte for byte. Some carry one
mistake people outside the team make (MISTAKES): each must be refused by ``legdsl check``
with exit status 2 and diagnostics of three lines, ``FILE:LINE:COL: error: MESSAGE`` with a
sentence saying what to do, the source line and a caret; never a traceback, "internal
error" or exit 70.

``LEGDSL_RANDOM_LANGUAGE=N`` checks N files (default ``CI_FILES``) from seeds
``LEGDSL_RANDOM_LANGUAGE_SEED``, +1, ...; a failure names its seed and prints the file.
"""

from __future__ import annotations

import os
import random
import re
from dataclasses import dataclass, field
from pathlib import Path

import pytest
from random_language_use import USE_MISTAKE_SAYS, UseSpec, draw_use, files, use_lines
from random_language_use import controller_lines as use_controller_lines
from runtime_helpers import legdsl_in_process, needs_c_compiler
from seeded import told_with_seed

CI_FILES = 8  # 5 valid (gait by speed, use chains, extends of a used file, groups of 1 and 2 swapped), 3 mistakes (one in a used file)
COUNT = int(os.environ.get("LEGDSL_RANDOM_LANGUAGE", CI_FILES))
FIRST_SEED = int(os.environ.get("LEGDSL_RANDOM_LANGUAGE_SEED", "0"))
MISTAKE_SHARE = 0.4

pytestmark = needs_c_compiler

MISTAKES = (
    "instance_unknown_parameter",
    "instance_missing_parameter",
    "instance_value_in_name",
    "instances_same_names",
    "mirror_sagittal_planar",
    "foot_not_contact",
    "foot_sole_other_body",
    "alias_other_leg",
    "place_body",
    "place_unknown_servo",
    "extends_missing",
    "extends_cycle",
    "scene_other_creature",
    "start_undefined_state",
    "state_twice",
    "each_unknown_leg",
    "own_unknown",
    "each_over_body",
    "record_in_each",
    "swap_leg",
    "member_misspelled",
    "include_unknown",
    "use_missing_file",
    "terrain_member_misspelled",
    "band_wrong_unit",
    "gait_and_switch",
    "controller_unknown_creature",
    "action_wrong_arity",
    "scene_param_at_time",
    "record_hides_param",
    "own_in_derived_unknown",
    "include_twice_declared",
    "place_servo_after_swap",  # the first leg's servo named, the role swapped to another
)


def num(x: float) -> str:
    return f"{x:.4g}"


@dataclass
class Spec:
    seed: int
    planar: bool
    legs: list[str]
    template: bool
    soles: bool  # a heel beside the toe, both listed as the foot
    mirrors: list[str]
    hips: list[tuple[float, float]]
    terrain: str
    second_creature: bool
    use_stdlib: bool
    use_file: bool
    shared: bool
    top_action: bool
    extends: bool
    path: bool
    scene: str  # "", "switch" or "gait"
    groups: bool
    own: bool
    place: bool
    each: bool
    mistake: str = ""
    rest: dict[str, float] = field(default_factory=dict)
    use: UseSpec = field(default_factory=lambda: draw_use(0, "none"))


def draw(seed: int) -> Spec:
    rng = random.Random(seed * 7919 + 3)
    planar = rng.random() < 0.5
    n = rng.choice([1, 2, 2, 3, 4])
    legs = [("l", "r", "f", "h")[i] + str(rng.randrange(3)) for i in range(n)]
    xs = [rng.uniform(-0.3, 0.3) for _ in legs]
    hips = [(x, 0.0 if planar else rng.uniform(0.05, 0.15)) for x in xs]
    mirrors = [rng.choice(["", " mirror frontal"] + ([] if planar else [" mirror sagittal"]))
               for _ in legs]  # fmt: skip
    extends = rng.random() < 0.6
    spec = Spec(
        seed=seed,
        planar=planar,
        legs=legs,
        template=rng.random() < 0.75,
        soles=rng.random() < 0.3,
        mirrors=mirrors,
        hips=hips,
        terrain=rng.choice(["", "box", "step", "slope"]),
        second_creature=rng.random() < 0.25,
        use_stdlib=rng.random() < 0.5,
        use_file=rng.random() < 0.3,
        shared=rng.random() < 0.5,
        top_action=rng.random() < 0.5,
        extends=extends,
        path=rng.random() < 0.4,  # a planar creature's: progress along x (accepted)
        scene=rng.choice(["", "switch", "gait"]) if extends else "",
        groups=n >= 2 and rng.random() < 0.6,
        own=rng.random() < 0.5,
        place=rng.random() < 0.6,
        each=rng.random() < 0.6,
    )
    spec.rest = {
        "k": rng.uniform(1500, 4000),
        "stroke": rng.uniform(0.005, 0.04),
        "speed": rng.uniform(0.2, 1.5),
        "kp": rng.uniform(50, 200),
        "z": rng.uniform(0.86, 0.95),
        "time": rng.choice([0.2, 0.3, 0.4]),
    }
    if rng.random() < MISTAKE_SHARE:
        spec.mistake = rng.choice(MISTAKES)
        _fit_mistake(spec)
    spec.use = draw_use(seed, spec.mistake)
    return spec


# what a drawn mistake needs of the file it is made in, beyond the draw
_MISTAKE_NEEDS: dict[str, dict[str, object]] = {
    "mirror_sagittal_planar": {"template": True, "planar": True, "path": False},
    "place_servo_after_swap": {"place": True, "groups": False},
    "foot_sole_other_body": {"soles": True},
    "alias_other_leg": {"template": False},
    "scene_other_creature": {"second_creature": True, "extends": True},
    "gait_and_switch": {"extends": True},
    "band_wrong_unit": {"extends": True, "scene": "gait"},
    "extends_cycle": {"extends": True},
    "terrain_member_misspelled": {"terrain": "box"},
    "member_misspelled": {"each": True},
    "action_wrong_arity": {"each": False},
    "own_unknown": {"own": True},
    "include_twice_declared": {"shared": True},
    "scene_param_at_time": {"extends": True, "scene": "switch"},
    "own_in_derived_unknown": {"extends": True},
}


def _fit_mistake(spec: Spec) -> None:
    """The parts the drawn mistake is made in."""
    m = spec.mistake
    if m.startswith("instance"):
        spec.template = True
    for name, value in _MISTAKE_NEEDS.get(m, {}).items():
        setattr(spec, name, value)
    if (
        m in ("instances_same_names", "alias_other_leg", "place_servo_after_swap")
        and len(spec.legs) < 2
    ):
        spec.legs.append("z1")
        spec.hips.append((0.1, 0.0 if spec.planar else 0.1))
        spec.mirrors.append("")
    if m == "mirror_sagittal_planar":
        spec.hips = [(x, 0.0) for x, _ in spec.hips]
        spec.mirrors = [" mirror frontal" if mirror else "" for mirror in spec.mirrors]


def _point(spec: Spec, x: float, y: float, z: float = 0.0) -> str:
    if spec.planar:
        return f"({num(x)} m, {num(z)} m)"
    return f"({num(x)} m, {num(y)} m, {num(z)} m)"


def _leg_lines(spec: Spec, s: str, hip: str, index: int) -> list[str]:
    """The parts of one leg, its side ``s`` standing in the names (a template's S)."""
    m = spec.mistake
    hip_joint = "revolute" if spec.planar else "gimbal"
    pitch = f"hip_{s}" if spec.planar else f"hip_{s}_y"
    lines = [
        f"body thigh_{s} on trunk via {hip_joint} hip_{s} at {hip} {{",
        "  length 0.3 m  com 0.15 m  mass 0.8 kg  "
        + ("inertia 0.01 kg*m^2" if spec.planar else "inertia (0.01, 0.01, 0.0005) kg*m^2"),
        "  limits -60 deg to 60 deg" if spec.planar else "",
        "}",
        f"body shank_{s} on thigh_{s} via prismatic leg_{s} at tip {{",
        "  length 0.5 m  com 0.25 m  mass 0.3 kg  "
        + ("inertia 0.006 kg*m^2" if spec.planar else "inertia (0.006, 0.006, 0.0001) kg*m^2"),
        "  limits -0.25 m to 0.1 m",
        "}",
        f"contact toe_{s} on shank_{s} at tip",
    ]
    feet = f"toe_{s}"
    if spec.soles:
        lines.append(f"contact heel_{s} on shank_{s} at {_point(spec, 0.03, 0.0, -0.49)}")
        heel = f"heel_{s}"
        if m == "foot_sole_other_body":
            lines[-1] = f"contact heel_{s} on thigh_{s} at tip"
        feet += f", {heel}"
    if m == "foot_not_contact" and index <= 0:
        feet = f"shank_{s}"
    spring = f"leg_{s}_spring"
    if m == "alias_other_leg" and len(spec.legs) > 1 and not spec.template and index == 0:
        spring = f"leg_{spec.legs[1]}_spring"
    aliases = f"spring = {spring}, hip_servo = hip_{s}_servo"
    if not spec.planar:
        aliases += f", roll_servo = hip_{s}_roll"
    lines += [
        f"leg {s} {{ joints hip_{s}, leg_{s}  foot {feet}  alias {aliases} }}",
        f"actuator leg_{s}_spring on leg_{s} spring(k = {num(spec.rest['k'])} N/m, "
        "b = 5 N*s/m, rest = 0 m)",
        f"actuator hip_{s}_servo on {pitch} servo(kp = 150 N*m/rad, kv = 6 N*m*s/rad, "
        "max = 100 N*m)",
    ]
    if not spec.planar:
        lines.append(
            f"actuator hip_{s}_roll on hip_{s}_x servo(kp = 150 N*m/rad, kv = 6 N*m*s/rad)"
        )
    return [line for line in lines if line]


def creature_lines(spec: Spec) -> list[str]:
    m = spec.mistake
    trunk_inertia = "inertia 0.4 kg*m^2" if spec.planar else "inertia (0.3, 0.6, 0.6) kg*m^2"
    init = f"x = 0 m, z = {num(spec.rest['z'])} m" + (", pitch = 0 deg" if spec.planar else "")
    out = [
        "creature walker {",
        "  planar" if spec.planar else "  spatial",
        "  body trunk free {",
        f"    mass 10 kg  {trunk_inertia}",
        f"    initial {init}",
        "  }",
    ]
    if spec.template:
        out.append("  template limb(S, HIP) {")
        out += [f"    {line}" for line in _leg_lines(spec, "S", "HIP", -1)]
        out.append("  }")
        for i, (s, (x, y)) in enumerate(zip(spec.legs, spec.hips, strict=True)):
            mirror = spec.mirrors[i]
            if m == "mirror_sagittal_planar" and i == 0 and spec.planar:
                mirror = " mirror sagittal"
            side = s
            if m == "instances_same_names" and i == 1:
                side = spec.legs[0]
            args = f"S = {side}, HIP = {_point(spec, x, y)}"
            if i == 0 and m == "instance_unknown_parameter":
                args = f"S = {side}, HPI = {_point(spec, x, y)}"
            elif i == 0 and m == "instance_missing_parameter":
                args = f"S = {side}"
            elif i == 0 and m == "instance_value_in_name":
                args = f"S = 0.5 m, HIP = {_point(spec, x, y)}"
            out.append(f"  instance {s} = limb({args}){mirror}")
    else:
        for i, (s, (x, y)) in enumerate(zip(spec.legs, spec.hips, strict=True)):
            out += [f"  {line}" for line in _leg_lines(spec, s, _point(spec, x, y), i)]
    out += [
        "  ground {",
        "    normal spring(k = 3e4 N/m, b = 300 N*s/m)",
        "    tangent spring(k = 2e4 N/m, b = 200 N*s/m)",
        "    friction none",
    ]
    if spec.terrain == "box":
        box = "x0 = 0.4 m, x1 = 0.9 m" + ("" if spec.planar else ", y0 = -1 m, y1 = 1 m")
        out.append(f"    terrain box({box}, height = 0.05 m)")
    elif spec.terrain == "step":
        out.append("    terrain step(x = 0.5 m, height = 0.03 m)")
    elif spec.terrain == "slope":
        out.append("    terrain slope(angle = 3 deg)")
    return [*out, "  }", "}"]


def _role_line(spec: Spec) -> tuple[str, list[str]]:
    """The roles line and the roles a `swap` may exchange."""
    legs = spec.legs
    if len(legs) == 1:
        return f"roles active = {legs[0]}", []
    if spec.groups and len(legs) >= 3:
        half = len(legs) // 2
        a, b = legs[:half], legs[half:]
        ga = a[0] if len(a) == 1 else "(" + ", ".join(a) + ")"
        gb = b[0] if len(b) == 1 else "(" + ", ".join(b) + ")"
        return f"roles active = {ga}, idle = {gb}", ["active", "idle"]  # sizes may differ
    if spec.groups:
        return f"roles active = ({', '.join(legs)})", []
    return f"roles active = {legs[0]}, idle = {legs[1]}", ["active", "idle"]


def controller_lines(spec: Spec) -> list[str]:
    m = spec.mistake
    r = spec.rest
    roles, swappable = _role_line(spec)
    forward = "for walker " if spec.second_creature else ""
    if m == "controller_unknown_creature":
        forward = "for walkr "
    out = [f"controller hop {forward}{{"]
    parts = (["gains"] if spec.shared else []) + (["soft"] if spec.use_file else [])
    if m == "include_unknown":
        parts.append("gain")
    if m == "include_twice_declared":
        parts.append("twice")
    if parts:
        out.append(f"  include {', '.join(parts)}")
    if not spec.shared:
        out += [f"  param kp = {num(r['kp'])} N*m/rad", "  param kv = 6 N*m*s/rad"]
    out += [
        f"  input speed = {num(r['speed'])} m/s",
        f"  param stroke = {num(r['stroke'] * 100)} cm",
        "  param k_speed = 0.05 s",
        "  signal speed_error = com.vx - speed",
        f"  {roles}",
    ]
    if spec.terrain in ("box", "step"):
        member = "ahead_deep" if m == "terrain_member_misspelled" else "ahead_depth"
        out.append(f"  signal obstacle = terrain.ahead_distance + terrain.{member} / 2")
    if spec.path:
        shape = "polyline((-5, 0) m, (5, 0) m)"
        if not spec.planar:
            shape = "circle(center = (0, 3) m, radius = 3 m, turn = left)"
        out += [f"  path route = {shape}", "  signal off_path = route.lateral"]
    if m == "start_undefined_state":
        out.append("  start STANCE")
    if spec.own:
        out.append("  own lifted_at" if m != "own_unknown" else "  own lifted_a")
    if not spec.top_action:
        out.append("  action lift(l, r) { l.spring.rest = r }")
    flight = ["record lifted_at = time" if m != "record_hides_param" else "record stroke = 1 cm"]
    if spec.each or m in ("each_over_body", "record_in_each", "each_unknown_leg"):
        over = {"each_over_body": "trunk", "each_unknown_leg": "activ"}.get(m, "active")
        inner = "m.spring.rest = stroke * m.touching / max(active.feet_down, 1)"
        if m == "member_misspelled":
            inner = "m.sprung.rest = 0 m"
        if m == "record_in_each":
            inner += "; record lowest = m.foot_z"
        flight.append(f"each m in {over} {{ {inner} }}")
    else:
        flight.append("lift(active, 0 m)" if m != "action_wrong_arity" else "lift(active)")
    if spec.place or m in ("place_body", "place_unknown_servo"):
        who = "trunk" if m == "place_body" else "active"
        servo = "hip_x9_servo" if m == "place_unknown_servo" else "active.hip_servo"
        if m == "place_servo_after_swap":
            servo = f"hip_{spec.legs[0]}_servo"
        goal = "x = k_speed * speed_error + 0.5 * k_speed * speed"
        if not spec.planar and spec.seed % 3 == 0 and m != "place_unknown_servo":
            goal += ", y = 0 m"
            servo += ", active.roll_servo"
        flight.append(f"place {who} at ({goal}) using {servo}")
    else:
        flight.append("active.hip_servo.setpoint = 0 deg")
    if swappable and m != "swap_leg":
        flight.insert(0, "swap active idle")
    elif m == "swap_leg":
        flight.insert(0, f"swap {spec.legs[0]} active")
    if spec.use_stdlib:
        flight.append("relax(active, 0 m)")
    if spec.use_file:
        flight.append("soften(active)")
    thrust = "active.spring.rest = stroke"
    if spec.top_action:
        thrust = "lift(active, stroke)"
    loading = "LOADING" if m != "state_twice" else "FLIGHT"
    steer = ""
    if spec.path:
        steer = "; active.hip_servo.setpoint = clamp(off_path * 0.1 rad/m, -0.1 rad, 0.1 rad)"
    elif spec.terrain in ("box", "step"):
        steer = "; active.hip_servo.setpoint = select(obstacle > 0.2 m, 0 deg, 2 deg)"
    out += [
        "  table {",
        f"    state FLIGHT on liftoff(active): {'; '.join(flight)}",
        f"    state {loading} on touchdown(active): active.hip_servo.kp = 0{steer}",
        "    state COMPRESSION on active.rate < 0: active.hip_servo.kp = kp;"
        " active.hip_servo.kv = kv",
        f"    state THRUST on active.rate >= 0: {thrust}",
        "  }",
        "}",
    ]
    return out


def extra_lines(spec: Spec) -> list[str]:
    """Shared parts, actions, derived controllers, a second creature and scenes."""
    m = spec.mistake
    r = spec.rest
    out: list[str] = []
    if spec.shared:
        out += [
            "shared gains {",
            f"  param kp = {num(r['kp'])} N*m/rad",
            "  param kv = 6 N*m*s/rad",
            "}",
        ]
    if m == "include_twice_declared":
        out += ["shared twice {", "  param kv = 5 N*m*s/rad", "}"]
    if spec.top_action:
        out.append("action lift(l, r) { l.spring.rest = r }")
    forward = "for walker " if spec.second_creature else ""
    if spec.extends or m in ("extends_missing", "extends_cycle"):
        base = "hpo" if m == "extends_missing" else "hop"
        if m == "extends_cycle":
            base = "stiff2"
            out += [f"controller stiff2 {forward}extends stiff {{", "}"]
        out += [
            f"controller stiff {forward}extends {base} {{",
            f"  param kp = {num(r['kp'] * 1.5)} N*m/rad",
            f"  param stroke = {num(r['stroke'] * 150)} cm",
        ]
        if spec.seed % 4 == 1:  # a table of its own in the place of hop's
            out += [
                "  table {",
                "    state UP on liftoff(active): active.spring.rest = 0 m"
                + ("; record lifted_at = time" if spec.own else ""),
                "    state DOWN on touchdown(active): active.spring.rest = stroke",
                "  }",
            ]
        if m == "own_in_derived_unknown":
            out.append("  own lifted_b")
        out.append("}")
    if spec.second_creature or m == "scene_other_creature":
        out += [
            "creature pogo {",
            "  planar",
            "  body box free { mass 5 kg  inertia 0.2 kg*m^2  initial x = 0 m, z = 0.8 m }",
            "  body rod on box via prismatic slide at (0 m, -0.05 m) {",
            "    length 0.6 m  com 0.3 m  mass 0.3 kg  inertia 0.009 kg*m^2",
            "  }",
            "  contact tip on rod at tip",
            "  leg main { joints slide  foot tip }",
            "  actuator slide_spring on slide spring(k = 2500 N/m, rest = 0 m)",
            "}",
            "controller bounce for pogo {",
            "  roles active = main",
            "  table {",
            "    state UP on liftoff(active): slide_spring.rest = 0 m",
            "    state DOWN on touchdown(active): slide_spring.rest = 1 cm",
            "  }",
            "}",
        ]
        forward = "for walker "
    half = num(r["time"] / 2)
    if spec.scene == "switch" or m in ("scene_other_creature", "gait_and_switch"):
        other = "bounce" if m == "scene_other_creature" else "stiff"
        out += [
            f"scene run {forward}{{",
            "  controller hop",
            f"  set speed = {num(r['speed'])} m/s",
            f"  at {half} s switch {other}",
            f"  at {half} s set speed = {num(r['speed'] * 1.5)} m/s",
            f"  set {other}.kp = {num(r['kp'] * 1.2)} N*m/rad" if other == "stiff" else "",
            f"  time {num(r['time'])} s",
        ]
        if m == "gait_and_switch":
            out.insert(-6, "  gait by speed { hop to 1 m/s; stiff from 0.8 m/s }")
        if m == "scene_param_at_time":
            out.insert(-1, f"  at {half} s set kp = 100 N*m/rad")
        out.append("}")
    elif spec.scene == "gait":
        unit = "m" if m == "band_wrong_unit" else "m/s"
        out += [
            f"scene run {forward}{{",
            f"  gait by speed {{ hop to 1 {unit}; stiff from 0.8 m/s }}",
            "  set speed = 0.5 m/s",
            f"  at {half} s set speed = 1.5 m/s",
            f"  time {num(r['time'])} s",
            "}",
        ]
    return out


def uses(spec: Spec) -> list[str]:
    out = []
    if spec.use_stdlib:
        out.append("use raibert")
    if spec.use_file or spec.mistake == "use_missing_file":
        out.append('use "parts.leg"' if spec.mistake != "use_missing_file" else 'use "prts.leg"')
    return out + use_lines(spec.use)


PARTS = "# actions for the random files of tests/lang/test_random_language.py\n" + (
    "shared soft {\n  param soft_b = 5 N*s/m\n}\naction soften(l) {\n  l.spring.b = soft_b\n}\n"
)


def file_text(spec: Spec) -> str:
    lines = [f"# random language, seed {spec.seed}", *uses(spec)]
    lines += creature_lines(spec) + controller_lines(spec) + extra_lines(spec)
    forward = "for walker " if spec.second_creature else ""
    lines += use_controller_lines(spec.use, _role_line(spec)[0], forward)
    return "\n".join(lines) + "\n"


HEAD = re.compile(r"(?P<file>[^:\n]+):(?P<line>\d+):(?P<col>\d+): error: (?P<message>.+)")
# a sentence that says what to do (as tests/bad's messages do)
FIX = re.compile(
    r"\b(write|use|give|declare|define|choose|rename|add|put|list|leave|break|say|"
    r"remove|include|keep|make|mirror|name|did you mean|declared with|must|needs?|takes?|"
    r"belongs?|only|is not|has no|has|cannot|are|is)\b"
)


def assert_refused(source: Path, code: int, err: str) -> None:
    """Exit 2; every diagnostic of the file: head with line and column, its line, a caret."""
    assert "Traceback" not in err and "internal error" not in err, err
    assert code == 2, f"exit {code}, a mistake not refused:\n{err}"
    text = source.read_text().split("\n")
    lines = err.splitlines()
    heads = [i for i, line in enumerate(lines) if HEAD.match(line)]
    assert heads, f"no FILE:LINE:COL: error: head:\n{err}"
    for i in heads:
        m = HEAD.match(lines[i])
        assert m is not None
        row, col = int(m["line"]), int(m["col"])
        where = Path(m["file"])  # a used file's mistake: told in it, by its path
        if not where.is_file():
            where = source.parent / where.name
        shown = where.read_text().split("\n") if where.name != source.name else text
        assert 1 <= row <= len(shown), lines[i]
        assert i + 2 < len(lines), f"no source line and caret after:\n{err}"
        quoted = [part.strip() for part in lines[i + 1].split("...") if part.strip()]
        assert quoted and all(part in shown[row - 1] for part in quoted), err  # long: elided
        caret = lines[i + 2]
        assert caret.strip().startswith("^") and set(caret.strip()) <= {"^", "~"}, err
        if "..." not in lines[i + 1]:  # the caret under the column (the line shown indented)
            assert caret.index("^") - lines[i + 1].index(shown[row - 1].strip()) == col - 1 - (
                len(shown[row - 1]) - len(shown[row - 1].lstrip())
            ), err
        assert FIX.search(m["message"]), f"a message that says nothing of a fix: {lines[i]}"


def assert_same_run(folder: Path, source: Path, spec: Spec) -> None:
    args = ["--time", num(spec.rest["time"])]
    if spec.scene:
        args = ["--scene", "run"]
    elif spec.use.run:
        args += ["--controller", spec.use.run]
    elif spec.extends and spec.seed % 2:
        args += ["--controller", "stiff"]
    else:
        args += ["--controller", "hop"]
    if spec.second_creature:
        args += ["--creature", "walker"]
    runs = {}
    for backend in ("python", "c"):
        out = folder / f"run_{backend}"
        argv = ["run", str(source), *args, "--backend", backend, "-o", str(out)]
        code, err = legdsl_in_process([*argv, "--generated", str(folder / "generated")])
        assert "Traceback" not in err and "internal error" not in err, err
        assert code in (0, 3, 4), f"legdsl {' '.join(argv)}: exit {code}\n{err}"
        runs[backend] = (code, (out / "trajectory.npz").read_bytes())
    assert runs["python"][0] == runs["c"][0], f"exit {runs['python'][0]} vs {runs['c'][0]}"
    assert runs["python"][1] == runs["c"][1], "trajectory.npz differs between the backends"


def check_file(seed: int, folder: Path) -> None:
    spec = draw(seed)
    source = folder / f"lang{seed}.leg"
    source.write_text(file_text(spec))
    (folder / "parts.leg").write_text(PARTS)
    (folder / "lib").mkdir(exist_ok=True)
    for name, text in files(spec.use, _role_line(spec)[0]).items():
        (folder / name).write_text(text)
    code, err = legdsl_in_process(["check", str(source)])
    if spec.mistake or spec.use.mistake:
        assert_refused(source, code, err)
        assert spec.mistake or USE_MISTAKE_SAYS[spec.use.mistake] in err, err
        return
    assert "Traceback" not in err and "internal error" not in err, err
    assert code == 0, f"a valid file refused: exit {code}\n{err}"
    assert_same_run(folder, source, spec)


SEEDS = range(FIRST_SEED, FIRST_SEED + COUNT)


@pytest.mark.parametrize("seed", SEEDS)
def test_random_language_file_runs_alike_or_is_refused_well(
    seed: int, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    rerun = f"LEGDSL_RANDOM_LANGUAGE_SEED={seed} LEGDSL_RANDOM_LANGUAGE=1"
    with told_with_seed(f"random language file of seed {seed}", rerun, lambda: _shown(seed)):
        check_file(seed, tmp_path)


def _shown(seed: int) -> str:
    """The drawn file, its mistake and the files it uses."""
    spec = draw(seed)
    mistake = f"mistake: {spec.mistake or spec.use.mistake or 'none'}\n"
    used = files(spec.use, _role_line(spec)[0]).items()
    return mistake + file_text(spec) + "".join(f"--- {n}\n{t}" for n, t in used)
