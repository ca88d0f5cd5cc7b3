"""``run()``'s options as ``legdsl run`` reads them: each with its unit, a misspelt one named,
and the step, control interval and record rate the creature's ``simulation`` block sets where
none is given (a scaled creature's, or a small one's finer step)."""

from __future__ import annotations

from dataclasses import fields
from typing import Any

import numpy as np

from legdsl.api.arguments import a_float, seconds, with_units
from legdsl.check.values import did_you_mean
from legdsl.ir.model import Model
from legdsl.lang.errors import UsageError
from legdsl.pipeline.options import RUN_NUMERIC
from legdsl.sim.run_loop import RunOptions

RUN_EXAMPLES = {"dt": "0.4 ms", "control_dt": "2 ms", "record_rate": "200 Hz",
                "fall_height": "5 cm", "fall_tilt": "60 deg", "drop": "2 cm"}  # fmt: skip
ARGUMENTS = ["controller", "set", "time", "path", "switch", "scene"]  # a typo of one is named


def run_options(model: Model, time: object, options: dict[str, Any]) -> RunOptions:
    """``RunOptions`` for ``time`` (5 s when None) and ``options``, the file's ``simulation``
    values filling in ``dt``, ``control_dt`` and ``record_rate`` not given, as ``legdsl run``."""
    from legdsl.pipeline.scaled import run_options as with_file_defaults

    tilt = options.get("fall_tilt")
    if isinstance(tilt, str) and _bare_number(tilt):  # --fall-tilt's is degrees, Python's radians
        raise UsageError(f"run(): fall_tilt={tilt!r} has no unit, and a bare number is degrees "
                         f"on the command line but radians in Python: write fall_tilt='{tilt.strip()}"
                         f" deg', or the number {tilt.strip()} for radians")  # fmt: skip
    options = with_units(options)
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


def _bare_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True
