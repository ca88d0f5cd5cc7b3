"""``legdsl run``: make sure the generated module is current, simulate, write the run directory.

The run directory gets ``trajectory.npz`` and ``trajectory.csv`` (see
``legdsl.sim.trajectory``) and ``run.json``: every input, parameter and option,
the legdsl version, the events (touchdowns, liftoffs, state changes), the
status and its message.
"""

from __future__ import annotations

import importlib.util
import json
import re
import sys
from dataclasses import asdict, dataclass
from pathlib import Path
from types import ModuleType
from typing import Any

from legdsl import __version__
from legdsl.codegen.python.dynamics import controller_fingerprint, model_fingerprint
from legdsl.ir.model import SETTABLE, Model, setting_kind
from legdsl.ir.paths import PathSpec
from legdsl.lang.errors import UsageError
from legdsl.lang.units import KINDS, Dim, UnitError, parse_unit
from legdsl.sim.machine import InputChange
from legdsl.sim.simulate import RunOptions, RunResult


def import_module_file(path: Path, name: str) -> ModuleType:
    spec = importlib.util.spec_from_file_location(name, path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def load_dynamics(model: Model, source: Path, generated: Path, log: Any = None) -> ModuleType:
    """The creature's generated dynamics module, compiled first if missing or stale."""
    return _load(
        model,
        source,
        generated,
        "dynamics.py",
        ("MODEL_FINGERPRINT", model_fingerprint(model)),
        log,
    )


def load_controller(
    model: Model, controller: str, source: Path, generated: Path, log: Any = None
) -> ModuleType:
    """The generated control module of one of the creature's controllers (compiled if needed)."""
    names = [c.name for c in model.controllers]
    if controller not in names:
        raise UsageError(
            f"--controller {controller}: creature '{model.name}' has no such controller "
            f"(it has {', '.join(names) or 'none'})"
        )
    fingerprint = controller_fingerprint(model, model.controller(controller))
    return _load(
        model, source, generated, f"control_{controller}.py", ("FINGERPRINT", fingerprint), log
    )


def _load(
    model: Model, source: Path, generated: Path, file: str, stamp: tuple[str, str], log: Any
) -> ModuleType:
    """Import ``generated/NAME/file`` if its fingerprint constant matches, else compile first."""
    path = generated / model.name / file
    label = f"legdsl_generated_{model.name}_{path.stem}"
    if path.is_file():
        module = import_module_file(path, label)
        if getattr(module, stamp[0], None) == stamp[1]:
            return module
        reason = "stale"
    else:
        reason = "missing"
    from legdsl.pipeline.compile import compile_model, write_generated

    if log is not None:
        print(f"legdsl: {path} is {reason}; compiling {source}", file=log)
    write_generated(compile_model(source, model.name), generated)
    return import_module_file(path, label + "_new")


def parse_setting(text: str) -> tuple[str, float, Dim | None]:
    """``NAME=VALUE`` with an optional unit right after the number (``hip_servo.setpoint=10deg``)."""
    name, sep, value = text.partition("=")
    if not sep or not name.strip():
        raise UsageError(f"--set {text!r}: write NAME=VALUE, e.g. --set hip_servo.setpoint=10deg")
    match = re.fullmatch(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(\S*)\s*", value)
    if match is None:
        raise UsageError(f"--set {text!r}: {value!r} is not a number with an optional unit")
    magnitude, unit = float(match.group(1)), match.group(2)
    if not unit:
        return name.strip(), magnitude, None
    try:
        factor, dim = parse_unit(unit)
    except UnitError as e:
        raise UsageError(f"--set {text!r}: {e}") from None
    return name.strip(), magnitude * factor, dim


@dataclass
class Settings:
    """``--set`` options sorted by what they set (all values in SI)."""

    actuators: dict[str, float]  # ACTUATOR.SETTING -> value, before the run
    inputs: dict[str, float]  # controller inputs at t = 0
    params: dict[str, float]  # controller parameters
    schedule: list[InputChange]  # NAME=VALUE@T: an input changed during the run

    def as_json(self) -> dict[str, Any]:
        return {
            "actuators": self.actuators,
            "inputs": self.inputs,
            "params": self.params,
            "schedule": [{"t": c.t, "input": c.name, "value": c.value} for c in self.schedule],
        }


def sort_settings(texts: list[str], model: Model, control: ModuleType | None) -> Settings:
    """Read ``--set`` options: ``ACTUATOR.SETTING=V``, ``INPUT=V``, ``PARAM=V`` or ``INPUT=V@T``."""
    out = Settings({}, {}, {}, [])
    for text in texts:
        at = None
        if "@" in text:
            text, _, when = text.rpartition("@")
            _, seconds, dim = parse_setting(f"t={when}")
            if dim not in (None, KINDS["time"][0]):
                raise UsageError(f"--set ...@{when}: the time after '@' is in seconds, e.g. @4s")
            at = seconds
        name, value, dim = parse_setting(text)
        if "." in name:
            if at is not None:
                raise UsageError(f"--set {text}@...: only controller inputs change during a run")
            _check_actuator_setting(model, name, value, dim)
            out.actuators[name] = value
            continue
        if control is None:
            raise UsageError(
                f"--set {name}: '{name}' is a controller input; choose a controller with --controller"
            )
        if name in control.INPUTS:
            if at is None:
                out.inputs[name] = value
            else:
                out.schedule.append(InputChange(at, name, value))
        elif name in control.PARAMS and at is None:
            out.params[name] = value
        else:
            known = ", ".join([*control.INPUTS, *control.PARAMS]) or "none"
            raise UsageError(
                f"--set {name}: controller {control.CONTROLLER} has no input or parameter {name!r} (it has {known})"
            )
    return out


def _check_actuator_setting(model: Model, name: str, value: float, dim: Dim | None) -> None:
    by_name = {a.name: a for a in model.actuators}
    actuator, _, key = name.partition(".")
    if actuator not in by_name or not key:
        raise UsageError(
            f"--set {name}: name an actuator setting such as ACTUATOR.setpoint "
            f"(actuators: {', '.join(by_name) or 'none'})"
        )
    a = by_name[actuator]
    if key not in SETTABLE[a.kind]:
        raise UsageError(f"--set {name}: a {a.kind} has {', '.join(SETTABLE[a.kind])}")
    kind = setting_kind(key, a.rotary)
    want, example_unit = KINDS[kind]
    if dim is None and value != 0:
        raise UsageError(f"--set {name}: give a unit, e.g. {name}={value:g}{example_unit}")
    if dim is not None and dim != want:
        raise UsageError(f"--set {name}: expected a {kind} ({example_unit})")


def progress_bar(t: float, total: float) -> None:
    width = 30
    frac = min(1.0, t / total) if total > 0 else 1.0
    bar = "#" * int(frac * width) + "." * (width - int(frac * width))
    end = "\n" if frac >= 1.0 else ""
    print(f"\r[{bar}] {t:6.2f} / {total:.2f} s", end=end, file=sys.stderr, flush=True)


def write_run(
    out: Path, model: Model, options: RunOptions, result: RunResult, extra: dict[str, Any]
) -> None:
    """Write trajectory.npz, trajectory.csv and run.json into ``out``."""
    out.mkdir(parents=True, exist_ok=True)
    result.trajectory.save(out)
    info = {
        "legdsl": __version__,
        "source": model.source,
        "creature": model.name,
        "options": asdict(options),
        **extra,
        "status": result.status,
        "message": result.message,
        "steps": result.steps,
        "sim_time": round(result.sim_time, 9),
        "samples": len(result.trajectory),
        "events": result.events,
    }
    text = json.dumps(info, indent=2, allow_nan=False) + "\n"
    tmp = out / "run.json.tmp"
    tmp.write_text(text)
    tmp.replace(out / "run.json")


def summary(model: Model, result: RunResult) -> str:
    """The table printed after a run."""
    tr = result.trajectory
    touchdowns = sum(1 for e in result.events if e["kind"] == "touchdown")
    liftoffs = sum(1 for e in result.events if e["kind"] == "liftoff")
    rows = [
        ("creature", f"{model.name} ({model.nv} DOF)"),
        ("status", result.status + (f": {result.message}" if result.message else "")),
        ("simulated", f"{result.sim_time:.3f} s in {result.steps} steps"),
        ("wall time", f"{result.wall_time:.2f} s (real-time factor {result.real_time_factor:.2f})"),
        ("samples", str(len(tr))),
        ("touchdowns / liftoffs", f"{touchdowns} / {liftoffs}"),
    ]
    if len(tr):
        energy0 = tr.kinetic[0] + tr.potential[0] + tr.elastic[0]
        energy1 = tr.kinetic[-1] + tr.potential[-1] + tr.elastic[-1]
        rows += [
            ("final root position", "(" + ", ".join(f"{x:.3f}" for x in tr.root_pos[-1]) + ") m"),
            ("mean speed along x, start to end", f"{_mean_speed(tr):.3f} m/s"),
            ("total energy start -> end", f"{energy0:.3f} J -> {energy1:.3f} J"),
        ]
    width = max(len(r[0]) for r in rows)
    return "\n".join(f"  {k:<{width}}  {v}" for k, v in rows)


def _mean_speed(tr: Any) -> float:
    if len(tr) < 2 or tr.t[-1] <= tr.t[0]:
        return 0.0
    return float((tr.com[-1, 0] - tr.com[0, 0]) / (tr.t[-1] - tr.t[0]))


def parse_path_option(text: str) -> PathSpec:
    """``--path [NAME=]SHAPE`` (the .leg file's syntax) or ``--path FILE.csv`` (x,y per line).

    Without ``NAME=`` the name is empty: the controller's only path (see
    ``legdsl.sim.machine.resolve_paths``).
    """
    from legdsl.check.controller import check_path
    from legdsl.ir.paths import read_waypoints
    from legdsl.lang.errors import Diagnostics
    from legdsl.lang.parser import parse_value

    match = re.match(r"\s*([A-Za-z_][A-Za-z0-9_]*)\s*=(?!=)", text)
    name, shape = ("", text) if match is None else (match.group(1), text[match.end() :])
    if re.fullmatch(r"\s*[^()]*\.(csv|txt)\s*", shape):
        file = Path(shape.strip())
        if not file.is_file():
            raise UsageError(f"--path {text}: no such file {file}")
        return read_waypoints(file, name)
    # parse the shape where it stands in the option, so the caret points into it
    padded = " " * (len(text) - len(shape)) + shape
    value = parse_value(padded, "--path")
    diag = Diagnostics({"--path": text})
    spec = check_path(name, value, diag)
    diag.raise_if_any()
    assert spec is not None
    return spec


def path_summary(report: dict[str, Any]) -> str:
    """The path rows printed after a run's summary."""
    from legdsl.analysis.metrics import path_rows

    rows = path_rows(report)
    width = max(len(r[0]) for r in rows)
    return "\n".join(f"  {k:<{width}}  {v}" for k, v in rows)
