"""The ``legdsl run`` command that makes a recorded run again, rebuilt from its run.json.

A run of a creature changed since (``legdsl.analysis.recorded``) is refused with this
command: everything the run was given, so that running it records the same run on the
changed creature rather than another one. Each option is given where a plain ``legdsl run``
would choose another value (or where the file's ``simulation`` block could); ``--set``
values are written in SI with their units (``--set speed=1.5m/s``), a ``--scale`` run's as
given for the scaled creature (run.json keeps them as the unscaled model ran them), and a
scene's own values and switches are left to ``--scene``.
"""

from __future__ import annotations

import math
import os
import shlex
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from legdsl.ir.model import Model, setting_kind
from legdsl.ir.paths import PathSpec, number
from legdsl.ir.scene import Scene
from legdsl.lang.scaling import factor
from legdsl.lang.units import KINDS, Dim, si_unit
from legdsl.sim.run_loop import RunOptions, default_control_dt

# a --set value: (NAME, SI value, time after '@' or None)
Setting = tuple[str, float, float | None]


def rerun_command(
    source: Path, directory: Path, info: dict[str, Any], model: Model, several: bool = False
) -> str:
    """``legdsl run SOURCE ... --out DIRECTORY`` for the run in ``directory`` (``info`` its
    run.json, ``model`` the creature as the file now has it, ``several``: the file has other
    creatures too), quoted for a shell."""
    scene = next((s for s in model.scenes if s.name == info.get("scene")), None)
    words = ["legdsl", "run", str(source), *(["--creature", model.name] if several else [])]
    if info.get("scene"):
        words += ["--scene", str(info["scene"])]
    elif info.get("controller"):
        words += ["--controller", str(info["controller"])]
    if scene is None or not scene.bands:  # a gait table's switches are the table's own
        own = {(w.t, w.controller) for w in scene.switches} if scene is not None else set()
        for w in info.get("switches") or []:
            if (w["t"], w["controller"]) not in own:
                words += ["--switch", f"{_written(w['t'])}s={w['controller']}"]
    scale = info.get("scale")
    words += list(_options(info.get("options") or {}, model, scale))
    if scale is not None:
        words += ["--scale", _written(scale)]
    for name, value, at in _settings(info, model, scale, scene):
        when = f"@{_written(at)}s" if at is not None else ""
        words += ["--set", f"{name}={_written(value)}{_unit(name, model, info)}{when}"]
    for text in _paths(info, model):
        words += ["--path", text]
    words += _generated(directory, info)
    return shlex.join([*words, "--out", str(directory)])


def _generated(directory: Path, info: dict[str, Any]) -> list[str]:
    """``--generated DIR`` where run.json records the folder the run's modules were in
    (``legdsl.pipeline.generated.recorded_folder``): from here through the run directory
    where it is found so (the two moved together), else its absolute path; nothing where
    that is the default, ``generated`` here."""
    folder = info.get("generated")
    if not isinstance(folder, dict):
        return []
    from_run, absolute = folder.get("from_run"), folder.get("absolute")
    near = os.path.normpath(directory / from_run) if isinstance(from_run, str) else None
    if near is not None and (Path(near).is_dir() or not isinstance(absolute, str)):
        return ["--generated", near] if near != "generated" else []  # the default's own
    return ["--generated", absolute] if isinstance(absolute, str) else []


def _written(value: float) -> str:
    """A value as short as it reads back the same."""
    return number(float(value))


def _rounded(value: float) -> float:
    """A value converted (scaled back, radians to degrees) to 12 digits: its last bits are
    the conversion's rounding, which would only lengthen the command."""
    return float(f"{value:.12g}")


def _options(options: dict[str, Any], model: Model, scale: float | None) -> Iterator[str]:
    """The options that a plain ``legdsl run`` would not choose as the run had them: the
    step, control interval and recording rate wherever the file's simulation block sets its
    own (or the run was scaled, which scales the block's)."""
    runner, sim = RunOptions(), model.simulation
    if isinstance(options.get("duration"), int | float):
        yield from ("--time", f"{_written(options['duration'])}s")
    dt = options.get("dt")
    timing = {
        "dt": ("--dt", "s", runner.dt),
        "control_dt": ("--control-dt", "s", default_control_dt(dt) if dt else runner.control_dt),
        "record_rate": ("--record-rate", "Hz", runner.record_rate),
    }
    for key, (flag, unit, default) in timing.items():
        value = options.get(key)
        if value is not None and (value != default or getattr(sim, key) is not None or scale):
            yield from (flag, f"{_written(value)}{unit}")
    if options.get("integrator", runner.integrator) != runner.integrator:
        yield from ("--integrator", str(options["integrator"]))
    for key, flag in (("drop", "--drop"), ("fall_height", "--fall-height")):
        if isinstance(options.get(key), str):  # --fall-height off
            yield from (flag, str(options[key]))
        elif options.get(key) is not None:
            yield from (flag, f"{_written(options[key])}m")
    tilt = options.get("fall_tilt")
    if tilt is not None and not math.isclose(tilt, runner.fall_tilt):
        yield from ("--fall-tilt", f"{_written(_rounded(math.degrees(tilt)))}deg")


def _settings(
    info: dict[str, Any], model: Model, scale: float | None, scene: Scene | None
) -> list[Setting]:
    """The run's ``--set`` values (a scaled run's for the scaled creature), but those of its
    ``scene``, which ``--scene`` gives."""
    recorded = info.get("settings") or {}
    given: list[Setting] = [
        *((n, v, None) for key in ("actuators", "inputs", "params")
          for n, v in (recorded.get(key) or {}).items()),
        *((f"{c}.{n}", v, None) for c, own in (recorded.get("by_controller") or {}).items()
          for n, v in own.items()),
        *((c["input"], c["value"], c["t"]) for c in recorded.get("schedule") or []),
    ]  # fmt: skip
    tick = math.sqrt(scale) if scale is not None else 1.0
    if scale is not None:  # run.json has them as the unscaled model ran them
        given = [
            (n, _rounded(v * factor(_dimension(n, model, info), scale)),
             None if t is None else _rounded(t * tick))
            for n, v, t in given
        ]  # fmt: skip
    for v in scene.values if scene is not None else ():
        ran = v.value * factor(v.dim, scale or 1.0), None if v.at is None else v.at * tick
        given = [s for s in given if not _same(s, (v.name, *ran))]
    return given


def _same(a: Setting, b: Setting) -> bool:
    times = a[2] is b[2] is None or (
        a[2] is not None and b[2] is not None and math.isclose(a[2], b[2])
    )
    return a[0] == b[0] and math.isclose(a[1], b[1], abs_tol=1e-12) and times


def _dimension(name: str, model: Model, info: dict[str, Any]) -> Dim | None:
    """What a ``--set`` NAME measures: an actuator's setting, a controller's own (CONTROLLER.
    NAME), or the input or parameter of the run's controllers; None if the file no longer has
    it (the run then says so)."""
    owner, dot, key = name.partition(".")
    controllers = {c.name: c for c in model.controllers}
    actuators = {a.name: a for a in model.actuators}
    if dot and owner in actuators:
        return KINDS[setting_kind(key, actuators[owner].rotary)][0]
    ran = [info.get("controller"), *(w["controller"] for w in info.get("switches") or [])]
    names = [owner] if dot else [*ran, *controllers]
    for c in (controllers[n] for n in names if n in controllers):
        found = next((x.dim for x in (*c.inputs, *c.params) if x.name == (key or owner)), None)
        if found is not None:
            return found
    return None


def _unit(name: str, model: Model, info: dict[str, Any]) -> str:
    dim = _dimension(name, model, info)
    return si_unit(dim) if dim is not None else ""


def _paths(info: dict[str, Any], model: Model) -> list[str]:
    """``--path NAME=SHAPE`` for each path the run followed that no controller of the file
    declares so (in the creature's metres, as run.json has it)."""
    declared = {(p.name, p.describe()) for c in model.controllers for p in c.paths}
    out = []
    for entry in info.get("paths") or []:
        spec = PathSpec.from_json(entry)
        if (spec.name, spec.describe()) not in declared:
            out.append(f"{spec.name}={spec.describe()}")
    return out
