"""The run session: a creature loaded once, run with a controller and settings, its run written.

    session = RunSession.from_file("creatures/kangaroo.leg")        # check; compile if stale
    run = session.run("hop", settings=["speed=3m/s", "speed=4m/s@1s"],
                      options=RunOptions(duration=2.0))
    run.write("runs/kangaroo")                                       # npz, csv, run.json
    print(run.summary())

``legdsl run`` is this plus argument parsing and printing; the tests and benchmarks use it too.
The run directory gets ``trajectory.npz`` and ``trajectory.csv`` (see
``legdsl.sim.trajectory``) and ``run.json``: every input, parameter and option, the legdsl
version, the events (touchdowns, liftoffs, state changes), the status and its message, and the
path reports of a run that followed paths.
"""

from __future__ import annotations

import itertools
import json
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from types import ModuleType
from typing import Any

from legdsl import __version__
from legdsl.check.source import check_tree, choose
from legdsl.codegen.fingerprints import creature_fingerprint, motion_fingerprint
from legdsl.files import file_sha256, remove, write_atomic, writing_alone
from legdsl.ir.model import Model
from legdsl.ir.paths import PathSpec
from legdsl.lang import ast
from legdsl.lang.errors import Diagnostic, LegError, UsageError
from legdsl.lang.parser import parse_file
from legdsl.pipeline import run_line, scaled
from legdsl.pipeline.backend import make_simulation
from legdsl.pipeline.generated import load_controller, load_dynamics, recorded_folder
from legdsl.pipeline.options import check_drop, check_run_options, notes_before_run
from legdsl.pipeline.path_option import path_specs
from legdsl.pipeline.report import path_summary, run_path_reports, summary
from legdsl.pipeline.run_notes import run_notes
from legdsl.pipeline.scenes import (
    followed_paths,
    parse_switch,
    refuse_two_commands,
    same_time,
    switches_not_made,
    switches_to_the_running,
)
from legdsl.pipeline.settings import Settings, overwritten_notes, sort_settings
from legdsl.pipeline.start_pose import check_fall_height, check_start
from legdsl.sim import switching
from legdsl.sim.coupled import inverse_inertia
from legdsl.sim.machine import StateMachine
from legdsl.sim.run_loop import RunOptions, RunResult, intervals_as_run
from legdsl.sim.simulate import Simulation
from legdsl.sim.stability import (
    TooStiff,
    in_unit,
    on_the_line,
    setting_unit,
    stop_message,
    stops_too_stiff,
    too_stiff,
)
from legdsl.sim.switching import Switch, SwitchingMachine, check_switch_paths, natural_scale

Progress = Callable[[float, float], None]  # (simulated time, duration)
RUN_FILES = ("run.json", "trajectory.npz", "trajectory.csv")
# What the commands that read a run write into its directory by default (plot, animate,
# metrics, replay, export-motion): a new run into the directory removes them with the old run.
DERIVED_FILES = ("figure6.png", "top.png", "footfall.png", "animation.html", "metrics.json",
                 "mujoco.mp4", *(f"motion.{f}" for f in ("glb", "gltf", "usd", "usda", "bvh")))  # fmt: skip


def check_file(
    path: str | Path, creature: str | None = None, scene: str | None = None,
    controller: str | None = None,
) -> tuple[Model, ast.SourceFile]:  # fmt: skip
    """Parse and check ``path`` (once) and pick the creature: of several, with no ``creature``
    named, the only one that has ``scene`` (or else ``controller``), if only one has."""
    source = Path(path)
    syntax, text = parse_file(source, recover=True)
    models = check_tree(syntax, text, source)
    if creature is None and len(models) > 1:
        owners: list[str] = []
        if scene is not None:
            owners = [m.name for m in models if any(s.name == scene for s in m.scenes)]
        elif controller is not None:
            owners = [m.name for m in models if any(c.name == controller for c in m.controllers)]
        creature = owners[0] if len(owners) == 1 else None
    return choose(models, creature, source), syntax


class RunSession:
    """One creature, checked, with its generated dynamics loaded (compiled first if stale)."""

    def __init__(
        self,
        model: Model,
        source: str | Path,
        dynamics: ModuleType,
        generated: str | Path = "generated",
        syntax: ast.SourceFile | None = None,
        log: Any = None,
    ):
        self.model = model
        self.source = Path(source)
        self.dynamics = dynamics
        self.generated = Path(generated)
        self.syntax = syntax
        self.log = log  # where "compiling ..." notes go (a file such as sys.stderr), or None
        self.note: Callable[[str], None] | None = None  # without a log: the API's warnings
        self.tells_runs = True  # run() tells its notes; off for a batch its caller tells
        # its messages advise --dt and --integrator; a sweep's or a tune's runs take the file's
        self.step_flags = True
        # the file as checked (hashed after the run, it was one saved while the run went on)
        self.source_sha256 = file_sha256(Path(model.source))
        self._controls: dict[str, ModuleType] = {}
        # diag(M^-1) at a start state: a batch's runs mostly share theirs (RunSession.run)
        self._inverse_inertia: dict[tuple[ModuleType, tuple[float, ...]], list[float]] = {}

    @classmethod
    def from_file(
        cls,
        path: str | Path,
        creature: str | None = None,
        generated: str | Path = "generated",
        log: Any = None,
        scene: str | None = None,
        controller: str | None = None,
    ) -> RunSession:
        """Parse and check ``path`` (once), pick the creature, load or compile its dynamics.
        Of several creatures, with no ``creature`` named, the only one that has ``scene`` (or
        else ``controller``) is picked: the scene's ``for`` says which."""
        model, syntax = check_file(path, creature, scene, controller)
        return cls.from_checked(model, path, syntax, generated, log)

    @classmethod
    def from_checked(cls, model: Model, source: str | Path, syntax: ast.SourceFile,
                     generated: str | Path = "generated", log: Any = None) -> RunSession:  # fmt: skip
        """``from_file``'s second half, for a creature ``check_file`` gave: its dynamics loaded,
        compiled first if stale (``legdsl run`` refuses its options in between)."""
        dynamics = load_dynamics(model, Path(source), Path(generated), log, syntax)
        return cls(model, source, dynamics, generated, syntax, log)

    @property
    def controllers(self) -> tuple[str, ...]:
        return tuple(c.name for c in self.model.controllers)

    def control(self, controller: str) -> ModuleType:
        """The generated module of one of the creature's controllers (compiled if stale)."""
        if controller not in self._controls:
            self._controls[controller] = load_controller(
                self.model, controller, self.source, self.generated, self.log, self.syntax
            )
        return self._controls[controller]

    def run(
        self,
        controller: str | None = None,
        settings: Sequence[str] = (),
        paths: Sequence[str | PathSpec] = (),
        options: RunOptions | None = None,
        progress: Progress | None = None,
        scale: float | None = None,
        switches: Sequence[str | Switch] = (),
        backend: str | None = None,
        sources: Mapping[str, str] | None = None,
    ) -> Run:
        """Simulate (``prepare``'s arguments, with ``progress`` called as the run goes), its
        notes told before and after it (``tell_before``, ``tell_after``)."""
        plan = self.prepare(controller, settings, paths, options, scale, switches, backend, sources)
        if self.tells_runs:
            self.tell_before(controller, settings, plan.options, (), plan.sources)
        done = plan.finish(plan.sim.run(progress))
        if self.tells_runs:
            self.tell_after(done)
        return done

    def prepare(
        self,
        controller: str | None = None,
        settings: Sequence[str] = (),
        paths: Sequence[str | PathSpec] = (),
        options: RunOptions | None = None,
        scale: float | None = None,
        switches: Sequence[str | Switch] = (),
        backend: str | None = None,
        sources: Mapping[str, str] | None = None,
    ) -> Plan:
        """A run ready to simulate (its ``sim``; ``Plan.finish`` makes the ``Run`` of its
        result), with ``controller`` if given; ``settings`` are ``--set`` texts
        (``speed=3m/s``, ``speed=4m/s@1s``, ``hip_servo.setpoint=10deg``), ``paths`` are
        ``--path`` texts or path specs (one alone needs no list). Mistakes in them raise
        ``UsageError`` before anything is simulated. With ``scale`` (L), every input is for the
        creature scaled by L (Table 1), run as the unscaled model with its inputs scaled by 1/L
        and its outputs by L (``legdsl.pipeline.scaled``). ``switches`` (``--switch`` texts,
        ``6s=gallop``, or ``Switch``es) change the controller during the run
        (``legdsl.sim.switching``). ``backend`` is ``python``, ``c`` or
        ``auto``; None takes ``$LEGDSL_BACKEND``, else ``auto``: C where a compiler is found
        (``legdsl.pipeline.backend``). ``sources``: a scene's lines by the ``--set`` texts they
        stand for (``scene_sources``), which the run's notes name (``tell_before``)."""
        asked = options if options is not None else scaled.run_options(self.model, scale)
        check_run_options(asked, self.step_flags)
        if asked.drop is not None:
            check_drop(asked.drop, self.model, scale)
        welded = self.model.welded_root
        if welded is not None and asked.fall_height is not None:  # it never falls (runtime.md)
            self.tell("note", f"--fall-height is left out: creature '{self.model.name}' is "
                       f"welded to the world (its root body '{welded}' is 'fixed'): it never falls")  # fmt: skip
            asked = replace(asked, fall_height=None)
        options = asked
        settings = [settings] if isinstance(settings, str) else list(settings)
        control = self.control(controller) if controller is not None else None
        switches = [switches] if isinstance(switches, str | Switch) else list(switches)
        changes = [w if isinstance(w, Switch) else parse_switch(w, self.model) for w in switches]
        for a, b in itertools.pairwise(sorted(changes, key=lambda w: w.t)):
            if same_time(a.t, b.t):
                raise UsageError(
                    f"--switch {a.t:g}s={a.controller} and --switch {b.t:g}s={b.controller} are "
                    "at the same time: the run changes to one controller at a time; keep one"
                )
        if changes and controller is None:
            raise UsageError(
                "--switch: say which controller starts the run with --controller (controller= in "
                "Python)"
            )
        if changes and scale is not None:
            raise UsageError(
                f"--switch with --scale is not supported: write the scaled file with 'legdsl "
                f"scale {self.model.source} --by {scale:g} -o OUT.leg' and run it with --switch"
            )
        later = [w.controller for w in changes]
        sorted_settings = sort_settings(settings, self.model, controller, later)
        refuse_two_commands(settings, sorted_settings)
        if controller is not None:
            for note in switches_to_the_running(controller, changes):
                self.tell("note", note)
        if controller is not None and not changes:  # one controller: its own values are the run's
            s = sorted_settings
            s.inputs, s.params = s.for_controller(self.model.controller(controller))
        specs = path_specs(paths)
        if control is not None and controller is not None:  # as given, before any --scale
            modules = {name: self.control(name) for name in dict.fromkeys([controller, *later])}
            told = [*sorted_settings.inputs, *(c.name for c in sorted_settings.schedule)]
            given = [scaled.path_as_given(p, scale) for p in specs] if scale else specs
            for note in switching.path_notes(self.model, modules, controller, changes, given, told):
                self.tell("note", note)
        if scale is not None:
            options = scaled.scale_options(asked, scale)
            sorted_settings = scaled.scale_settings(sorted_settings, self.model, controller, scale)
            specs = [scaled.scale_path(p, scale) for p in specs]
        if specs and control is None:
            raise UsageError(
                "--path: a path is followed by a controller; choose one with --controller "
                "(controller= in Python)"
            )
        machine: StateMachine | SwitchingMachine | None = None
        if control is not None and controller is not None and changes:
            s = sorted_settings
            check_switch_paths(self.model, [controller, *later], specs)
            machine = SwitchingMachine(
                self.model, modules, controller, changes, s.inputs, s.params, s.schedule, specs,
                s.by_controller,
            )  # fmt: skip
        elif control is not None:
            s = sorted_settings
            machine = StateMachine(self.model, control, s.inputs, s.params, s.schedule, specs)
        where = (self.source, self.generated, self.syntax)
        sim = make_simulation(
            self.model, self.dynamics, options, machine, backend, where, self.log, self.note
        )
        sim.step_flags = self.step_flags
        if scale is not None:
            scaled.scale_checks(sim, scale)
        self._check_start(sim)
        for name, value in sorted_settings.actuators.items():
            actuator, _, key = name.partition(".")
            sim.actuators.by_name[actuator].set(key, value)
        controls = getattr(machine, "modules", {"": control}).values()
        self._check_stiffness(sim, controls, set(sorted_settings.actuators))
        shown = asked if scale is not None else options  # a scaled run reports the scaled
        return Plan(self.model, sim, controller, shown, sorted_settings, machine, scale,
                    self.source_sha256, dict(sources or {}), self.generated)  # fmt: skip

    def _check_start(self, sim: Simulation) -> None:
        """A contact that starts under the ground is refused at the line that places it."""
        check_start(self.model, sim, self.source)
        check_fall_height(sim)

    def _check_stiffness(
        self, sim: Simulation, controls: Iterable[ModuleType | None], given: set[str]
    ) -> None:
        """An actuator too stiff or too damped for the step diverges at once: refused (exit 2)
        with the bound (``legdsl.sim.stability``), at its line of the .leg file unless the
        value came from ``--set`` (``given``: ACTUATOR.KEY); one held by its ``max`` chatters:
        a warning."""
        written = {t for control in controls
                   for targets in getattr(control, "SETTINGS", {}).values() for t in targets}  # fmt: skip
        key = (sim.dyn, tuple(sim.q))
        inverse = self._inverse_inertia.get(key)
        if inverse is None:
            inverse = inverse_inertia(self.model, sim.dyn.mass_matrix, sim.q)
            if len(self._inverse_inertia) < 256:
                self._inverse_inertia[key] = inverse
        opts, scale = sim.options, sim.size_scale  # a --scale L run tells its creature's numbers
        flags = self.step_flags
        rotary = {a.name: a.rotary for a in self.model.actuators}
        spans = {a.name: a.span for a in self.model.actuators}

        def unit(f: TooStiff) -> str:
            return setting_unit(f.setting, rotary[f.actuator])

        def said(f: TooStiff, saturating: bool = False) -> str:
            return in_unit(f, unit(f), scale).message(opts.dt, unit(f), saturating, flags)

        def told(f: TooStiff) -> str:  # at its line (a template's names the instance)
            return said(f) + on_the_line(f, unit(f), scale) + spans[f.actuator].within

        found = too_stiff(sim.actuators.states, inverse, opts.dt, opts.integrator, written)
        if any(f"{f.actuator}.{f.setting}" in given or spans[f.actuator].line <= 0 for f in found):
            raise UsageError("; ".join(map(said, found)))
        if found:
            files = {spans[f.actuator].file for f in found}
            raise LegError(
                [Diagnostic(spans[f.actuator], told(f)) for f in found],
                {file: Path(file).read_text(encoding="utf-8") for file in files},
            )
        if self.log is None and self.note is None:
            return
        held = too_stiff(sim.actuators.states, inverse, opts.dt, opts.integrator, written, True)
        for f in held:  # saturating actuators past the bound: they chatter, a warning
            self.tell("warning", said(f, True))
        # a stop acts only once its limit is reached, which a run may never do: a warning
        stops = {st.dof: st for st in self.model.stops}
        for f in stops_too_stiff(stops.values(), inverse, opts.dt, opts.integrator):
            stop = stops[f.actuator]
            line = on_the_line(f, stop.units[0 if f.setting == "k" else 1], scale)
            self.tell("warning", f"{stop.span}: {stop_message(f, stops.values(), scale, flags)}{line}; "
                      "a run that reaches it diverges there")  # fmt: skip

    def tell_before(
        self,
        controller: str | None,
        settings: Sequence[str],
        options: RunOptions,
        unreached: Sequence[str] = (),
        sources: Mapping[str, str] | None = None,
    ) -> None:
        """Tell what a run ``prepare`` accepted does unasked: settings for gait bands it never
        reaches (``unreached``), changes after its end (a scene's named by its line, ``sources``),
        a drop outlasting it, a setting its controller writes (``legdsl run``'s, the API's)."""
        texts = [settings] if isinstance(settings, str) else list(settings)
        late = notes_before_run(texts, options, self.model, sources, flags=self.log is not None)
        written = overwritten_notes(texts, controller, self, sources)
        for note in [*unreached, *late, *written]:
            self.tell("note", note)

    def tell_after(self, run: Run) -> None:
        """Tell a switch of ``run`` that never took over, and its ``run_notes`` (after its table)."""
        for note in [*switches_not_made(run, run.sources), *run_notes(run)]:
            self.tell("note", note)

    def tell(self, kind: str, text: str) -> None:
        """A note or warning about a run: printed to the log (``legdsl run``'s stderr), or
        else given to ``note`` (the API's ``LegdslWarning``), never both."""
        if self.log is not None:
            print(f"legdsl: {kind}: {text}" if kind else f"legdsl: {text}", file=self.log)
        elif self.note is not None:
            self.note(text)


def _controller_fingerprints(machine: StateMachine | SwitchingMachine | None) -> dict[str, Any]:
    """run.json's ``controller_fingerprint``: the generated module's ``FINGERPRINT``, or for a
    run that changes controllers each one's by name."""
    if isinstance(machine, SwitchingMachine):
        return {"controller_fingerprint": {n: m.FINGERPRINT for n, m in machine.modules.items()}}
    if machine is not None:
        return {"controller_fingerprint": machine.module.FINGERPRINT}
    return {}


@dataclass
class Plan:
    """A run set up and not yet simulated (``RunSession.prepare``)."""

    model: Model
    sim: Simulation
    controller: str | None
    options: RunOptions  # as asked (a scaled run's are those of the scaled creature)
    settings: Settings
    machine: StateMachine | SwitchingMachine | None
    scale: float | None = None
    source_sha256: str | None = None  # the file's as checked (RunSession.source_sha256)
    sources: dict[str, str] = field(default_factory=dict)  # a scene's lines (scene_sources)
    generated: Path | None = None  # the folder of its generated modules (RunSession.generated)

    def finish(
        self,
        result: RunResult,
        settings: Settings | None = None,
        machine: StateMachine | SwitchingMachine | None = None,
    ) -> Run:
        """The ``Run`` of ``result`` (with other ``settings`` and ``machine``: a copy's of a
        batch, ``legdsl.pipeline.batch``): scaled back, its paths reported."""
        machine = machine or self.machine
        size = natural_scale(self.sim)
        if isinstance(machine, SwitchingMachine) and machine.unit is None:
            # a C run ticks it only from its first command or switch: the notes need the size
            machine.unit = size
        if self.scale is not None:
            result = scaled.scale_result(result, self.model, self.scale)
        unit = size * (self.scale or 1.0) ** 0.5  # the creature as run
        reports = run_path_reports(machine, result, self.scale, unit, self.model)
        return Run(self.model, self.controller, self.options, settings or self.settings,
                   machine, result, reports, self.scale, self.source_sha256,
                   time_unit=unit, generated=self.generated, sources=self.sources)  # fmt: skip


@dataclass(repr=False)  # its own printed the model and every array (290 kB)
class Run(run_line.OneLine):
    """One run of a session: what went in, what came out."""

    model: Model
    controller: str | None
    options: RunOptions
    settings: Settings
    machine: StateMachine | SwitchingMachine | None
    result: RunResult
    path_reports: list[dict[str, Any]] = field(default_factory=list)
    scale: float | None = None  # run as the creature scaled by this (legdsl run --scale)
    source_sha256: str | None = None  # the file's as checked, else read when run.json is made
    scene: str | None = None  # the scene run (--scene), which run.json names
    start: dict[str, dict[str, float]] | None = None  # its own q and v (a batch copy's q0, v0)
    time_unit: float = 1.0  # its natural time over a 0.81 m creature's (path_report.time_unit)
    generated: Path | None = None  # its generated modules' folder, which run.json records
    sources: dict[str, str] = field(default_factory=dict)  # a scene's lines (scene_sources)

    @property
    def status(self) -> str:  # ok | diverged | fell | interrupted
        return self.result.status

    def info(self) -> dict[str, Any]:
        """The content of ``run.json``."""
        extra: dict[str, Any] = {"controller": self.controller, "settings": self.settings.as_json()}
        if self.machine is not None:
            m = self.machine
            first = m.first if isinstance(m, SwitchingMachine) else m  # the run's start
            extra["inputs"] = first.initial_inputs
            extra["params"] = dict(zip(first.param_names, first.params, strict=True))
            extra["paths"] = [
                p.as_json() | ({"followed": [list(s) for s in spans]} if spans else {})
                for p, spans in followed_paths(m, self.result.sim_time, self.scale)
            ]
            extra["path_reports"] = self.path_reports
            if isinstance(m, SwitchingMachine):
                extra["switches"] = [{"t": w.t, "controller": w.controller} for w in m.switches]
                for gone, by in m.superseded:  # it never took over: the later one came due
                    entry = extra["switches"][m.switches.index(gone)]
                    entry["superseded_by"] = {"t": by.t, "controller": by.controller}
                extra["segments"] = m.segment_info(self.result.sim_time)
        result, at = self.result, self.result.diverged_at
        cause = {"ended_at": round(result.sim_time, 9), "cause": result.cause}
        ended = cause if result.cause else {}
        return {
            "legdsl": __version__,
            "source": self.model.source,
            "creature": self.model.name,
            # what the run was made from: the commands that read it refuse another creature
            "source_sha256": self.source_sha256 or file_sha256(Path(self.model.source)),
            "creature_fingerprint": creature_fingerprint(self.model),
            **_controller_fingerprints(self.machine),
            "options": asdict(self.options),
            **({"scale": self.scale} if self.scale is not None else {}),
            **{k: v for k, v in {"scene": self.scene, "start": self.start}.items() if v},
            **extra,
            "motion_fingerprint": motion_fingerprint(self.model),  # without its appearance
            "status": result.status,
            "message": result.message,
            **ended,
            **({"diverged_at": round(at, 9)} if at is not None else {}),
            **({"time_on_stops": result.stop_time} if result.stop_time else {}),
            "steps": result.steps,
            "sim_time": round(result.sim_time, 9),
            "samples": len(result.trajectory),
            "time_unit": round(self.time_unit, 9),
            **intervals_as_run(self.options),
            "events": result.events,
            **({"notes": notes} if (notes := run_notes(self)) else {}),
        }

    def write(self, out: str | Path) -> Path:
        """Write trajectory.npz, trajectory.csv and run.json into ``out`` (made if missing).

        run.json is made (in memory) before anything is written, then written first with the
        status ``incomplete``, an older run's trajectory files removed, then the trajectory,
        then run.json as it is: a run killed while writing leaves a run.json that says so and
        no file of another run. Each file is replaced whole (``legdsl.files``)."""
        out = Path(out)
        info = self.info() | recorded_folder(self.generated, out)  # from where it is written
        text = json.dumps(info, indent=2, allow_nan=False) + "\n"
        pending = dict(info, status="incomplete", message="the run directory is being written")
        out.mkdir(parents=True, exist_ok=True)
        with writing_alone(out):
            held_a_run = any((out / name).exists() for name in RUN_FILES)  # else: the user's
            for name in DERIVED_FILES if held_a_run else ():  # drawn from the run before
                if (out / name).is_file():
                    remove(out / name)
            write_atomic(out / "run.json", json.dumps(pending, indent=2, allow_nan=False) + "\n")
            for name in (n for n in RUN_FILES[1:] if (out / n).is_file()):  # an older run's
                remove(out / name)
            self.result.trajectory.save(out)
            write_atomic(out / "run.json", text)
        return out

    def summary(self) -> str:
        """The table ``legdsl run`` prints, with the path rows of each path followed."""
        parts = [summary(self.model, self.result), *map(path_summary, self.path_reports)]
        return "\n".join(parts)
