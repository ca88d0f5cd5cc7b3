"""``Creature.run_copies``' refusals in the words of its arguments: its settings are checked
as ``--set`` checks them, and it said so ('--set speed=1.0kg: ... write e.g. speed=1.0m/s')
to a Python caller who gave ``set={'speed': '1.0kg'}`` or ``vary={'speed': (v, 'kg')}``."""

from __future__ import annotations

import contextlib
import inspect
import re
from collections.abc import Callable, Iterator, Mapping
from typing import Any

from legdsl.lang.errors import UsageError

# the CLI's words for what the API calls otherwise (a step too large for a stiffness)
_OPTIONS = (("(--dt, or dt in", "(dt=, or dt in"), ("(--set cannot", "(set= cannot"))


def check_copies(plan: dict[str, Any], progress: Callable[..., Any] | None, vary: Any) -> None:
    """``run_copies``' own arguments, before the batch is made."""
    if plan["switches"]:  # a batch runs one controller: a switch would be left out
        raise UsageError(
            "run_copies(): the copies run one controller, and this run switches "
            f"({', '.join(plan['switches'])}); run them with run_many() instead"
        )
    if progress is not None and not callable(progress):
        raise UsageError(f"run_copies(): progress= is a function called with (done, n, "
                         f"seconds_left), or None; not {progress!r}")  # fmt: skip
    if progress is not None:
        _check_progress(progress)
    if vary is not None and not isinstance(vary, Mapping):
        raise UsageError(f"run_copies(): vary= maps names to their values and unit, e.g. "
                         f"{{'speed': (speeds, 'm/s')}}, not {vary!r}")  # fmt: skip


def _check_progress(progress: Callable[..., Any]) -> None:
    """``progress=`` takes the three arguments it is called with, ``(done, n, seconds_left)``:
    one that did not (``lambda: None``) was a bare TypeError from the batch, mid-run."""
    try:
        signature = inspect.signature(progress)
    except (TypeError, ValueError):  # a builtin without one: it is called as it is
        return
    try:
        signature.bind(0, 1, 0.0)
    except TypeError:
        raise UsageError(f"run_copies(): progress= is called with three arguments, (done, n, "
                         f"seconds_left): the copies done, their number and the seconds left "
                         f"(nan before the first is done), and {progress!r} takes "
                         f"{signature}; give e.g. progress=lambda done, n, left: print(done, n)"
                         ) from None  # fmt: skip


@contextlib.contextmanager
def copies_words(vary: Any) -> Iterator[None]:
    """A refusal of a setting within, told as ``run_copies``' ``set=`` or ``vary=``."""
    try:
        yield
    except UsageError as e:
        said = reworded(str(e), vary if isinstance(vary, Mapping) else {})
        if said == str(e):
            raise
        raise UsageError(said) from None


def reworded(message: str, vary: Mapping[str, Any]) -> str:
    """``--set NAME=VALUE: why; write e.g. NAME=2m/s`` as ``run_copies(): vary['NAME'] ...``
    or ``run_copies(): set['NAME'] = 'VALUE': ...``, its advice in the argument's form."""
    for cli, api in _OPTIONS:
        message = message.replace(cli, api)
    if message.startswith("run(): "):  # run()'s own reading of the arguments they share
        return "run_copies(): " + message.removeprefix("run(): ")
    # the name and value as --set wrote them, or quoted as a whole ('speed=3.6km/h', which
    # was told as set["'speed"] = "3.6km/h'")
    match = re.match(
        r"--set (?:'([^'\s=]+)(?:=([^'\s]*))?'|(\S+?)(?:=(\S*))?): (.*)$", message, re.S
    )
    if match is None:
        return message
    quoted = match.group(1) is not None
    name, value = (match.group(1), match.group(2)) if quoted else (match.group(3), match.group(4))
    why = match.group(5)
    if value is not None and "@" in value:  # set={'speed@2': '1 m/s'}, as --set speed=1m/s@2
        value, _, when = value.partition("@")
        name = f"{name}@{when}"
        why = re.sub(
            r"e\.g\. @(\S+)$",
            lambda m: f"e.g. set={{{name.partition('@')[0] + '@' + m.group(1)!r}: {value!r}}}",
            why,
        )
    key = name.partition("@")[0]
    advice = re.search(r"(write|give its unit),? e\.g\. \S+?=[-+\d.eE]*([^\s@]*)$", why)
    if key in vary:
        unit = advice.group(2) if advice else ""
        if advice:
            why = why[: advice.start()] + (
                f"give the values' unit, e.g. vary={{{key!r}: (values, {unit!r})}}"
            )
        shown = f", the value {value}" if value else ""
        return f"run_copies(): vary[{key!r}]{shown}: {why}"
    if advice:
        number = re.search(r"e\.g\. \S+?=([-+\d.eE]*)", why[advice.start() :])
        example = f"{number.group(1) if number else '1'} {advice.group(2)}"
        why = why[: advice.start()] + f"give e.g. set={{{name!r}: {example!r}}}"
    shown = f" = {value!r}" if value is not None else ""
    return f"run_copies(): set[{name!r}]{shown}: {why}"
