"""A run's controllers and timed commands: ``--switch``, a scene's lines and the command
line's added to them (``scene_plan``), and the notes on commands after the run's end."""

from __future__ import annotations

import contextlib
from collections.abc import Mapping, Sequence
from typing import Any

from legdsl.analysis.path_report import Followed
from legdsl.check.values import did_you_mean
from legdsl.ir.model import Model
from legdsl.ir.paths import PathSpec
from legdsl.ir.scene import Scene, choose_gaits, first_command, starts_in_band
from legdsl.lang.errors import UsageError
from legdsl.lang.units import KINDS, Dim, si_unit
from legdsl.pipeline.scaled import scale_path
from legdsl.pipeline.settings import Settings, check_dimension, parse_given, sort_settings
from legdsl.sim.run_loop import RunOptions, last_tick
from legdsl.sim.switching import HANDOVER_WAIT, Switch, SwitchingMachine

_TIME: Dim = KINDS["time"][0]


def parse_switch(text: str, model: Model) -> Switch:
    """``--switch 6s=gallop``: from 6 s on the run is driven by controller ``gallop``."""
    when, sep, name = text.partition("=")
    name = name.strip()
    if not sep or not when.strip() or not name:
        raise UsageError(f"--switch {text!r}: write TIME=CONTROLLER, e.g. --switch 6s=gallop")
    given = parse_given(when, f"--switch {text}")
    check_dimension(f"--switch {text}", "the time before '=' is in seconds", given, _TIME,
                    "--switch {}=" + name)  # fmt: skip
    controllers = [c.name for c in model.controllers]
    if name not in controllers:
        raise UsageError(
            f"--switch {text}: creature '{model.name}' has no controller {name!r}"
            f"{did_you_mean(name, controllers)} (it has {', '.join(controllers) or 'none'})"
        )
    if not given.value > 0:
        raise UsageError(
            f"--switch {text}: a switch comes after the start; to start with {name}, write "
            f"--controller {name}, else give a time after 0, e.g. --switch 1s={name}"
        )
    return Switch(given.value, name)


def too_late(
    settings: Sequence[str],
    options: RunOptions,
    sources: Mapping[str, str] | None = None,
    flags: bool = True,
) -> list[str]:
    """The input changes (``--set NAME=V@T``, a scene's ``at T set``) that come after the
    run's end, or after its last control tick (which reads them): notes for the user, since
    they will not happen (a switch that never took over is told after the run, which knows
    whether it waited for a liftoff). ``sources`` names a scene's lines as written
    (``scene_sources``), not as the ``--set`` they stand for; unless ``flags``, in the API's
    words (``set={'speed@5s': '1m/s'}``, ``time=``)."""
    duration, last = options.duration, last_tick(options)
    notes = []
    sources = sources or {}
    for text in (text for text in settings if "@" in text):
        with contextlib.suppress(UsageError):  # a mistake in it is reported by the run
            given = parse_given(text.rpartition("@")[2], text)
            check_dimension(text, "", given, _TIME, "@{}")
            said = sources.get(text, f"--set {text}" if flags else _set_written(text))
            longer = "give a longer --time" if flags else "give a longer time="
            if given.value > duration:
                notes.append(
                    f"{said} comes after the run's end ({duration:g} s) and has no effect; "
                    f"{longer} to see it"
                )
            elif given.value > last + 1e-12:  # as the machine reads a change (machine.py)
                notes.append(
                    f"{said} comes after the controller's last tick ({last:.4g} s of the "
                    f"{duration:g} s run) and has no effect; {longer} to see it"
                )
    return notes


def _set_written(text: str) -> str:
    """``speed=1m/s@5s`` as the API's ``set={'speed@5s': '1m/s'}``."""
    name, _, rest = text.partition("=")
    value, _, when = rest.rpartition("@")
    return f"set={{{f'{name}@{when}'!r}: {value!r}}}"


def scene_texts(scene: Scene) -> tuple[list[str], list[str]]:
    """A scene's ``set`` and ``at T switch`` lines as the ``--set`` and ``--switch`` texts
    they stand for (SI values with their SI units, exact: ``repr`` of each float)."""
    sets = [
        f"{v.name}={v.value!r}{si_unit(v.dim)}" + (f"@{v.at!r}s" if v.at is not None else "")
        for v in scene.values
    ]
    switches = [f"{w.t!r}s={w.controller}" for w in scene.switches]
    return sets, switches


def scene_sources(scene: Scene, written: Scene | None = None) -> dict[str, str]:
    """Each ``set`` line of ``scene`` by the ``--set`` text it stands for, as a note names it:
    its place in the file and its words (``demo.leg:30:3: 'at 11 s set speed' of scene demo``),
    with the times of ``written``, the file's scene that ``scene`` is scaled from
    (``scale_scene``: a note quoted its scaled times as the file's words)."""
    sets, switches = scene_texts(scene)
    named: dict[str, str] = {}
    for text, v, ran in zip(sets, (written or scene).values, scene.values, strict=True):
        at = "" if v.at is None else f"at {v.at:g} s "
        scaled = f", at {ran.at:g} s once scaled," if ran.at != v.at else ""
        named[text] = f"{v.span}: '{at}set {v.name}' of scene {scene.name}{scaled}"
    # its switches by '--switch TEXT', as a note after the run names them (switches_not_made)
    for text, s, done in zip(switches, (written or scene).switches, scene.switches, strict=True):
        scaled = f", at {done.t:g} s once scaled," if done.t != s.t else ""
        named[f"--switch {text}"] = (
            f"{s.span}: 'at {s.t:g} s switch {s.controller}' of scene {scene.name}{scaled}"
        )
    # a gait table's switches, by the command of its input that chooses them (scene_plan)
    bands = dict.fromkeys(b.controller for b in scene.bands)
    for v, ran in zip((written or scene).values, scene.values, strict=True):
        if v.at is None or ran.at is None or v.name != scene.band_input:
            continue
        scaled = f", at {ran.at:g} s once scaled," if ran.at != v.at else ""
        for name in bands:
            named.setdefault(
                f"--switch {ran.at!r}s={name}",
                f"the switch to {name} that the gait table of scene {scene.name} chooses for "
                f"{v.span}: 'at {v.at:g} s set {v.name}'{scaled}",
            )
    return named


def switch_source(w: Switch, sources: Mapping[str, str] | None) -> str:
    """A switch as a note names it: a scene's line where it is written (``scene_sources``),
    else the ``--switch`` it was given as."""
    return (sources or {}).get(
        f"--switch {w.t!r}s={w.controller}", f"--switch {w.t:g}s={w.controller}"
    )


def find_scene(model: Model, name: str) -> Scene:
    """``--scene NAME``: the creature's scene of that name, or a ``UsageError`` naming them."""
    names = [s.name for s in model.scenes]
    if name not in names:
        raise UsageError(
            f"--scene {name}: creature '{model.name}' has no scene {name!r} "
            f"(scenes: {', '.join(names) or 'none; write one: scene NAME { controller ...; }'})"
        )
    return model.scene(name)


def _not_overridden(
    scene: Scene,
    model: Model,
    sets: list[str],
    changes: list[str],
    settings: Sequence[str],
    switches: Sequence[str],
) -> tuple[list[str], list[str]]:
    """The scene's ``set`` and ``switch`` texts less those the command line overrides: a
    ``--set NAME=V@T`` replaces the scene's command for NAME at T, a ``--switch T=C`` its
    switch at T (two at one time would be refused, and the scene's line cannot be left out
    from the command line). Its untimed ``--set`` already wins, as the later value."""
    timed: set[tuple[str, float]] = set()
    for text in settings:
        if "@" in text:
            setting, _, when = text.rpartition("@")
            with contextlib.suppress(UsageError):  # a malformed one is told by sort_settings
                timed.add((setting.partition("=")[0].strip(), parse_given(when, text).value))
    times = set()
    for text in switches:
        with contextlib.suppress(UsageError):
            times.add(parse_switch(text, model).t)
    kept_sets = [
        text
        for text, v in zip(sets, scene.values, strict=True)
        if v.at is None or not any(n == v.name and same_time(t, v.at) for n, t in timed)
    ]
    kept_changes = [
        text
        for text, w in zip(changes, scene.switches, strict=True)
        if not any(same_time(t, w.t) for t in times)
    ]
    return kept_sets, kept_changes


def same_time(a: float, b: float) -> bool:
    """Two times of a run's commands or switches that are one (written apart: 8s, 8000ms)."""
    return abs(a - b) < 1e-9


def refuse_two_commands(texts: Sequence[str], settings: Settings) -> None:
    """Two commands for one input at one time: the run would keep the later one silently."""
    timed = [text for text in texts if "@" in text]  # in order, one per scheduled change
    seen: dict[tuple[str, float], str] = {}
    for text, change in zip(timed, settings.schedule, strict=True):
        other = next((o for (n, t), o in seen.items()
                      if n == change.name and same_time(t, change.t)), None)  # fmt: skip
        if other is not None:
            raise UsageError(
                f"--set {other} and --set {text} command {change.name} at the same time "
                f"({change.t:g} s): an input takes one command at a time; keep one"
            )
        seen[(change.name, change.t)] = text


def scene_plan(
    scene: Scene,
    model: Model,
    settings: Sequence[str],
    switches: Sequence[str],
    notes: list[str] | None = None,
) -> tuple[str, list[str], list[str]]:
    """The controller, ``--set`` and ``--switch`` texts of a run of ``scene`` with the command
    line's own ``settings`` and ``switches`` added after the scene's lines. A scene with a
    gait table (``gait by speed { ... }``) gets its switches from the final speed commands
    (``legdsl.ir.scene.choose_gaits``); a command no band holds is a ``UsageError``. A
    ``settings`` text left out, as it is only for a band the commands never reach, is told
    in ``notes``."""
    sets, changes = scene_texts(scene)
    sets, changes = _not_overridden(scene, model, sets, changes, settings, switches)
    texts = sets + list(settings)
    if not scene.bands:
        return scene.controller, texts, changes + list(switches)
    if switches:
        raise UsageError(
            f"--switch: scene {scene.name} chooses its controllers by its gait table; leave out "
            "--switch (a --set of the table's input at a time changes gait), or run without "
            "--scene, giving --controller and --switch"
        )
    names = list(dict.fromkeys([scene.controller, *(b.controller for b in scene.bands)]))
    given = sort_settings(texts, model, names[0], names[1:])
    by = scene.band_input
    default = next(
        (c.value for n in names for c in model.controller(n).inputs if c.name == by), 0.0
    )
    initial = given.inputs.get(by, default)
    commands = [(c.t, c.value) for c in given.schedule if c.name == by]
    start = None if scene.starts_by_band else scene.controller
    first, planned, lost = choose_gaits(scene.bands, start, initial, commands)
    bands = "; ".join(b.text() for b in scene.bands)
    if lost:
        t, v = lost[0]
        raise UsageError(
            f"--scene {scene.name}: no band of its gait table holds {by} = {v:g} (SI) at {t:g} s "
            f"(bands, SI: {bands})"
        )
    speed = first_command(initial, commands)
    if start is not None and not starts_in_band(scene.bands, start, speed):  # a --set moved it
        raise UsageError(
            f"--scene {scene.name} starts with {start} (its 'controller' line), but no band of "
            f"{start} holds the first command, {by} = {speed:g} (SI) (bands, SI: {bands}); give "
            "a first command in its band"
        )
    # a band's values ('set pace.kp = ...', or a name only its controller has) wait for its
    # band: a band the commands never reach has none (the run refuses names it lacks)
    chosen = {first, *(name for _, name in planned)}
    idle = {n for n in names if n not in chosen}
    has = {n: {v.name for v in (*c.inputs, *c.params)} for n in names
           for c in [model.controller(n)]}  # fmt: skip
    kept = set().union(*(has[n] for n in chosen))
    waiting = set().union(*(has[n] for n in idle)) - kept

    def runs(text: str) -> bool:
        name = text.partition("=")[0].strip()
        return name.partition(".")[0] not in idle and name not in waiting

    if notes is not None:
        for text in (t for t in settings if not runs(t)):
            name = text.partition("=")[0].strip()
            owners = [n for n in idle if name.partition(".")[0] == n or name in has[n]]
            notes.append(
                f"--set {text}: only {' and '.join(owners)} has it, and the commands never "
                f"reach its band of the gait table of scene {scene.name} (SI: "
                + "; ".join(b.text() for b in scene.bands if b.controller in owners)
                + "): it changes nothing in this run"
            )
    return first, [t for t in texts if runs(t)], [f"{t!r}s={name}" for t, name in planned]


def switches_to_the_running(first: str, switches: Sequence[Switch]) -> list[str]:
    """Notes for a switch to the controller the switch before it (or the start) asked for:
    not nothing, a restart of its state machine (docs/runtime.md#changing-controllers)."""
    notes, running, since = [], first, "the start"
    for w in sorted(switches, key=lambda w: w.t):
        if w.controller == running:
            notes.append(
                f"the switch to {w.controller} at {w.t:g} s is to the controller already asked "
                f"for (since {since}): it restarts {w.controller}'s state machine at the next "
                "liftoff (the state that matches the feet down, its 'own' records from 0); "
                "leave it out to keep the run as it is"
            )
        running, since = w.controller, f"{w.t:g} s"
    return notes


def switches_not_made(run: Any, sources: Mapping[str, str] | None = None) -> list[str]:
    """Notes of the switches that never took over, each named as written (a scene's line,
    ``sources``, else its ``--switch``), as a late ``--set`` is: those still waiting for a
    liftoff when the next came due, and those the run ended before (given for after its end,
    or still waiting). run.json lists them with the switches made."""
    machine = run.machine
    if not isinstance(machine, SwitchingMachine):
        return []
    wait = HANDOVER_WAIT * (machine.unit or 1.0)  # for this creature's size
    restarted = _restarts(machine)
    lines = [
        f"{switch_source(gone, sources)} was still waiting for a liftoff when the switch to "
        f"{by.controller} at {by.t:g} s came due, and never took over (a switch waits up to "
        f"{wait:.3g} s): give the later one a later time to see both"
        + (
            f"; {by.controller} was still running, so {switch_source(by, sources)} restarts "
            f"its state machine (the state that matches the feet down, its 'own' records "
            "from 0)"
            if id(by) in restarted
            else ""
        )
        for gone, by in machine.superseded
    ]
    over = {id(w) for w in machine.made} | {id(gone) for gone, _ in machine.superseded}
    left = [w for w in machine.switches if id(w) not in over]
    if not left or run.result.status != "ok":
        return lines
    end = run.result.sim_time
    # a switch whose time never came did not wait for a liftoff: told as a late --set is
    for w in left:
        if w.t <= end:
            lines.append(
                f"{switch_source(w, sources)} was still waiting for a liftoff when the run ended "
                f"at {end:g} s, and never took over (a switch waits up to {wait:.3g} s for a "
                "liftoff); give a longer --time to see it"
            )
        else:
            lines.append(
                f"{switch_source(w, sources)} comes after the run's end ({end:g} s) and never "
                "took over; give a longer --time to see it"
            )
    return lines


def _restarts(machine: SwitchingMachine) -> set[int]:
    """The switches that took over from the controller they name (by ``id``): a switch to
    another one came between them but never took over (``switches_to_the_running`` tells
    the others, asked for twice in a row, before the run)."""
    running, out = machine.segments[0]["controller"], set()
    for w in machine.made:
        if w.controller == running:
            out.add(id(w))
        running = w.controller
    return out


def followed_paths(machine: Any, end: float, scale: float | None = None) -> list[Followed]:
    """The paths given to a run's controllers (``path NAME`` left without one is none), each
    with the spans of the run in which a controller followed it: None for one followed from
    start to ``end``. A switched run's later controller may follow another shape under the
    same name, or none; consecutive segments with one path share its tracker, as in the run.
    A run of the creature scaled by ``scale`` (never switched) has its paths as the file's."""
    if not isinstance(machine, SwitchingMachine):
        given = [p for p in machine.paths if p.shape != "none"]
        back = [p if scale is None else scale_path(p, 1 / scale) for p in given]
        return [(p, None) for p in back]
    machines = [m for _, m in machine.finished] + [machine.current]
    specs: list[PathSpec] = []
    spans: list[list[tuple[float, float]]] = []
    for seg, m in zip(machine.segment_info(end), machines, strict=True):
        for spec in (p for p in m.paths if p.shape != "none"):
            if spec not in specs:
                specs.append(spec)
                spans.append([])
            mine = spans[specs.index(spec)]
            if mine and same_time(mine[-1][1], seg["from"]):  # its tracker carried on
                mine[-1] = (mine[-1][0], seg["to"])
            else:
                mine.append((seg["from"], seg["to"]))
    return [
        (spec, None if len(s) == 1 and s[0][0] == 0 and same_time(s[0][1], end) else s)
        for spec, s in zip(specs, spans, strict=True)
    ]
