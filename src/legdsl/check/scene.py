"""Check ``scene NAME { ... }`` blocks: a run written in the file (``legdsl.ir.scene``).

A scene names its creature's controllers, inputs, parameters and actuator settings; each
is resolved here against the checked creature (its controllers already attached), and each
value's dimension against the one declared for it, every mistake at its place with a caret:

    controller NAME            exactly one: the controller the run starts with
    set NAME = VALUE           an input or parameter of a controller of the scene, or
                               ACTUATOR.KEY (an actuator setting before the run starts)
    at T set NAME = VALUE      an input changed at time T (only inputs change during a run)
    at T switch CONTROLLER     from time T on, CONTROLLER drives the run
    time T                     how long the run lasts
"""

from __future__ import annotations

import dataclasses
import re

from legdsl.check.gait_bands import reversed_band, tell_never_chosen, widen_advice
from legdsl.check.simulation import counted
from legdsl.check.values import (
    did_you_mean,
    doubled_minus,
    measures,
    owning_creature,
    unit_to_write,
    written_unit,
)
from legdsl.ir.model import NON_NEGATIVE, SETTABLE, Model, setting_kind
from legdsl.ir.scene import (
    GaitBand,
    Scene,
    SceneSwitch,
    SceneValue,
    choose_gaits,
    first_command,
    starts_in_band,
)
from legdsl.lang import ast
from legdsl.lang.errors import Diagnostics, Span
from legdsl.lang.scaling import DEFAULT_DT, MOST_STEPS
from legdsl.lang.turning import as_turning
from legdsl.lang.units import DIMENSIONLESS, KINDS, Dim, a_kind, out_of_range

_TIME: Dim = KINDS["time"][0]


def _example(dim: Dim) -> str:
    for kind_dim, unit in KINDS.values():
        if kind_dim == dim:
            return unit
    return ""


def _digits(text: str) -> str:
    match = re.match(r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?", text)
    return match.group(0) if match else text


def _number(
    value: ast.Value, want: Dim, what: str, diag: Diagnostics, declared: str = ""
) -> float | None:
    """The SI value of a number written for ``what`` (of dimension ``want``, which the file
    declared in the unit ``declared``, if any: the advice keeps it), or None after reporting
    why not."""
    declared = declared if measures(declared, want) else ""
    if doubled_minus(value, diag.error):
        return None
    sign, written = 1.0, value  # the value as written, its minus too ('-1 rad')
    while isinstance(value, ast.Neg):
        sign, value = -sign, value.value
    if not isinstance(value, ast.Number):
        diag.error(value.span, f"{what} is a number with its unit here")
        return None
    q = value.quantity
    number = sign * q.value
    text = ("-" if sign < 0 else "") + value.text
    trouble = out_of_range(value.text, q.value)
    if trouble is not None:  # it read as inf (or 0), and the run would refuse it placeless
        diag.error(value.span, trouble)
        return None
    if want == DIMENSIONLESS:
        if not q.unitless and q.dim != DIMENSIONLESS:
            diag.error(written.span, f"{what} is dimensionless, but {text} is {a_kind(q.dim)}")
            return None
        return number
    if q.unitless:
        if number != 0:
            diag.error(
                written.span,
                f"{what} is {a_kind(want, declared)}: give its unit, e.g. {text} "
                f"{declared or _example(want)}",
            )
            return None
        return 0.0
    if q.dim != want:
        unit = unit_to_write(written_unit(value.text), want, declared) or _example(want)
        fix = as_turning(text, number, q.dim, want, unit)  # '1 Hz' for deg/s: 360 deg/s
        diag.error(
            written.span,
            f"{what} is {a_kind(want, declared)}, but {text} is {a_kind(q.dim)}; "
            + (fix or f"write e.g. {_digits(text)} {unit}".rstrip()),
        )
        return None
    return number


class _SceneChecker:
    def __init__(self, decl: ast.SceneDecl, model: Model, diag: Diagnostics, refused: set[str],
                 elsewhere: dict[str, str]):  # fmt: skip
        self.decl, self.model, self.diag = decl, model, diag
        self.elsewhere = elsewhere  # the other creatures' controllers: their creature
        self.controllers = {c.name: c for c in model.controllers}
        # controllers of the file refused with their own errors: no unknown ones, and the
        # names the scene sets may be theirs (a second, false error would say they are absent)
        self.refused = refused - set(self.controllers)
        self.partial = False
        self.switched_to: list[str] = []  # the controllers of its `at T switch` lines

    def _controller(self, ident: ast.Ident) -> bool:
        if ident.name in self.controllers:
            return True
        # an unknown controller's names are unknown too: a `set` of one is not told absent
        self.partial = True
        if ident.name in self.refused:
            return False
        known = ", ".join(self.controllers) or "none"
        if ident.name in self.elsewhere:
            self.diag.error(
                ident.span,
                f"'{ident.name}' is a controller of creature '{self.elsewhere[ident.name]}'; a "
                f"scene runs its own creature's controllers: use one of {self.model.name}'s "
                f"({known}), or write this in a scene for {self.elsewhere[ident.name]}",
            )
            return False
        self.diag.error(
            ident.span,
            f"creature '{self.model.name}' has no controller '{ident.name}' (controllers: "
            f"{known}){did_you_mean(ident.name, self.controllers)}",
        )
        return False

    def check(self) -> Scene | None:
        decl, diag = self.decl, self.diag
        first = [i for i in decl.items if isinstance(i, ast.SceneController)]
        tables = [i for i in decl.items if isinstance(i, ast.SceneGaits)]
        if not first and not tables:
            diag.error(
                decl.name.span,
                f"scene '{decl.name.name}' needs 'controller NAME' (the controller it starts "
                "with) or 'gait by speed { ... }'",
            )
            return None
        for extra in first[1:]:
            diag.error(
                extra.span,
                f"a scene starts with one controller (the first is at line {first[0].span.line}); change controllers with 'at T switch NAME'",
            )
        for again in tables[1:]:
            diag.error(
                again.span,
                f"a scene has one gait table (the first is at line {tables[0].span.line})",
            )
        ok = not first or self._controller(first[0].name)
        switches = self._switches(bool(tables))
        bands = self._bands(tables[0]) if tables else ()
        # the table's controllers, even when a band is wrong: its sets are still theirs
        names = [*(f.name.name for f in first[:1]), *self.switched_to,
                 *(b.controller.name for b in (tables[0].bands if tables else ()))]  # fmt: skip
        used = [self.controllers[n] for n in dict.fromkeys(names) if n in self.controllers]
        values = [v for item in decl.items if isinstance(item, ast.SceneSet)
                  for v in [self._value(item, used)] if v is not None]  # fmt: skip
        self._two_commands(values)
        duration = self._duration()
        if not ok or bands is None:
            return None
        start = first[0].name.name if first else None
        by = tables[0].input.name if tables else ""
        for v in values if bands else []:  # the table chooses by the command all share
            owner, _, key = v.name.partition(".")
            if key == by and owner in self.controllers:
                diag.error(
                    v.span,
                    f"'gait by {by}' chooses by one command of {by} for all its controllers; "
                    f"give it with 'set {by} = ...' (a scene with a gait table gives no "
                    f"controller its own {by})",
                )
                return None
        if bands:
            start = self._gaits(tables[0], bands, first[0] if first else None, used, values)
            if start is None:
                return None
        assert start is not None
        switches.sort(key=lambda s: s.t)
        return Scene(decl.name.name, start, tuple(values), tuple(switches), duration, decl.span,
                     bands, by, not first)  # fmt: skip

    def _switches(self, by_table: bool) -> list[SceneSwitch]:
        diag = self.diag
        switches: list[SceneSwitch] = []
        seen: dict[float, Span] = {}
        for item in self.decl.items:
            if not isinstance(item, ast.SceneSwitch):
                continue
            if by_table:
                diag.error(
                    item.span,
                    "this scene chooses its controllers with 'gait by'; leave out 'at T switch' (or the gait table)",
                )
                continue
            assert item.at is not None
            t = _number(item.at, _TIME, "the time after 'at'", diag)
            good = self._controller(item.controller)
            if good:  # its sets are its own, even when the time is wrong
                self.switched_to.append(item.controller.name)
            if t is not None and t <= 0:
                diag.error(
                    item.at.span,
                    "a switch comes after the start (the scene's 'controller' starts it)",
                )
            elif t is not None and t in seen:
                diag.error(
                    item.span,
                    f"two switches at {t:g} s (the other at line {seen[t].line}); the run "
                    "changes to one controller at a time: keep one",
                )
            elif t is not None and good:
                seen[t] = item.span
                switches.append(SceneSwitch(t, item.controller.name, item.span))
        return switches

    def _two_commands(self, values: list[SceneValue]) -> None:
        """Two ``at T set`` lines for one input at one time, two ``set`` lines of one name, or
        a ``set`` and an ``at 0 s set`` of one (the command replaces the value before it is
        used): the run would keep one silently (as such ``--set`` texts are refused)."""
        seen: dict[tuple[str, float], Span] = {}
        given: dict[str, Span] = {}
        for v in values:
            if v.at is None and v.name in given:
                self.diag.error(
                    v.span,
                    f"{v.name} is set twice (the other at line {given[v.name].line}); the later "
                    "would win silently: keep one",
                )
            if v.at is None:
                given.setdefault(v.name, v.span)
                continue
            if v.at == 0 and v.name in given:
                self.diag.error(
                    v.span,
                    f"{v.name} is set at line {given[v.name].line} and commanded here at 0 s: the "
                    "command replaces that value before it is used: keep one",
                )
            if (v.name, v.at) in seen:
                self.diag.error(
                    v.span,
                    f"two commands for {v.name} at {v.at:g} s (the other at line "
                    f"{seen[v.name, v.at].line}); an input takes one command at a time: keep one",
                )
            else:
                seen[v.name, v.at] = v.span

    def _duration(self) -> float | None:
        diag = self.diag
        times = [i for i in self.decl.items if isinstance(i, ast.SceneTime)]
        for later in times[1:]:
            diag.error(
                later.span, f"the scene's time is given twice (first at line {times[0].span.line})"
            )
        if not times:
            return None
        duration = _number(times[0].value, _TIME, "the scene's time", diag)
        if duration is not None and duration <= 0:
            diag.error(times[0].value.span, "the scene's time must be more than zero")
        step = self.model.simulation.dt or DEFAULT_DT
        if duration is not None and duration / step > MOST_STEPS:
            diag.error(times[0].value.span, counted("the scene's time", duration, step))
        return duration

    def _band_input(self, table: ast.SceneGaits, names: list[str]) -> Dim | None:
        want = table.input.name
        for name in names:
            found = next((c for c in self.controllers[name].inputs if c.name == want), None)
            if found is not None:
                return found.dim
        self.diag.error(
            table.input.span, f"'gait by {want}': no controller of the table has an input '{want}'"
        )
        return None

    def _bands(self, table: ast.SceneGaits) -> tuple[GaitBand, ...] | None:
        diag = self.diag
        if not table.bands:
            diag.error(table.span, "a gait table needs a band: CONTROLLER from LOW to HIGH")
            self.partial = True  # the names the scene sets are its missing controllers' own
            return None
        good = [b for b in table.bands if self._controller(b.controller)]
        if len(good) < len(table.bands):
            self.partial = True
            return None
        dim = self._band_input(table, [b.controller.name for b in good])
        if dim is None:
            return None
        out, fine = [], True
        for b in good:
            what = f"a band of {table.input.name}"
            low = _number(b.low, dim, what, diag) if b.low is not None else None
            high = _number(b.high, dim, what, diag) if b.high is not None else None
            if (b.low is not None and low is None) or (b.high is not None and high is None):
                fine = False
            elif low is not None and high is not None and not low < high:
                diag.error(b.span, reversed_band(b, table.input.name))
                fine = False
            else:
                out.append(GaitBand(b.controller.name, low, high, b.span))
        start = next(
            (i.name.name for i in self.decl.items if isinstance(i, ast.SceneController)), None
        )
        if fine and not tell_never_chosen(tuple(out), start, table.input.name, _example(dim), diag):
            fine = False
        return tuple(out) if fine else None

    def _gaits(self, table: ast.SceneGaits, bands: tuple[GaitBand, ...],
               line: ast.SceneController | None, used: list,
               values: list[SceneValue]) -> str | None:  # fmt: skip
        """The controller the scene starts with; a command no band holds is an error at it, and
        a ``controller`` line whose bands do not hold the first command at the line."""
        name = table.input.name
        start = line.name.name if line is not None else None
        given = [v for v in values if v.name == name and v.at is None]
        default = next((c.value for ctl in used for c in ctl.inputs if c.name == name), 0.0)
        initial = given[-1].value if given else default
        changes = [(v.at, v.value) for v in values if v.name == name and v.at is not None]
        first, _, lost = choose_gaits(bands, start, initial, changes)
        unit = _example(next(c.dim for ctl in used for c in ctl.inputs if c.name == name))
        bands_text = "; ".join(b.text(unit) for b in bands)
        for t, v in lost:
            at = next((x for x in values if x.name == name and x.at == t and x.value == v), None)
            span = at.span if at is not None else (given[-1].span if given else table.span)
            self.diag.error(
                span,
                f"no band of 'gait by {name}' holds {name} = {v:g} {unit} (bands: {bands_text}): "
                + widen_advice(bands, v, unit),
            )
        if lost:
            return None
        speed = first_command(initial, changes)
        if line is not None and not starts_in_band(bands, line.name.name, speed):
            by_band, _, _ = choose_gaits(bands, None, initial, changes)
            self.diag.error(
                line.name.span,
                f"the scene starts with {line.name.name}, but no band of {line.name.name} holds the first "
                f"command, {name} = {speed:g} {unit} (bands: {bands_text}): leave out this line "
                f"(the table starts with {by_band}), or give a first command in its band",
            )
            return None
        return first

    def _value(self, item: ast.SceneSet, used: list) -> SceneValue | None:
        diag = self.diag
        at = None
        if item.at is not None:
            at = _number(item.at, _TIME, "the time after 'at'", diag)
            if at is None:
                return None
            if at < 0:
                diag.error(
                    item.at.span, "the time after 'at' must not be negative: 0 s is the start"
                )
                return None
        name = ".".join(i.name for i in item.target)
        where = item.target[0].span
        path = next((c.name for c in used for p in c.paths if p.name == item.target[0].name), None)
        if path is not None:  # a path is the controller's, or the command line's
            diag.error(
                where,
                f"'{item.target[0].name}' is a path of controller {path}; a scene does not give "
                f"paths: write it in the controller ('path {item.target[0].name} = circle(...)', "
                f"in a controller that extends {path}), or run with --path "
                f"{item.target[0].name}=...",
            )
            return None
        if item.target[0].name in self.refused:
            return None  # that controller's own errors are told
        if len(item.target) == 2 and item.target[0].name in self.controllers:
            return self._own_value(item, name, at, used)
        if len(item.target) > 1:
            return self._actuator(item, name, at)
        inputs = {c.name: c for ctl in reversed(used) for c in ctl.inputs}
        params = {c.name: c for ctl in reversed(used) for c in ctl.params}
        if name in inputs:
            dim, declared = inputs[name].dim, inputs[name].unit
        elif name in params:
            if at is not None:
                diag.error(
                    where,
                    f"{name} is a parameter; only inputs change during a run (inputs: {', '.join(inputs) or 'none'})",
                )
                return None
            dim, declared = params[name].dim, params[name].unit
        elif self.partial:  # perhaps a name of a refused controller of the scene
            return None
        else:
            known = [*inputs, *params]
            diag.error(where, f"no controller of this scene has an input or parameter '{name}' "
                              f"(they have {', '.join(known) or 'none'}){did_you_mean(name, known)}")  # fmt: skip
            return None
        value = _number(item.value, dim, name, diag, declared)
        return None if value is None else SceneValue(name, value, dim, at, item.span)

    def _own_value(
        self, item: ast.SceneSet, name: str, at: float | None, used: list
    ) -> SceneValue | None:
        """``set CONTROLLER.NAME = VALUE``: one controller's own parameter or input default."""
        diag = self.diag
        owner, key = item.target
        if owner.name not in [c.name for c in used]:
            if self.partial:  # perhaps the controller of a line told wrong
                return None
            runs = ", ".join(c.name for c in used) or "none"
            diag.error(
                owner.span,
                f"controller '{owner.name}' does not run in this scene (it runs {runs}); switch "
                f"to it with 'at T switch {owner.name}', or leave out this line",
            )
            return None
        if at is not None:
            diag.error(
                item.at.span if item.at is not None else owner.span,
                f"{name} is controller {owner.name}'s own value, set before the run; "
                f"to change an input during the run write 'at T set {key.name} = ...'",
            )
            return None
        ctl = self.controllers[owner.name]
        own = {c.name: c for c in (*ctl.inputs, *ctl.params)}
        if key.name not in own:
            diag.error(key.span, f"controller {owner.name} has no input or parameter '{key.name}'"
                                 f"{did_you_mean(key.name, own)}")  # fmt: skip
            return None
        constant = own[key.name]
        value = _number(item.value, constant.dim, name, diag, constant.unit)
        return None if value is None else SceneValue(name, value, constant.dim, None, item.span)

    def _actuator(self, item: ast.SceneSet, name: str, at: float | None) -> SceneValue | None:
        diag = self.diag
        by_name = {a.name: a for a in self.model.actuators}
        actuator, key = item.target[0], item.target[1]
        if at is not None:
            diag.error(
                item.target[0].span,
                "only controller inputs change during a run; an actuator is set before it starts",
            )
            return None
        if actuator.name not in by_name or len(item.target) != 2:
            diag.error(
                actuator.span,
                f"no controller or actuator '{actuator.name}'"
                f"{did_you_mean(actuator.name, [*self.controllers, *by_name])}",
            )
            return None
        a = by_name[actuator.name]
        if key.name not in SETTABLE[a.kind]:
            diag.error(key.span, f"a {a.kind} has {', '.join(SETTABLE[a.kind])}")
            return None
        dim = KINDS[setting_kind(key.name, a.rotary)][0]
        value = _number(item.value, dim, name, diag)
        if value is not None and key.name in NON_NEGATIVE and value < 0:
            diag.error(item.value.span, f"'{key.name}' must not be negative")
            return None
        return None if value is None else SceneValue(name, value, dim, None, item.span)


def _written_for(tree: ast.SourceFile, model: Model, models: list[Model]) -> set[str]:
    """The names of the file's controllers written for ``model``: those naming it with
    'for', and those without 'for' that no other creature has."""
    others = {c.name for m in models if m is not model for c in m.controllers}
    return {
        c.name.name
        for c in tree.controllers
        if (c.creature.name == model.name if c.creature else c.name.name not in others)
    }


def check_scenes(tree: ast.SourceFile, models: list[Model], diag: Diagnostics) -> list[Model]:
    """Attach each scene of the file to its creature (``Model.scenes``)."""
    scenes: dict[str, list[Scene]] = {m.name: [] for m in models}
    seen: dict[tuple[str, str], Span] = {}
    for decl in tree.scenes:
        model = owning_creature(decl, "scene demo", tree, models, diag)
        if model is None:
            continue
        key = (model.name, decl.name.name)
        if key in seen:
            diag.error(
                decl.name.span,
                f"scene '{decl.name.name}' is defined twice (first at line {seen[key].line}); "
                "give each scene of a creature a name of its own",
            )
            continue
        seen[key] = decl.name.span
        elsewhere = {c.name: m.name for m in models if m is not model for c in m.controllers}
        written = _written_for(tree, model, models)
        scene = _SceneChecker(decl, model, diag, written, elsewhere).check()
        if scene is not None:
            scenes[model.name].append(scene)
    return [
        dataclasses.replace(m, scenes=tuple(scenes[m.name])) if scenes[m.name] else m
        for m in models
    ]
