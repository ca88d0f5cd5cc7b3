"""``run()``'s arguments as ``legdsl run`` reads them (``session_args``), and its options: each
with its unit, a misspelt one named, and the step, control interval and record rate the
creature's ``simulation`` block sets where none is given (a scaled creature's, or a small
one's finer step)."""

from __future__ import annotations

import math
import numbers
import os
import re
from collections.abc import Mapping
from dataclasses import fields
from typing import Any

import numpy as np

from legdsl.api.arguments import a_float, seconds, setting_text, with_units
from legdsl.check.values import did_you_mean
from legdsl.ir.model import Model
from legdsl.lang.errors import UsageError
from legdsl.lang.units import bare_number
from legdsl.pipeline.options import OFF_VALUES, RUN_NUMERIC, check_run_options, is_off
from legdsl.pipeline.settings import refuse_repeated
from legdsl.pipeline.text_numbers import one_text
from legdsl.sim.run_loop import RunOptions

RUN_EXAMPLES = {"dt": "0.4 ms", "control_dt": "2 ms", "record_rate": "200 Hz",
                "fall_height": "5 cm", "fall_tilt": "60 deg", "drop": "2 cm"}  # fmt: skip
# options whose None is the runner's default (dt, control_dt, record_rate: the file's; drop,
# fall_height: RunOptions' own None)
DEFAULT_WHEN_NONE = ("fall_tilt", "integrator")
ARGUMENTS = ["controller", "set", "time", "path", "switch", "scene"]  # a typo of one is named


def run_options(model: Model, time: object, options: dict[str, Any]) -> RunOptions:
    """``RunOptions`` for ``time`` (5 s when None) and ``options``, the file's ``simulation``
    values filling in ``dt``, ``control_dt`` and ``record_rate`` not given, as ``legdsl run``;
    an option given as None is one not given (``fall_tilt=None``, ``integrator=None`` were
    refused, though ``dt=None`` and ``drop=None`` meant the default)."""
    from legdsl.pipeline.scaled import run_options as with_file_defaults

    options = {k: v for k, v in options.items() if not (v is None and k in DEFAULT_WHEN_NONE)}

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
    if isinstance(path, os.PathLike):  # a pathlib.Path, as save(), plot() and load() take
        path = os.fspath(path)
    for name, value in (("controller", controller), ("path", path), ("scene", scene)):
        if name == "path" and value is not None and not isinstance(value, str):
            raise UsageError(f"run(): path= takes a text (a --path's) or a pathlib.Path, "
                             f"not {value!r}")  # fmt: skip
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
    for (when, name), text in zip((switch or {}).items(), switches, strict=True):
        _check_switch(model, text, when, name)
    unreached: list[str] = []  # settings for gait bands the run never reaches
    sources: dict[str, str] = {}  # the scene's lines, which its notes name as written
    if scene is not None:
        from legdsl.pipeline.scenes import find_scene, scene_plan, scene_sources

        plan, given = find_scene(model, scene), controller
        sources = scene_sources(plan)
        controller, settings, switches = scene_plan(plan, model, settings, switches, unreached)
        if given is not None and given != controller:  # a gait table's: its first band's
            raise UsageError(f"run(): scene {scene} starts with controller {controller}; leave "
                             "out controller= (or give another scene=)")  # fmt: skip
        if time is None and plan.duration is not None:
            time = plan.duration
    options_read = run_options(model, time, options)
    try:  # told in the arguments' words (it was --dt, --time, --record-rate)
        check_run_options(options_read, api=True)
    except UsageError as e:
        raise UsageError(f"run(): {e}") from None
    return {
        "controller": controller,
        "settings": settings,
        "paths": [path] if path is not None else [],
        "options": options_read,
        "switches": switches,
        "sources": sources,
        "unreached": unreached,
    }


def _check_switch(model: Model, text: str, when: object, name: object) -> None:
    """A switch read as ``--switch TEXT`` reads, a mistake told as ``switch=``'s: ``--switch
    0.0s=gallop: ... write --controller gallop ... e.g. --switch 1s=gallop`` was the CLI's."""
    from legdsl.pipeline.scenes import parse_switch

    try:
        parse_switch(text, model)
    except UsageError as e:
        said = str(e).replace(f"--switch {text}", f"run(): switch={{{when!r}: {name!r}}}", 1)
        said = re.sub(r"write --controller (\w+)", r"give controller='\1'", said)
        said = re.sub(r"--switch (\S+?)=(\w+)", r"switch={'\1': '\2'}", said)
        raise UsageError(said) from None


def _a_time(key: object) -> bool:
    """A switch's time: a text with its unit, or a number of seconds (as ``time=`` takes)."""
    if isinstance(key, numbers.Real) and not math.isfinite(key):  # it read as '--switch nans'
        return False
    return isinstance(key, str | numbers.Real) and not isinstance(key, bool)


def _seconds_text(when: str | float) -> str:
    """A switch's time as ``--switch`` takes it: ``"6 s"`` -> ``6s``, ``0.5`` -> ``0.5s``."""
    if isinstance(when, str):  # blanks inside its number refused ('0.1 0 s' ran at 0.10 s)
        return one_text(f"run(): switch={{{when!r}: ...}}", when, "switch={{'{}': ...}}")
    return f"{float(when)!r}s"


def many_plans(session: Any, runs: list[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """``run_many``'s runs as ``session_args`` plans, each prepared (checked as its run will
    be, its notes held back) before any runs: a run refused was told only after the runs
    before it had run, and not which run it was. A refusal names the run by its index in
    ``runs``, in the API's words: ``run_many(): runs[2]: set['speed'] = '1kg': ...``."""
    from legdsl.api.copies_words import reworded

    plans = []
    told = session.log, session.note
    session.log = session.note = None  # each run's notes are told as it comes back
    try:
        for i, r in enumerate(runs):
            try:
                plan = session_args(session.model, **r)
                session.prepare(**{k: v for k, v in plan.items() if k != "unreached"})
            except UsageError as e:
                said = reworded(str(e), {}).removeprefix("run_copies(): ")
                raise UsageError(f"run_many(): runs[{i}]: {said}") from None
            plans.append(plan)
    finally:
        session.log, session.note = told
    return plans
