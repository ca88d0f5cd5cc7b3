"""The Python API's arguments checked and read as ``legdsl run``'s options are: times and
options with their units, paths, thread counts, ``set=`` entries. A wrong one is a
``UsageError`` that names the argument."""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from legdsl.lang.errors import UsageError
from legdsl.pipeline.text_numbers import one_text


def as_text(value: object) -> object:
    """A ``Quantity`` (a creature's default, as ``load`` gives it) as the text of its SI value
    and unit, every digit kept, so that its dimension is checked as a text's (one without a
    unit as its number: SI, as any number); a 0-d numpy array of a real number
    (``np.array(0.2)``, which numpy's reductions give) as that number; else ``value``."""
    from legdsl.api import Quantity

    if isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in "iuf":
        return value[()]  # a numpy scalar (True/False and complex ones stay refused)
    if not isinstance(value, Quantity):
        return value
    return f"{value.value!r}{value.unit}" if value.unit else value.value


def a_float(value: int | float | np.number, meaning: str) -> float:
    """``float(value)``; a whole number too large for a double is ``meaning``'s UsageError (it
    was float()'s OverflowError)."""
    try:
        return float(value)
    except OverflowError:
        size = int(value).bit_length()  # its digits may be too many to print (str() refuses)
        raise UsageError(f"{meaning}, not a whole number of about 2**{size}, too large for "
                         "a double") from None  # fmt: skip


def seconds(time: object) -> float:
    """``time=``: seconds, or a text with its unit as ``--time`` takes it (``"500 ms"``), or a
    ``Quantity`` of a time."""
    from legdsl.pipeline.options import RUN_NUMERIC

    time = as_text(time)
    meaning = "run(): time= is seconds (a number, or a text like '500 ms')"
    if isinstance(time, str):
        return read_text("time", time, RUN_NUMERIC["duration"][1])
    if isinstance(time, bool) or not isinstance(time, int | float | np.integer | np.floating):
        raise UsageError(f"{meaning}, not {time!r}")
    return a_float(time, meaning)


def with_units(options: dict[str, Any]) -> dict[str, Any]:
    """Options written as text with their unit, as ``legdsl run`` takes them (``dt="0.4 ms"``,
    ``fall_tilt="60 deg"``), in SI; a number is SI already (``fall_tilt`` in radians)."""
    from legdsl.pipeline.options import RUN_NUMERIC

    out = dict(options)
    for key, value in options.items():
        value = out[key] = as_text(value)
        if key in RUN_NUMERIC and isinstance(value, str):
            out[key] = read_text(key, value, RUN_NUMERIC[key][1])
    return out


def read_text(name: str, text: str, spec: Any) -> float:
    """Argument ``name``'s ``text`` with its unit (``"0.4 ms"``), read as ``legdsl run``'s
    option is (``pipeline.options.read_numeric``, ``spec`` its ``Numeric``), a mistake told
    in the argument's words: ``min_stance='20 kg'`` was told "write e.g. min_stance=20s" (no
    Python), ``dt='0.4 kg'`` as ``--dt``, and ``time='nan s'`` as 'nans'."""
    from legdsl.pipeline.options import read_numeric

    flag, compact = f"{name}=", one_text(f"{name}={text!r}", text, f"{name}='{{}}'")
    if re.match(r"\s*[-+]?(?:nan|inf(?:inity)?)(?![a-z])", text, re.I):
        raise UsageError(f"{name}={text!r}: {text.split()[0]} is not a finite number; give "
                         f"e.g. {name}='2 {spec.bare}'")  # fmt: skip
    try:
        return read_numeric(flag, compact, spec)
    except UsageError as e:
        said = str(e)
        if said.startswith(f"{flag}{compact}:"):  # as given, a Python text
            said = f"{name}={text!r}:" + said[len(flag + compact) + 1 :]
        said = re.sub(  # e.g. min_stance=20s -> min_stance='20 s', a Python argument
            rf"e\.g\. {re.escape(flag)}([-+\d.eE]+)([^\s,;()]*)",
            lambda m: f"e.g. {name}='{m.group(1)} {m.group(2)}'".replace(" '", "'"),
            said,
        )
        raise UsageError(said) from None


def a_path(call: str, path: object) -> Path:
    """A path given as text or ``pathlib.Path``; an empty text (``Path("")`` is the current
    directory: ``save("")`` wrote the run there) is refused."""
    if not isinstance(path, str | Path) or (isinstance(path, str) and not path.strip()):
        raise UsageError(f"{call}: give a path (a text or a pathlib.Path), not {path!r}")
    return Path(path)


def a_generated(call: str, generated: object) -> Path:
    """``generated=``: the directory of the generated code (not an empty text, which would be
    the current directory)."""
    if not isinstance(generated, str | Path) or (
        isinstance(generated, str) and not generated.strip()
    ):
        raise UsageError(f"{call}: generated= is the directory of the generated code, not "
                         f"{generated!r}")  # fmt: skip
    return Path(generated)


def thread_count(threads: object) -> int | None:
    """``threads=``: None (one per core) or a whole number, 1 or more."""
    if threads is not None and (
        isinstance(threads, bool) or not isinstance(threads, int | np.integer) or threads < 1
    ):
        raise UsageError(f"threads= is how many threads run at once, a whole number, 1 or "
                         f"more (or None: one per core), not {threads!r}")  # fmt: skip
    return None if threads is None else int(threads)


def window_time(name: str, value: object) -> float:
    """``start=``, ``end=``: seconds from the run's start (0 or more), or a text with its unit
    as ``--from`` takes it (``"3 s"``)."""
    return _seconds(name, value, "nonnegative", f"{name}= is seconds from the run's start, a "
                    "number 0 or more (or a text like '3 s')")  # fmt: skip


def min_stance_time(value: object) -> float | None:
    """``metrics()``'s ``min_stance=``: None, seconds more than zero, or a text with its unit
    as ``--min-stance`` takes it (``"20 ms"``)."""
    if value is None:
        return None
    return _seconds("min_stance", value, "positive", "metrics(): min_stance= is seconds, a "
                    "number more than zero (or a text like '20 ms')")  # fmt: skip


def friction_edge_time(value: object) -> float:
    """``metrics()``'s ``friction_edge=``: seconds, 0 or more, or a text with its unit as
    ``--friction-edge`` takes it (``"10 ms"``)."""
    return _seconds("friction_edge", value, "nonnegative", "metrics(): friction_edge= is "
                    "seconds, a number 0 or more (or a text like '10 ms')")  # fmt: skip


def _seconds(name: str, value: object, least: str, meaning: str) -> float:
    """``value`` in seconds: a text with its unit (``read_seconds``), or a finite number, 0 or
    more (``least="nonnegative"``) or more than 0 (``"positive"``); else ``meaning``."""
    from legdsl.pipeline.options import Numeric

    value = as_text(value)
    if isinstance(value, str):
        return read_text(name, value, Numeric("time", "s", least))
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        raise UsageError(f"{meaning}, not {value!r}")
    number = a_float(value, meaning)
    if not math.isfinite(number) or not (number > 0 or (least == "nonnegative" and number == 0)):
        raise UsageError(f"{meaning}, not {value!r}")
    return number


def setting_text(name: str, value: object) -> str:
    """``("speed@4s", "2 m/s")`` -> ``speed=2m/s@4s`` (the CLI's form); a ``Quantity`` (a
    controller's default, as ``load`` gives it) goes with its SI unit, every digit kept."""
    value = as_text(value)
    if not isinstance(name, str):  # the name is the mistake, not its value
        raise UsageError(f"set {name!r}: a name is a text, an input, parameter or actuator "
                         f"setting as --set takes it, e.g. {{'speed': '2 m/s'}}")  # fmt: skip
    if not (
        isinstance(value, str | int | float | np.integer | np.floating)
        and not isinstance(value, bool)
    ):
        raise UsageError(f"set {name!r}: give a value with its unit as text, e.g. "
                         f"{{'speed': '2 m/s'}} (or a Quantity), not {value!r}")  # fmt: skip
    key, at, when = name.partition("@")
    if at:  # told here, in set='s words: the run's own check says --set speed=1m/s@ (or @nans)
        example = f"set={{'{key.strip()}@4 s': {value!r}}}"
        if not when.strip():
            raise UsageError(f"set {name!r}: no time after '@': give e.g. {example} (from 4 s "
                             "on), or leave the '@' out to set it from the start")  # fmt: skip
        if re.match(r"\s*[-+]?(?:nan|inf(?:inity)?)(?![a-z])", when, re.I):
            raise UsageError(f"set {name!r}: the time after '@', {when.strip()!r}, is not a "
                             f"finite number; give e.g. {example}")  # fmt: skip
    meaning = f"set {name!r}: give a value with its unit as text, e.g. {{'speed': '2 m/s'}}"
    if re.match(r"\s*[-+]?(?:nan|inf(?:inity)?)(?![a-z])", str(value), re.I):  # not 'speed=nanm/s'
        raise UsageError(
            f"set {name!r}: {value!r} is not a finite number; {meaning[len(f'set {name!r}: ') :]}"
        )
    if isinstance(value, str):
        text = one_text(f"set {name!r}: {value!r}", value, f"set={{{{{name!r}: '{{}}'}}}}")
    else:
        text = repr(a_float(value, meaning))
    if at:
        when = one_text(
            f"set {name!r}: the time after '@'",
            when,
            f"set={{{{'{key.strip()}@{{}}': {value!r}}}}}",
        )
    return f"{key}={text}" + (f"@{when}" if at else "")


def an_output(call: str, path: object, suffixes: tuple[str, ...], what: str) -> Path:
    """``plot()``'s and ``animate()``'s ``path=``: a file, not a directory, named for what is
    written into it (a PNG named ``.mp4``, or a player named ``.mp4``, misleads)."""
    from legdsl.pipeline.options import check_output_file

    out = check_output_file(a_path(call, path), call)
    if out.suffix.lower() not in suffixes:
        raise UsageError(f"{call} {out}: this writes {what}; give a name ending in {suffixes[0]}")
    return out


GROUP_FORMS = "a dict {'front': ['fl', 'fr']} or a list of texts ['front=fl,fr']"


def metrics_groups(groups: object) -> tuple[str, ...]:
    """``metrics()``'s ``groups=``: a dict of name -> legs, or texts ``NAME=LEG,LEG`` (one
    text alone too), as the texts ``legdsl metrics --group`` takes."""
    if isinstance(groups, str):
        groups = (groups,)
    if isinstance(groups, Mapping):
        texts = []
        for name, legs in groups.items():
            legs = [legs] if isinstance(legs, str) else legs
            legs = list(legs) if isinstance(legs, Iterable) else None
            if not (isinstance(name, str) and "=" not in name and legs
                    and all(isinstance(leg, str) and leg.strip() for leg in legs)):  # fmt: skip
                raise UsageError(f"metrics(): groups= is {GROUP_FORMS}; the group "
                                 f"{name!r}: {groups[name]!r} is not a name and its legs")  # fmt: skip
            texts.append(f"{name}={','.join(legs)}")
        return tuple(texts)
    if isinstance(groups, Iterable):
        groups = tuple(groups)
        if all(isinstance(g, str) and "=" in g for g in groups):
            return groups
    raise UsageError(f"metrics(): groups= is {GROUP_FORMS}, not {groups!r}")


def check_vary(
    set_: Mapping[str, Any] | None, vary: Mapping[str, Any], controller: str | None
) -> None:
    """``run_copies``' ``vary=`` against ``set=``: a name in both (in ``set=`` also as
    ``CONTROLLER.NAME``, the same parameter) would have one value overridden unseen (a change
    during the run, ``NAME@T``, is ``set=``'s alone); True/False or complex values are not
    numbers of a unit (numpy would read them as 1/0, or drop a part)."""
    own = f"{controller}."  # the running controller's own NAME, as legdsl sweep reads it
    fixed = {str(name).strip().removeprefix(own): str(name).strip()
             for name in (set_ or {}) if "@" not in str(name)}  # fmt: skip
    for name, given in vary.items():
        if name in fixed:
            spelt = "" if fixed[name] == name else f" (as {fixed[name]})"
            raise UsageError(f"run_copies(): {name} is in both set={spelt} and vary=, and each "
                             "copy's vary= value would override set='s: give it in one of "
                             "them")  # fmt: skip
        if isinstance(given, tuple) and len(given) == 2:
            kind = np.asarray(given[0]).dtype.kind
            if kind in "bc":
                what = "True/False" if kind == "b" else "complex numbers"
                raise UsageError(f"vary {name}: its values are {what}, not numbers of "
                                 f"{given[1]!r}; give real numbers")  # fmt: skip
