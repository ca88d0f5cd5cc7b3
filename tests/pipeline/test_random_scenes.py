"""Random scenes: a copy of the shipped biped or quadruped with a scene drawn from a seed
(controllers switched at drawn times, among them equal times, times past the run's end and
switches to the running controller; `set`, `at T set` and `set CONTROLLER.NAME` of inputs,
parameters and actuator settings in drawn units; sometimes a gait table by speed), run for a
second or two on both backends. Each run ends as the runtime tells (ok, fell or diverged, or a
one-line refusal), never an internal error; the backends agree to the byte; the scene runs as
the --controller/--set/--switch/--time flags it stands for (docs/language.md, "Scenes"); every
switch the run reached took over, was superseded or is told as not made.

LEGDSL_RANDOM_SCENES=60 LEGDSL_RANDOM_SCENE_SEED=0 runs seeds 0-59 (CI: seed 0; seed 1, the quadruped,
27 s, with LEGDSL_RANDOM_SCENES=2)."""

from __future__ import annotations

import json
import os
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TypeVar

import numpy as np
import pytest
from conftest import CREATURES, shipped_model
from runtime_helpers import legdsl_in_process, needs_c_compiler
from seeded import told_with_seed

from legdsl.cli.common import EXIT_DIVERGED, EXIT_FELL, EXIT_USER_ERROR
from legdsl.ir.model import SETTABLE, Model, setting_kind
from legdsl.lang.units import KINDS, Dim, parse_unit, si_unit

pytestmark = needs_c_compiler
T = TypeVar("T")

COUNT = int(os.environ.get("LEGDSL_RANDOM_SCENES", "1"))
FIRST = int(os.environ.get("LEGDSL_RANDOM_SCENE_SEED", "0"))
RERUN = "LEGDSL_RANDOM_SCENES=1 LEGDSL_RANDOM_SCENE_SEED={}"

# written units to draw from, by dimension (M, L, T, angle); others use the SI unit
UNITS: dict[Dim, list[str]] = {
    (0, 1, -1, 0): ["m/s", "cm/s", "mm/s"],
    (0, 1, 0, 0): ["m", "cm", "mm"],
    (0, 0, 1, 0): ["s", "ms"],
    (0, 0, 0, 1): ["rad", "deg"],
    (0, 0, -1, 1): ["rad/s", "deg/s"],
    (0, 0, 0, 0): [""],
}


def _units(dim: Dim) -> list[str]:
    return UNITS.get(dim) or [si_unit(dim)]


@dataclass
class Draw:
    """A scene drawn from ``seed`` for a shipped creature: its lines, and the flags it stands
    for (a gait table's worked out by ``gaits_as_flags``)."""

    seed: int
    rng: np.random.Generator
    model: Model
    duration: float = 0.0
    lines: list[str] = field(default_factory=list)
    flags: list[str] = field(default_factory=list)
    switches: list[tuple[float, str]] = field(default_factory=list)
    # a gait table by speed: (controller, low, high) in m/s, and the speed commands (t, v)
    bands: list[tuple[str, float | None, float | None]] = field(default_factory=list)
    speeds: list[tuple[float, float, str]] = field(default_factory=list)

    def pick(self, options: Sequence[T]) -> T:
        return options[int(self.rng.integers(len(options)))]

    def quantity(self, si: float, dim: Dim) -> tuple[str, str]:
        """``si`` written in a drawn unit of ``dim``: the scene's text and --set's."""
        unit = str(self.pick(_units(dim)))
        factor = parse_unit(unit)[0] if unit else 1.0
        number = f"{float(np.round(si / factor, 4)):g}"
        return (f"{number} {unit}".rstrip(), f"{number}{unit}")

    def set(self, name: str, si: float, dim: Dim, at: tuple[str, str] | None = None) -> None:
        """``set NAME = ...`` (``at T set`` with ``at``, the scene's and the flag's time) and
        the --set it stands for; a name set twice is left out (a bad scenes' case)."""
        scene, flag = self.quantity(si, dim)
        if at is None and f"set {name} =" in "\n".join(self.lines):
            return
        if at is None:
            self.lines.append(f"set {name} = {scene}")
            self.flags += ["--set", f"{name}={flag}"]
        else:
            self.lines.append(f"at {at[0]} set {name} = {scene}")
            self.flags += ["--set", f"{name}={flag}@{at[1]}"]

    def time(self) -> tuple[float, str, str]:
        """A drawn time of a line: 0, during the run (sometimes the same as another), or past
        its end."""
        t = float(self.pick([0.0, 0.05, 0.3, 0.5, 0.8, 1.0, 1.2, self.duration + 0.5]))
        if self.rng.random() < 0.5:
            t = float(np.round(self.rng.uniform(0.05, self.duration * 1.2), 2))
        scene, flag = self.quantity(t, (0, 0, 1, 0))
        return parse_written(flag), scene, flag


def parse_written(flag: str) -> float:
    number, unit = re.match(r"([-+0-9.e]+)(.*)", flag).groups()  # type: ignore[union-attr]
    return float(number) * (parse_unit(unit)[0] if unit else 1.0)


def draw_scene(seed: int) -> Draw:
    rng = np.random.default_rng(seed)
    name = "biped" if seed % 2 == 0 else "quadruped"
    d = Draw(seed, rng, shipped_model(name))
    d.duration = float(np.round(rng.uniform(0.8, 2.0), 2))
    controllers = {c.name: c for c in d.model.controllers}
    first = str(d.pick(list(controllers)))
    d.lines.append(f"controller {first}")
    d.flags += ["--controller", first]
    used = [first]
    times: set[float] = set()
    if rng.random() < 0.35:
        used = draw_gait_table(d, list(controllers))
    for _ in range(int(rng.integers(0, 5)) if not d.bands else 0):
        t, scene_t, flag_t = d.time()
        if t <= 0 or any(abs(t - u) < 1e-9 for u in times):
            continue  # a switch at 0 or two at one time are refused: the bad scenes' cases
        times.add(t)
        to = str(d.pick([*list(controllers), used[-1]]))  # sometimes the running one again
        used.append(to)
        d.lines.append(f"at {scene_t} switch {to}")
        d.flags += ["--switch", f"{flag_t}={to}"]
        d.switches.append((t, to))
    running = [controllers[n] for n in dict.fromkeys(used)]
    # a gait table's speed is its own commands (one controller's speed is refused)
    inputs = {
        i.name: i
        for c in reversed(running)
        for i in c.inputs
        if not (d.bands and i.name == "speed")
    }
    params = {p.name: p for c in reversed(running) for p in c.params}
    near = lambda v: v * float(rng.uniform(0.8, 1.2))  # noqa: E731
    plain: set[str] = set()
    for _ in range(int(rng.integers(0, 3))):
        i = inputs[str(d.pick(list(inputs)))]
        plain.add(i.name)
        d.set(i.name, near(i.value) if i.value else float(rng.uniform(-0.2, 0.2)), i.dim)
    timed: set[tuple[str, float]] = set()
    for _ in range(int(rng.integers(0, 5))):
        i = inputs[str(d.pick(list(inputs)))]
        t, scene_t, flag_t = d.time()
        if t < 0 or (i.name, t) in timed or (t == 0 and i.name in plain):
            continue  # a value and a command at 0 s of one input are refused: a bad scene
        timed.add((i.name, t))
        d.set(i.name, near(i.value) if i.value else float(rng.uniform(-0.2, 0.2)), i.dim,
              (scene_t, flag_t))  # fmt: skip
    for _ in range(int(rng.integers(0, 3))):
        p = params[str(d.pick(list(params)))]
        d.set(p.name, near(p.value), p.dim)
    for _ in range(int(rng.integers(0, 3))):
        c = running[int(rng.integers(len(running)))]
        v = d.pick([v for v in [*c.inputs, *c.params] if v.name in inputs or v.name in params])
        d.set(f"{c.name}.{v.name}", near(v.value), v.dim)
    for _ in range(int(rng.integers(0, 3))):
        a = d.model.actuators[int(rng.integers(len(d.model.actuators)))]
        key = str(d.pick(list(SETTABLE[a.kind])))
        value = dict(a.params).get(key, 0.0)
        dim = KINDS[setting_kind(key, a.rotary)][0]
        d.set(f"{a.name}.{key}", near(value) if value else float(rng.uniform(-0.1, 0.1)), dim)
    if d.bands:
        gaits_as_flags(d)
    scene_time, flag_time = d.quantity(d.duration, (0, 0, 1, 0))
    d.duration = parse_written(flag_time)
    d.lines.append(f"time {scene_time}")
    d.flags += ["--time", flag_time]
    return d


def draw_gait_table(d: Draw, controllers: list[str]) -> list[str]:
    """``gait by speed { ... }`` over two or three controllers, its bands overlapping by a drawn
    margin, with speed commands (at drawn times, 0 among them) away from the bands' edges; the
    scene's controller line kept or left out."""
    rng = d.rng
    names = [str(n) for n in rng.choice(controllers, int(rng.integers(2, 4)), replace=False)]
    cuts = sorted(float(np.round(rng.uniform(0.8, 2.8), 2)) for _ in names[1:])
    for k in range(1, len(cuts)):  # two equal cuts: the band between them never chosen
        cuts[k] = max(cuts[k], round(cuts[k - 1] + 0.01, 2))
    overlap = float(np.round(rng.uniform(0.0, 0.3), 2))
    for k, name in enumerate(names):
        low = cuts[k - 1] - overlap if k > 0 else None
        high = cuts[k] + overlap if k < len(cuts) else None
        d.bands.append((name, low, high))
    words = [f"{n}{f' from {lo:g} m/s' if lo is not None else ''}"
             f"{f' to {hi:g} m/s' if hi is not None else ''}" for n, lo, hi in d.bands]  # fmt: skip
    d.lines.append(f"gait by speed {{ {'; '.join(words)} }}")
    if rng.random() < 0.5:  # no controller line: the first command's band starts the run
        d.lines.pop(0)
        d.flags.clear()
    edges = [e for _, lo, hi in d.bands for e in (lo, hi) if e is not None]

    def speed() -> float:
        v = float(np.round(rng.uniform(0.5, 3.2), 2))
        return v if all(abs(v - e) > 0.015 for e in edges) else speed()

    if rng.random() < 0.7:
        d.speeds.append((-1.0, speed(), ""))
        d.lines.append(f"set speed = {d.speeds[-1][1]:g} m/s")
    for _ in range(int(rng.integers(1, 5))):
        t, scene_t, flag_t = d.time()
        if any(abs(t - u) < 1e-9 or (t == 0 and u < 0) for u, _, _ in d.speeds):
            continue  # two at one time, or a value (t = -1) and a command at 0 s: refused
        d.speeds.append((t, speed(), flag_t))
        d.lines.append(f"at {scene_t} set speed = {d.speeds[-1][1]:g} m/s")
    if d.lines[0].startswith("controller "):  # one of the bands holding the first command
        held = [n for n, lo, hi in d.bands if _holds(lo, hi, _first_speed(d))]
        d.lines[0] = f"controller {rng.choice(held)}"
        d.flags[:2] = ["--controller", d.lines[0].split()[1]]
    kept = d.lines[0].split()[1:] if d.lines[0].startswith("controller ") else []
    return list(dict.fromkeys([*kept, *names]))


def _holds(low: float | None, high: float | None, v: float) -> bool:
    return (low is None or v >= low) and (high is None or v <= high)


def _first_speed(d: Draw) -> float:
    """The first speed command: a command at 0 s, else the value, else the controllers'."""
    first = 1.5 if d.model.name == "biped" else 1.0  # every shipped controller's speed
    for t, v, _ in sorted(d.speeds):
        first = v if t <= 0 else first
    return first


def gaits_as_flags(d: Draw) -> None:
    """The flags a gait table stands for, worked out here as docs/language.md says: the start
    (the controller line, else the first band holding the first command: a command at 0 s is
    the first), and a switch where a command leaves the current controller's band."""

    def first_holding(v: float) -> str:
        return next(n for n, lo, hi in d.bands if _holds(lo, hi, v))

    start = d.lines[0].split()[1:] if d.lines[0].startswith("controller ") else []
    current = start[0] if start else first_holding(_first_speed(d))
    if not start:
        d.flags[:0] = ["--controller", current]
    for t, v, flag_t in sorted(d.speeds):
        held = any(n == current and _holds(lo, hi, v) for n, lo, hi in d.bands)
        if t > 0 and not held:
            current = first_holding(v)
            d.switches.append((t, current))
            d.flags += ["--switch", f"{flag_t}={current}"]
    for t, v, flag_t in d.speeds:
        d.flags += ["--set", f"speed={v:g}m/s" + (f"@{flag_t}" if t >= 0 else "")]
    # a band's own values wait for its band: a band the run never takes has none
    idle = {n for n, _, _ in d.bands} - {*start, *d.flags[1:2], *(n for _, n in d.switches)}
    names = {n: {v.name for v in (*c.inputs, *c.params)} for n, _, _ in d.bands
             for c in [d.model.controller(n)]}  # fmt: skip
    chosen = {*start, *d.flags[1:2], *(n for _, n in d.switches)}
    waiting = set().union(*(names[n] for n in idle)) - set().union(
        *(names.get(n) or {v.name for c in [d.model.controller(n)] for v in (*c.inputs, *c.params)}
          for n in chosen))  # fmt: skip
    for k in range(len(d.flags) - 1, 0, -1):
        name = d.flags[k].partition("=")[0]
        if d.flags[k - 1] == "--set" and (name.partition(".")[0] in idle or name in waiting):
            del d.flags[k - 1 : k + 1]


def scene_text(d: Draw) -> str:
    body = "\n".join(f"  {line}" for line in d.lines)
    return f"scene drawn {{\n{body}\n}}\n"


def write_copy(d: Draw, root: Path) -> Path:
    """The shipped file with the drawn scene added (its `use raibert` is the standard
    library's, so the copy resolves it from anywhere)."""
    source = (CREATURES / f"{d.model.name}.leg").read_text()
    assert re.findall(r"^\s*use\s+(\S+)", source, re.M) == ["raibert"]
    path = root / f"{d.model.name}.leg"
    path.write_text(source + "\n" + scene_text(d))
    return path


def _run(argv: list[str], out: Path) -> tuple[int, str, dict | None, dict | None]:
    code, err = legdsl_in_process([*argv, "--out", str(out)])
    assert "Traceback" not in err and "internal error" not in err, err
    assert code in (0, EXIT_FELL, EXIT_DIVERGED, EXIT_USER_ERROR), (code, err)
    if code == EXIT_USER_ERROR:  # refused before it ran (a setting too stiff for the step)
        assert err.startswith("legdsl: ") and "\n" not in err.strip(), err
        return code, err, None, None
    info = json.loads((out / "run.json").read_text())
    with np.load(out / "trajectory.npz") as arrays:
        return code, err, info, {k: arrays[k] for k in arrays.files}


SAME = ("status", "message", "cause", "ended_at", "steps", "sim_time", "samples", "events",
        "segments", "switches", "inputs", "params", "controller")  # fmt: skip


def _same_runs(a: tuple, b: tuple, what: str) -> None:
    assert a[0] == b[0], f"{what}: exit {a[0]} vs {b[0]}: {a[1]} | {b[1]}"
    if a[2] is None:
        assert a[1] == b[1], what
        return
    for key in SAME:
        assert a[2].get(key) == b[2].get(key), f"{what}: {key}: {a[2].get(key)} vs {b[2].get(key)}"
    assert a[3].keys() == b[3].keys(), what
    for name in a[3]:
        assert a[3][name].tobytes() == b[3][name].tobytes(), f"{what}: array {name} differs"


def _switch_notes(err: str) -> list[str]:
    return [line for line in err.splitlines() if "switch" in line]


def _switches_told(d: Draw, run: tuple) -> None:
    """Every switch the run reached took over (a switch event at its segment's start), was
    superseded by the next, or is told as waiting when the run ended."""
    code, err, info, _ = run
    if info is None:
        return
    segments, end = info["segments"] if d.switches else [], info["sim_time"]
    events = [(e["t"], e["controller"]) for e in info["events"] if e["kind"] == "switch"]
    assert events == [(s["from"], s["controller"]) for s in segments[1:]]
    made = [(s.get("asked", s["from"]), s["controller"]) for s in segments[1:]]
    listed = {(w["t"], w["controller"]): w for w in info.get("switches", [])}
    for t, to in d.switches:
        entry = listed[t, to]
        if t > end or "superseded_by" in entry:
            assert (t, to) not in made
            if "superseded_by" in entry:
                assert f"'at {t:g} s switch {to}' of scene drawn was still waiting" in err, err
            continue
        if not any(abs(t - m) < 1e-9 and c == to for m, c in made):
            assert code != 0 or f"'at {t:g} s switch {to}' of scene drawn" in err, (t, to, err)


def check_draw(d: Draw, root: Path, generated: Path) -> None:
    root.mkdir(parents=True, exist_ok=True)
    path = write_copy(d, root)
    gen = generated / d.model.name
    base = ["run", str(path), "--generated", str(gen)]
    scene = [*base, "--scene", "drawn"]
    python = _run([*scene, "--backend", "python"], root / "py")
    c = _run([*scene, "--backend", "c"], root / "c")
    _same_runs(python, c, "python vs c")
    assert _switch_notes(python[1]) == _switch_notes(c[1]), (python[1], c[1])
    flags = _run([*base, *d.flags, "--backend", "c"], root / "flags")
    _same_runs(c, flags, "scene vs flags")
    _switches_told(d, c)


SEEDS = list(range(FIRST, FIRST + COUNT))


@pytest.fixture(scope="module")
def generated(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """One generated tree for the module's copies: each creature compiles once."""
    return tmp_path_factory.mktemp("generated")


@pytest.mark.parametrize("seed", SEEDS)
def test_a_random_scene_runs_as_its_flags_on_both_backends(
    seed: int, tmp_path: Path, generated: Path
) -> None:
    d = draw_scene(seed)
    with told_with_seed(f"random scene seed {seed}", RERUN.format(seed), lambda: scene_text(d)):
        check_draw(d, tmp_path / "draw", generated)


def test_a_switch_past_the_end_is_told_alike_on_both_backends(
    tmp_path: Path, generated: Path
) -> None:
    """Found by this file: the C backend's run never ticked the Python switching machine before
    3 s, so its note said a switch waits up to 1 s where the Python run's said 1.01 s (the
    biped's natural scale). The scene's switches come after the end (no wait is told for
    them): the one at 0.45 s waits for a liftoff when the run ends."""
    told = []
    for backend in ("python", "c"):
        argv = ["run", str(CREATURES / "biped.leg"), "--scene", "run_gallop_run", "--time", "0.5",
                "--switch", "0.45s=gallop",
                "--generated", str(generated / "biped"), "--backend", backend]  # fmt: skip
        code, err, _, _ = _run(argv, tmp_path / backend)
        assert code == 0
        told.append(_switch_notes(err))
    assert told[0] == told[1] and any("waits up to 1.01 s" in line for line in told[0]), told


# Hand-picked mistakes: each refused at its place (file:line:col and a caret), saying what to
# write instead, never a traceback.
BAD = {
    "wrong unit": ("set speed = 2 m", "write e.g. 2 m/s"),
    "unknown controller": ("at 1 s switch galop", "did you mean 'gallop'"),
    "unknown name": ("set sped = 2 m/s", "did you mean 'speed'"),
    "negative time": ("at -1 s set speed = 2 m/s", "must not be negative: 0 s is the start"),
    "switch at the start": ("at 0 s switch gallop", "the scene's 'controller' starts it"),
    "parameter at a time": ("at 1 s set kp = 200 N*m/rad", "only inputs change during a run"),
    "actuator at a time": ("at 1 s set hip_l_roll.kp = 200 N*m/rad", "set before it starts"),
    "own value at a time": ("at 1 s set run.k_speed = 50 ms", "write 'at T set k_speed"),
    "controller not run": ("set gallop.k_speed = 50 ms", "switch to it with 'at T switch"),
    "two switches at one time": ("at 1 s switch gallop\n  at 1000 ms switch run", "to one controller at a time: keep one"),
    "two commands at one time": (
        "at 1 s set speed = 1 m/s\n  at 1 s set speed = 2 m/s", "keep one"),
    "one name set twice": ("set speed = 1 m/s\n  set speed = 2 m/s", "keep one"),
    "a value and a command at the start": (
        "set speed = 1 m/s\n  at 0 s set speed = 2 m/s", "replaces that value before it is used"),
}  # fmt: skip


@pytest.mark.parametrize("mistake", list(BAD))
def test_a_bad_scene_is_refused_at_its_place(mistake: str, tmp_path: Path) -> None:
    line, fix = BAD[mistake]
    source = (CREATURES / "biped.leg").read_text()
    path = tmp_path / "biped.leg"
    path.write_text(f"{source}\nscene bad {{\n  controller run\n  {line}\n  time 1 s\n}}\n")
    code, err = legdsl_in_process(["check", str(path)])
    assert code == EXIT_USER_ERROR and "Traceback" not in err, err
    at = re.search(rf"{re.escape(str(path))}:(\d+):(\d+): error: (.*)", err)
    assert at is not None and fix in at.group(3), err
    lines = err.splitlines()
    caret = lines[lines.index(at.group(0)) + 2]
    assert caret.strip().startswith("^") and caret.index("^") > 0, err


def test_two_scenes_of_one_name_are_refused(tmp_path: Path) -> None:
    source = (CREATURES / "biped.leg").read_text()
    path = tmp_path / "biped.leg"
    path.write_text(f"{source}\nscene run_gallop_run {{ controller run }}\n")
    first = source.splitlines().index("scene run_gallop_run {") + 1
    code, err = legdsl_in_process(["check", str(path)])
    assert code == EXIT_USER_ERROR and "Traceback" not in err, err
    assert re.search(rf"{re.escape(str(path))}:\d+:\d+: error: scene 'run_gallop_run' is "
                     rf"defined twice \(first at line {first}\); give each scene of a creature a "
                     "name of its own", err), err  # fmt: skip


GAITS = "gait by speed { gallop to 1.6 m/s; run from 1.4 m/s }"


@pytest.mark.parametrize(
    "lines, flags",
    [  # found by the random scenes (seed 8 of the first draft, seed 1)
        (  # a command at 0 s is the first: it chooses the band the run starts in
            "at 0 s set speed = 2 m/s",
            ["--controller", "run", "--set", "speed=2m/s@0s"],
        ),
        (  # run's band is never taken: its own value waits for it, refused by no --set
            "set speed = 1 m/s\n  set run.k_speed = 50 ms",
            ["--controller", "gallop", "--set", "speed=1m/s"],
        ),
        (  # nor is a name only run has (seed 18: the gallop's stagger)
            "set speed = 1 m/s\n  set balance = 2",
            ["--controller", "gallop", "--set", "speed=1m/s"],
        ),
    ],
)
def test_a_gait_table_scene_runs_as_its_flags(
    lines: str, flags: list[str], tmp_path: Path, generated: Path
) -> None:
    """`at 0 s set speed` outside the first band was refused as '--switch 0.0s=run: a switch
    comes after the start', a flag nobody wrote; `set run.k_speed` of a band the commands never
    reach as '--set run.k_speed=0.05s: controller 'run' does not run here'."""
    source = (CREATURES / "biped.leg").read_text()
    path = tmp_path / "biped.leg"
    path.write_text(f"{source}\nscene gaits {{\n  {GAITS}\n  {lines}\n  time 0.3 s\n}}\n")
    base = ["run", str(path), "--generated", str(generated / "biped"), "--backend", "c"]
    scene = _run([*base, "--scene", "gaits"], tmp_path / "scene")
    assert scene[0] == 0, scene[1]
    _same_runs(scene, _run([*base, *flags, "--time", "0.3"], tmp_path / "flags"), "flags")
