"""``run()``'s arguments as ``legdsl run`` reads them (``session_args``), and its options: each
with its unit, a misspelt one named, and the step, control interval and record rate the
creature's ``simulation`` block sets where none is given (a scaled creature's, or a small
one's finer step)."""

from __future__ import annotations

import math
import numbers
from collections.abc import Mapping
from dataclasses import fields
from typing import Any

import numpy as np

from legdsl.api.arguments import a_float, seconds, setting_text, with_units
from legdsl.check.values import did_you_mean
from legdsl.ir.model import Model
from legdsl.lang.errors import UsageError
from legdsl.lang.units import bare_number
from legdsl.pipeline.options import OFF_VALUES, RUN_NUMERIC, is_off
from legdsl.pipeline.settings import refuse_repeated
from legdsl.sim.run_loop import RunOptions

RUN_EXAMPLES = {"dt": "0.4 ms", "control_dt": "2 ms", "record_rate": "200 Hz",
                "fall_height": "5 cm", "fall_tilt": "60 deg", "drop": "2 cm"}  # fmt: skip
ARGUMENTS = ["controller", "set", "time", "path", "switch", "scene"]  # a typo of one is named


def run_options(model: Model, time: object, options: dict[str, Any]) -> RunOptions:
    """``RunOptions`` for ``time`` (5 s when None) and ``options``, the file's ``simulation``
    values filling in ``dt``, ``control_dt`` and ``record_rate`` not given, as ``legdsl run``."""
    from legdsl.pipeline.scaled import run_options as with_file_defaults

    tilt = options.get("fall_tilt")
    if isinstance(tilt, str) and bare_number(tilt):  # --fall-tilt's is degrees, Python's radians
        raise UsageError(f"run(): fall_tilt={tilt!r} has no unit, and a bare number is degrees "
                         f"on the command line but radians in Python: write fall_tilt='{tilt.strip()}"
                         f" deg', or the number {tilt.strip()} for radians")  # fmt: skip
    # fall_height='off', fall_tilt='off': the fall rule's height or tilt turned off
    off = {
        key: OFF_VALUES[key]
        for key, value in options.items()
        if key in OFF_VALUES and is_off(value)
    }
    options = with_units({key: value for key, value in options.items() if key not in off}) | off
    known = [f.name for f in fields(RunOptions) if f.name != "duration"]
    for key in options:  # else RunOptions' own TypeError, which names no way out
        if key not in known:
            where = " (the backend is $LEGDSL_BACKEND's: c or python)" * (key == "backend")
            raise UsageError(f"run(): no option '{key}'{where}; the options are "
                             f"{', '.join(known)}"
                             f"{did_you_mean(key, [*ARGUMENTS, *known])}")  # fmt: skip
    for key, value in options.items():  # numpy's numbers as floats: run.json is written of them
        if key in RUN_NUMERIC and value is not None and not isinstance(value, str):
            if isinstance(value, bool) or not isinstance(value, int | float | np.number):
                raise UsageError(f"run(): {key}= is a number in SI units, or a text with its "
                                 f"unit (e.g. {key}='{RUN_EXAMPLES[key]}'), not {value!r}")  # fmt: skip
            options[key] = a_float(value, f"run(): {key}= is a number in SI units")
    for key in ("dt", "control_dt", "record_rate"):  # None is the file's (or the runner's)
        options.setdefault(key, None)
    duration = seconds(5.0 if time is None else time)
    return with_file_defaults(model, None, duration=duration, **options)


def session_args(
    model: Model,
    controller: str | None = None,
    set: Mapping[str, str | float] | None = None,  # noqa: A002
    time: float | None = None,
    path: str | None = None,
    switch: Mapping[str, str] | None = None,
    scene: str | None = None,
    **options: Any,
) -> dict[str, Any]:
    """``Creature.run``'s arguments as those of ``RunSession.run`` (a scene's lines named in
    ``sources``), with ``unreached``: the notes of settings for gait bands the run never
    reaches (told before it, not passed)."""
    for name, value in (("controller", controller), ("path", path), ("scene", scene)):
        if value is not None and not isinstance(value, str):
            raise UsageError(f"run(): {name}= takes a text, not {value!r}")
    if switch is not None and (
        not isinstance(switch, Mapping) or not all(_a_time(k) for k in switch)
    ):
        raise UsageError(f"run(): switch= maps times to controllers, e.g. {{'6 s': "
                         f"'gallop'}} or {{6: 'gallop'}} (seconds), not {switch!r}")  # fmt: skip
    if set is not None and not isinstance(set, Mapping):
        raise UsageError(f"run(): set= maps names to values, e.g. {{'speed': '2 m/s'}}, "
                         f"not {set!r}")  # fmt: skip
    settings = [setting_text(name, value) for name, value in (set or {}).items()]
    refuse_repeated(settings)  # 'speed' and 'speed ' (or 'speed@0s'): the later would win
    switches = [f"{_seconds_text(when)}={name}" for when, name in (switch or {}).items()]
    unreached: list[str] = []  # settings for gait bands the run never reaches
    sources: dict[str, str] = {}  # the scene's lines, which its notes name as written
    if scene is not None:
        from legdsl.pipeline.scenes import find_scene, scene_plan, scene_sources

        plan, given = find_scene(model, scene), controller
        sources = scene_sources(plan)
        controller, settings, switches = scene_plan(plan, model, settings, switches, unreached)
        if given is not None and given != controller:  # a gait table's: its first band's
            raise UsageError(f"run(): scene {scene} starts with {controller}")
        if time is None and plan.duration is not None:
            time = plan.duration
    options_read = run_options(model, time, options)
    return {
        "controller": controller,
        "settings": settings,
        "paths": [path] if path is not None else [],
        "options": options_read,
        "switches": switches,
        "sources": sources,
        "unreached": unreached,
    }


def _a_time(key: object) -> bool:
    """A switch's time: a text with its unit, or a number of seconds (as ``time=`` takes)."""
    if isinstance(key, numbers.Real) and not math.isfinite(key):  # it read as '--switch nans'
        return False
    return isinstance(key, str | numbers.Real) and not isinstance(key, bool)


def _seconds_text(when: str | float) -> str:
    """A switch's time as ``--switch`` takes it: ``"6 s"`` -> ``6s``, ``0.5`` -> ``0.5s``."""
    return when.replace(" ", "") if isinstance(when, str) else f"{float(when)!r}s"
