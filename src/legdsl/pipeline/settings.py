"""``--set`` and ``--path``: values given to a run, checked against what the ``.leg`` file declared.

``--set NAME=VALUE`` sets a controller input or parameter, ``NAME=VALUE@T`` changes an input at
time ``T`` of the run, ``CONTROLLER.NAME=VALUE`` sets one controller's parameter or input
default only (in a run that switches controllers; it wins over ``NAME=VALUE`` there, and a
command ``NAME=VALUE`` wins over an input default), ``ACTUATOR.KEY=VALUE`` sets an actuator
before it starts. Every value is
checked against the dimension declared for it (``legdsl.ir.controller.Constant.dim``, or the
actuator setting's kind): a dimensioned value needs a unit of that dimension, a dimensionless
one a bare number. A bare 0 is taken for any dimension (zero is zero in every unit), as it
always was for actuator settings. Values are stored in SI units.
"""

from __future__ import annotations

import argparse
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from legdsl.check.values import did_you_mean, measures, unit_to_write
from legdsl.ir.model import NON_NEGATIVE, SETTABLE, Model, setting_kind
from legdsl.lang.errors import UsageError
from legdsl.lang.habits import unit_after_slash
from legdsl.lang.lookalikes import ascii_for, lookalike, minus_sign
from legdsl.lang.units import (
    DIMENSIONLESS,
    KINDS,
    Dim,
    UnitError,
    a_kind,
    parse_unit,
    si_unit,
    unit_for,
    unknown_unit,
)
from legdsl.pipeline.suggested_values import written
from legdsl.sim.machine import InputChange, overwritten
from legdsl.sim.switching import starting_values

# ASCII digits alone, as in a .leg file (\d took '٦٠' for 60, float() too)
NUMBER_AND_UNIT = re.compile(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(\S*)\s*", re.ASCII)
# Python's digit separator, which float() takes ('6_0' for 60): no number of legdsl's has it
_SEPARATED = re.compile(r"\s*[-+]?\.?\d[\d.]*_[\d._]*", re.ASCII)
_TIME: Dim = KINDS["time"][0]


@dataclass(frozen=True)
class Given:
    """A number with an optional unit, as written after ``=`` or ``@``."""

    number: str  # the digits as written ("2.5")
    unit: str  # the unit as written ("m/s"), empty for a bare number
    value: float  # in SI units
    dim: Dim | None  # None for a bare number

    @property
    def text(self) -> str:
        return self.number + self.unit


def _spaced_unit(value: str) -> str | None:
    """A value whose unit has spaces in it, ``150 N m/rad``, written joined as a unit is
    (``150N*m/rad``); None for a text that is not that."""
    parts = value.split()
    if len(parts) < 3 or not NUMBER_AND_UNIT.fullmatch(parts[0]):
        return None
    number, words = parts[0], parts[1:]
    unit = words[0]
    for word in words[1:]:  # '*' between symbols, nothing beside an operator
        unit += word if unit[-1] in "*/^" or word[0] in "*/^" else "*" + word
    try:
        parse_unit(unit)
    except UnitError:
        return None
    return number + unit


def plain_number(text: str, what: str) -> float:
    """An option that is a plain number, as argparse reads it; one written with a unit is told
    ``what`` the number is (a sentence), not argparse's "invalid float value". Its digits are
    0-9 without '_', as in a .leg file (Python's float() reads '1_5' as 15 and other scripts'
    digits: '--scale 1_5' ran a creature 15 times as large)."""
    if not text.isascii() or "_" in text:
        raise argparse.ArgumentTypeError(
            f"{text!r} is not a number: write it with the digits 0-9, without '_'"
        )
    try:
        return float(text)
    except ValueError:
        pass
    try:
        given = parse_given(text, text)
    except UsageError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    raise argparse.ArgumentTypeError(f"{what}, not {given.text!r}: write {given.number}")


def _odd(value: str) -> str:
    """What a character that looks like ASCII and is not does in ``value`` ('−1m/s': "'−' is
    a typographic minus sign"), said as in a .leg file; "" where there is none."""
    for ch in value:
        if (said := lookalike(ch)) is not None:
            fixed = "".join(ascii_for(c) or c for c in value)
            return ": " + (minus_sign(ch, fixed) if ascii_for(ch) == "-" else said)
    return ""


def parse_given(value: str, where: str, want: Dim | None = None) -> Given:
    """``2.5m/s`` -> Given("2.5", "m/s", 2.5, velocity); ``where`` starts an error message;
    ``want``, the dimension the value must have if known, to suggest units of it only."""
    if separated := _SEPARATED.match(value):
        number = separated.group().strip()
        raise UsageError(f"{where}: {number!r} is not a number: write it with the digits "
                         "0-9, without '_' (as in a .leg file)")  # fmt: skip
    match = NUMBER_AND_UNIT.fullmatch(value)
    joined = _spaced_unit(value) if match is None else None
    if joined is not None:
        raise UsageError(f"{where}: a unit is written without spaces, its symbols joined "
                         f"by '*': write e.g. {joined}")  # fmt: skip
    if match is None:
        raise UsageError(f"{where}: {value!r} is not a number with an optional unit{_odd(value)}")
    number, unit = match.group(1), match.group(2)
    if not math.isfinite(float(number)):
        raise UsageError(f"{where}: {number} is too large to be a number (it overflows)")
    factor, dim = 1.0, None
    if unit:
        try:
            factor, dim = parse_unit(unit)
        except UnitError:  # with the number, for the value to write instead ('10km/h')
            told = (
                unit_after_slash(number, unit[1:])
                if re.fullmatch(r"/[A-Za-z][\w^*/-]*", unit)
                else unknown_unit(unit, number, want)
            )  # ('6/s', as a file's '6 /s' is told)
            if odd := _odd(unit):  # 'м/s' with a Cyrillic 'м': said as in a file
                told = f"{unit!r} is not a unit legdsl knows{odd}"
            raise UsageError(f"{where}: {told}") from None
    si = float(number) * factor
    if not math.isfinite(si):
        raise UsageError(f"{where}: {number}{unit} is too large to be a number (it overflows)")
    if si == 0 and re.search("[1-9]", re.split("[eE]", number)[0]):
        raise UsageError(
            f"{where}: {number}{unit} is too small to be a number (nearer 0 than a double "
            "holds, it would read as 0); write 0 if you mean zero"
        )
    return Given(number, unit, si, dim)


def parse_setting(text: str) -> tuple[str, float, Dim | None]:
    """``NAME=VALUE`` with an optional unit right after the number (``hip_servo.setpoint=10deg``)."""
    name, given = _split(text, text)
    return name, given.value, given.dim


def _split(text: str, where: str) -> tuple[str, Given]:
    name, sep, value = text.partition("=")
    if not sep or not name.strip():
        raise UsageError(f"--set {text!r}: write NAME=VALUE, e.g. --set hip_servo.setpoint=10deg")
    return name.strip(), parse_given(value, f"--set {where!r}")


def check_dimension(
    where: str, what: str, given: Given, want: Dim, write: str, declared: str = ""
) -> None:
    """Raise a ``UsageError`` unless ``given`` has the dimension ``want``.

    ``what`` says what is wanted ("speed is a velocity (m/s)"), ``write`` how to write the
    value, with ``{}`` for its number and unit (``speed={}``, ``@{}``), for the example;
    ``declared`` the unit the file wrote the value in, which the example keeps.
    """
    unit = unit_to_write(given.unit, want, declared) or unit_for(want)
    example = written(given, want, unit, write)
    if want == DIMENSIONLESS:
        if given.dim is not None and given.dim != DIMENSIONLESS:
            raise UsageError(
                f"{where}: {what}, but {given.text} is {a_kind(given.dim)}; "
                f"write a bare number, e.g. {example}"
            )
        return
    if given.dim is None:
        if given.value != 0:  # a unit that is not SI's, guessed: the number in SI's too
            in_si = si_unit(want) if parse_unit(unit)[0] != 1 else ""
            also = f" or {write.format(given.number + in_si)}" if in_si else ""
            raise UsageError(f"{where}: {what}; give its unit, e.g. {example}{also}")
        return
    if given.dim != want:
        raise UsageError(
            f"{where}: {what}, but {given.text} is {a_kind(given.dim)}; write e.g. {example}"
        )


def _check_named(where: str, name: str, given: Given, want: Dim, declared: str = "") -> None:
    kind = a_kind(want, declared if measures(declared, want) else "")
    check_dimension(where, f"{name} is {kind}", given, want, f"{name}={{}}", declared)


@dataclass
class Settings:
    """``--set`` options sorted by what they set (all values in SI)."""

    actuators: dict[str, float]  # ACTUATOR.SETTING -> value, before the run
    inputs: dict[str, float]  # controller inputs at t = 0
    params: dict[str, float]  # controller parameters
    schedule: list[InputChange]  # NAME=VALUE@T: an input changed during the run
    # CONTROLLER.NAME=V: one controller's own parameters and input defaults, by controller
    by_controller: dict[str, dict[str, float]] = field(default_factory=dict)

    def as_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {
            "actuators": self.actuators,
            "inputs": self.inputs,
            "params": self.params,
            "schedule": [{"t": c.t, "input": c.name, "value": c.value} for c in self.schedule],
        }
        return out | ({"by_controller": self.by_controller} if self.by_controller else {})

    def for_controller(self, ir: Any) -> tuple[dict[str, float], dict[str, float]]:
        """The inputs and parameters one controller starts with (``starting_values``)."""
        own = self.by_controller.get(ir.name, {})
        names = ([c.name for c in ir.inputs], [c.name for c in ir.params])
        return starting_values(*names, own, self.inputs, self.params)


def require_controller(model: Model, controller: str) -> None:
    """``--controller NAME``: a ``UsageError`` unless the creature has that controller."""
    names = [c.name for c in model.controllers]
    if controller not in names:
        raise UsageError(
            f"--controller {controller}: creature '{model.name}' has no such controller"
            f"{did_you_mean(controller, names)} (it has {', '.join(names) or 'none'})"
        )


def _no_controller_chosen(model: Model, name: str) -> None:
    """``--set NAME=V`` without ``--controller``: say which controllers declare NAME, or that
    none does (a misspelt name is not a controller input)."""
    inputs = [c.name for c in model.controllers if name in {n.name for n in c.inputs}]
    owners = inputs or [c.name for c in model.controllers if name in {n.name for n in c.params}]
    if owners:
        kind = "input" if inputs else "parameter"
        raise UsageError(
            f"--set {name}: '{name}' is a controller {kind} (of {', '.join(owners)}); choose a "
            f"controller with --controller {owners[0]} (controller= in Python)"
        )
    known = list(dict.fromkeys(n.name for c in model.controllers for n in (*c.inputs, *c.params)))
    if not known:
        raise UsageError(
            f"--set {name}: creature '{model.name}' has no controllers, so no inputs or parameters;"
            " --set ACTUATOR.SETTING=VALUE sets an actuator"
        )
    raise UsageError(
        f"--set {name}: no controller of creature '{model.name}' has an input or parameter "
        f"{name!r}{did_you_mean(name, known)} (they have {', '.join(known)})"
    )


def sort_settings(
    texts: list[str], model: Model, controller: str | None, later: Sequence[str] = ()
) -> Settings:
    """Read ``--set`` options: ``ACTUATOR.SETTING=V``, ``INPUT=V``, ``PARAM=V`` or ``INPUT=V@T``,
    each checked against the dimension the file declares for it. ``later`` are the controllers
    a run switches to (``--switch``): a name may be an input or parameter of any of them."""
    out = Settings({}, {}, {}, [])
    ir = model.controller(controller) if controller is not None else None
    inputs: dict[str, Any] = {}
    params: dict[str, Any] = {}
    for name in dict.fromkeys([controller, *later] if ir is not None else []):
        assert name is not None
        ctl = model.controller(name)
        inputs |= {c.name: c for c in ctl.inputs if c.name not in inputs}
        params |= {c.name: c for c in ctl.params if c.name not in params}
    for original in texts:
        where = f"--set {original}"
        text, at = _command_time(original)
        if at is not None and at < 0:  # ran as if given from the start, unsaid
            raise UsageError(f"{where}: a change comes at a time from the run's start, 0 or "
                             f"more; to set it from the start, write --set {text}"
                             + _caret(original, len(text) + 1, len(original) - len(text) - 1))  # fmt: skip
        name, given = _split(text, original)
        owner, dot, own_name = name.partition(".")
        if dot and owner in {c.name for c in model.controllers}:
            _controller_setting(model, [controller, *later], name, given, at, where)
            out.by_controller.setdefault(owner, {})[own_name] = given.value
            continue
        if dot and owner not in {a.name for a in model.actuators}:
            _unknown_owner(model, owner, where)
        if "." in name:
            if at is not None:
                raise UsageError(f"--set {text}@...: only controller inputs change during a run")
            _check_actuator_setting(model, name, given, where)
            out.actuators[name] = given.value
            continue
        if ir is None:
            _no_controller_chosen(model, name)
        if name in inputs:
            _check_named(where, name, given, inputs[name].dim, inputs[name].unit)
            if at is None:
                out.inputs[name] = given.value
            else:
                out.schedule.append(InputChange(at, name, given.value))
        elif name in params:
            if at is not None:
                raise UsageError(
                    f"{where}: {name} is a parameter; only controller inputs change during a run "
                    f"(inputs: {', '.join(inputs) or 'none'})"
                )
            _check_named(where, name, given, params[name].dim, params[name].unit)
            out.params[name] = given.value
        else:
            known = ", ".join([*inputs, *params]) or "none"
            which = f"controller {controller}" if not later else "no controller of the run"
            hint = did_you_mean(name, [*inputs, *params])
            raise UsageError(
                f"--set {name}: {which} has no input or parameter {name!r}{hint} (it has {known})"
                if not later
                else f"--set {name}: {which} has an input or parameter {name!r}{hint} "
                f"(they have {known})"
            )
    return out


def _caret(text: str, start: int, length: int) -> str:
    """The option's text (``--set TEXT``, as written) with a caret under the part of TEXT
    from ``start`` that is wrong."""
    return f"\n    --set {text}\n    {' ' * (len('--set ') + start)}{'^' * max(length, 1)}"


def _unknown_owner(model: Model, owner: str, where: str) -> None:
    """``--set X.NAME=V`` where X is neither a controller nor an actuator of the creature."""
    from legdsl.check.values import did_you_mean

    controllers = [c.name for c in model.controllers]
    actuators = [a.name for a in model.actuators]
    raise UsageError(
        f"{where}: the creature has no controller or actuator {owner!r}"
        f"{did_you_mean(owner, [*controllers, *actuators])} (controllers: "
        f"{', '.join(controllers) or 'none'}; actuators: {', '.join(actuators) or 'none'})"
        + _caret(where.removeprefix("--set "), 0, len(owner))
    )


def _controller_setting(
    model: Model,
    running: Sequence[str | None],
    name: str,
    given: Given,
    at: float | None,
    where: str,
) -> None:
    """Check ``CONTROLLER.NAME=VALUE``: a controller of the run and one of its inputs or
    parameters, in its dimension; no ``@T`` (it is that controller's own value)."""
    owner, _, key = name.partition(".")
    text = where.removeprefix("--set ")
    if owner not in running:
        runs = ", ".join(c for c in dict.fromkeys(running) if c) or "none"
        raise UsageError(
            f"{where}: controller {owner!r} does not run here (the run's: {runs}); "
            f"add --switch T={owner} or set it for a controller that runs"
            + _caret(text, 0, len(owner))
        )
    ctl = model.controller(owner)
    declared = {c.name: c for c in (*ctl.inputs, *ctl.params)}
    dims = {c.name: c.dim for c in declared.values()}
    if key not in dims:
        known = ", ".join(dims) or "none"
        raise UsageError(
            f"{where}: controller {owner} has no input or parameter {key!r}"
            f"{did_you_mean(key, dims)} (it has {known})" + _caret(text, len(owner) + 1, len(key))
        )
    if at is not None:
        raise UsageError(
            f"{where}: {name} is controller {owner}'s own value, set before the run; to change "
            f"an input during the run write --set {key}=...@T"
            + _caret(text, text.rfind("@"), len(text) - text.rfind("@"))
        )
    _check_named(where, name, given, dims[key], declared[key].unit)


def _check_actuator_setting(model: Model, name: str, given: Given, where: str) -> None:
    by_name = {a.name: a for a in model.actuators}
    actuator, _, key = name.partition(".")
    if actuator not in by_name or not key:
        raise UsageError(
            f"--set {name}: name an actuator setting such as ACTUATOR.setpoint "
            f"(actuators: {', '.join(by_name) or 'none'})"
        )
    a = by_name[actuator]
    if key not in SETTABLE[a.kind]:
        fixed = f"'{key}' is the .leg file's alone (change it there); " if key == "max" else ""
        if a.kind == "force" and a.rotary:  # a torque(...) actuator: its torque is its 'force'
            raise UsageError(f"--set {name}: {fixed}a torque actuator's one setting is its "
                             f"torque, named 'force': write --set {actuator}.force=VALUE (N*m)")  # fmt: skip
        raise UsageError(
            f"--set {name}: {fixed}a {a.kind}'s settings are {', '.join(SETTABLE[a.kind])}"
        )
    if key in NON_NEGATIVE and given.value < 0:  # the rule the .leg checker applies
        raise UsageError(  # before the unit: its advice would be the negative value
            f"{where}: '{key}' must not be negative (as in the .leg file); give 0 or more"
        )
    _check_named(where, name, given, KINDS[setting_kind(key, a.rotary)][0])


def refuse_repeated(texts: Sequence[str]) -> None:
    """The command line's own ``--set NAME=V`` twice for one name (``speed`` and ``speed ``
    alike: the API's keys): the later would win silently; so would ``NAME=V@0s``, a command at
    the start, over ``NAME=V`` (a scene's value is the command line's to override, and is not
    among these)."""
    seen: dict[str, str] = {}
    at_start: dict[str, str] = {}
    for text in texts:
        if "=" not in text:
            continue  # a malformed one is told by the run
        name = text.partition("=")[0].strip()
        if "@" in text:  # two commands at one time are refused by the session
            if _at_the_start(text):
                at_start.setdefault(name, text)
            continue
        if name in seen:
            raise UsageError(f"--set {seen[name]} and --set {text} both set {name}: keep one")
        seen[name] = text
    for name in seen.keys() & at_start.keys():
        raise UsageError(
            f"--set {seen[name]} and --set {at_start[name]} both set {name} from the start (a "
            f"command at 0 s replaces the value before it is used): keep one"
        )


def _at_the_start(text: str) -> bool:
    """Whether the ``--set NAME=V@T`` text ``text`` commands at 0 s (a mistake in it: no, the
    run tells it)."""
    try:
        return _command_time(text)[1] == 0
    except UsageError:
        return False


def _command_time(original: str) -> tuple[str, float | None]:
    """A ``--set`` text as its ``NAME=V`` and the time after its '@' in seconds (None
    without one), that time's unit checked."""
    if "@" not in original:
        return original, None
    text, _, when = original.partition("@")
    if "@" in when:  # read as the value's unit ('m@4s' is not a unit)
        second = len(text) + 1 + when.index("@")
        raise UsageError(
            f"--set {original}: one '@' to a --set: it changes the value once, at the time after "
            f"its '@'; for another change give another --set, e.g. --set {original[:second]} "
            f"--set {text}{original[second:]}" + _caret(original, second, len(original) - second)
        )
    if not when:
        raise UsageError(
            f"--set {original}: no time after '@': write e.g. --set {original}4s (from 4 s on), "
            f"or leave the '@' out to set it from the start" + _caret(original, len(text), 1)
        )
    given = parse_given(when, f"--set {original}", _TIME)
    check_dimension(f"--set {original}", "the time after '@' is in seconds", given, _TIME, "@{}")
    return text, given.value


def overwritten_notes(
    settings: Sequence[str],
    controller: str | None,
    session: Any,
    sources: Mapping[str, str] | None = None,
) -> list[str]:
    """``--set TEXT: why`` for each ``--set`` text of an actuator setting that ``controller``
    writes itself (``legdsl.sim.machine.overwritten``), a scene's line named as ``sources``
    has it (``scene_sources``: it was told as a --set in SI units the user never wrote); none
    while the settings or the controller's name hold a mistake, which the run tells alone."""
    if controller is None or session is None:
        return []
    if controller not in {c.name for c in session.model.controllers}:
        return []  # an unknown name: the run says so, with the names there are
    try:
        sort_settings(list(settings), session.model, controller)
    except UsageError:
        return []
    module = session.control(controller)
    said = [
        (t, overwritten(t.partition("=")[0].strip(), controller, module, session.model))
        for t in settings
    ]
    said += [(t, _commanded_too(t, controller, session.model, settings)) for t in settings]
    named = sources or {}
    return [f"{named.get(text, f'--set {text}')}: {why}" for text, why in said if why]


def _commanded_too(text: str, controller: str, model: Model, settings: Sequence[str]) -> str:
    """Why ``CONTROLLER.INPUT=V`` of the starting controller changes nothing: a plain
    ``INPUT=W`` (a command, which an input's default sits under) is given too."""
    owner, _, name = text.partition("=")[0].strip().partition(".")
    inputs = {i.name for i in model.controller(controller).inputs}
    if owner != controller or name not in inputs or "@" in text:
        return ""
    plain = next((t for t in settings if "@" not in t and t.partition("=")[0].strip() == name), "")
    return (f"--set {plain} commands {name} from the start, over {controller}'s default this sets: "
            "it changes nothing; keep one") if plain else ""  # fmt: skip
