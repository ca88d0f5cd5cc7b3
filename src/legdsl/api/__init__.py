"""The public Python API: a creature loaded from its ``.leg`` file, run, measured and drawn.

    >>> import legdsl
    >>> roo = legdsl.load("creatures/kangaroo.leg")
    >>> run = roo.run(controller="hop", set={"speed": "3 m/s"}, time=2)
    >>> run["com.x"][-1] > 1.0                     # samples as named numpy arrays
    True
    >>> run.metrics(start=1).running_speed.mean    # doctest: +SKIP
    >>> run.save("runs/roo")                       # trajectory.npz, .csv, run.json

``legdsl.open_run(directory)`` reads a saved run back. A run shows its player inline in
Jupyter. docs/api.md has the whole tour; the command line is a thin layer over the same
run session (``legdsl.pipeline.session``).
"""

from __future__ import annotations

import html
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from legdsl.analysis.results import GaitMetrics
from legdsl.analysis.series_units import series_unit
from legdsl.api import notes, pickling
from legdsl.api.arguments import (
    a_generated,
    a_path,
    an_output,
    check_vary,
    thread_count,
    window_time,
)
from legdsl.api.measured import run_metrics
from legdsl.api.notes import LegdslWarning
from legdsl.api.quantity import Quantity
from legdsl.api.read_only import read_only, read_only_trajectory
from legdsl.api.run_options import many_plans, session_args
from legdsl.check.values import did_you_mean
from legdsl.export.motion import DEFAULT_FPS, motion_from, read_run
from legdsl.export.stances import recorded_every_step
from legdsl.files import write_atomic, writing_alone
from legdsl.ir.model import Model
from legdsl.lang.errors import UsageError
from legdsl.pipeline.generated import load_dynamics, recorded_candidates
from legdsl.pipeline.session import RunSession
from legdsl.signals import import_held
from legdsl.sim.trajectory import Trajectory

__all__ = ["Copies", "Creature", "LegdslWarning", "Quantity", "Run", "load", "open_run"]


@dataclass(frozen=True)
class ControllerInfo:
    """A controller's name, states, and its inputs and parameters with their defaults."""

    name: str
    states: tuple[str, ...]
    inputs: Mapping[str, Quantity]
    params: Mapping[str, Quantity]


class Creature:
    """A checked creature with its generated dynamics (compiled when missing or stale)."""

    def __init__(self, session: RunSession):
        self.session = session
        if session.log is None:  # its notes about a run: LegdslWarning (legdsl.api.notes)
            session.note = notes.warn

    @property
    def name(self) -> str:
        return self.session.model.name

    @property
    def model(self) -> Model:
        return self.session.model

    @property
    def controllers(self) -> dict[str, ControllerInfo]:
        out = {}
        for c in self.model.controllers:
            inputs = {k.name: Quantity(k.value, k.dim) for k in c.inputs}
            params = {k.name: Quantity(k.value, k.dim) for k in c.params}
            out[c.name] = ControllerInfo(c.name, c.state_names, inputs, params)
        return out

    def run(
        self,
        controller: str | None = notes.NOT_GIVEN,
        set: Mapping[str, str | float] | None = None,  # noqa: A002  (the CLI's --set)
        time: float | None = None,
        path: str | None = None,
        switch: Mapping[str, str] | None = None,
        scene: str | None = None,
        **options: Any,
    ) -> Run:
        """Simulate for ``time`` seconds (default 5, or the scene's). ``set`` maps inputs,
        parameters and actuator settings to values with units (``{"speed": "5 m/s",
        "speed@4s": "2 m/s"}``; a plain number for a dimensionless one), checked as ``legdsl
        run --set`` checks them. ``switch`` maps times to controllers (``{"6 s": "gallop"}``, as
        ``--switch 6s=gallop``); ``scene`` runs the file's scene of that name (``--scene``), with
        ``set`` and ``switch`` added to it. ``options`` are those of ``legdsl run`` (``dt``,
        ``integrator``, ``control_dt``, ``record_rate``, ``fall_height``, ``fall_tilt`` in
        radians, ``drop``). Without ``controller`` (nor ``scene``) the run is passive and says
        so in a ``LegdslWarning``; ``controller=None`` asks for a passive run, without it."""
        asked = controller is not notes.NOT_GIVEN
        plan = session_args(self.model, controller if asked else None, set, time, path, switch,
                            scene, **options)  # fmt: skip
        unreached = plan.pop("unreached")
        prepared = self.session.prepare(**plan)  # a refused run is told its mistake alone
        self._before({**plan, "unreached": unreached}, asked)
        done = prepared.finish(prepared.sim.run())
        done.scene = scene
        self._after(done)
        return self._wrap(done)

    def run_many(
        self, runs: Sequence[Mapping[str, Any]], threads: int | None = None
    ) -> Iterator[tuple[int, Run]]:
        """Many runs at once, each a dict of ``run``'s keyword arguments: (its index, its
        ``Run``) as each finishes. On the C backend they go on in ``threads`` parallel
        threads (default: one per core) through its batched entry point
        (``legdsl.pipeline.backend.iter_batch``), on the Python backend one after another.
        Every run's arguments are checked before any runs: a mistake is a ``UsageError``
        naming the run by its index (``run_many(): runs[2]: ...``)."""
        from legdsl.pipeline.backend import iter_batch

        if isinstance(runs, str | bytes | Mapping) or not isinstance(runs, Iterable):
            raise UsageError(f"run_many(): runs= is a list of run()'s keyword arguments, e.g. "
                             f"[{{'controller': 'hop', 'time': 2}}], not {runs!r}")  # fmt: skip
        runs = list(runs)
        for r in runs:
            if not isinstance(r, Mapping):
                raise UsageError(f"run_many(): each run is a dict of run()'s keyword arguments, "
                                 f"e.g. {{'controller': 'hop', 'time': 2}}, not {r!r}")  # fmt: skip
        plans = many_plans(self.session, runs)
        # a run's notes before it are told as it comes back: a run refused is told alone
        before = [plan.pop("unreached") for plan in plans]
        with notes.from_threads(self.session) as flush:
            for i, done in iter_batch(self.session, plans, thread_count(threads)):
                self._before({**plans[i], "unreached": before[i]}, "controller" in runs[i])
                flush()
                done.scene = runs[i].get("scene")  # run.json names it, as run()'s
                self._after(done)
                yield i, self._wrap(done)

    def run_copies(
        self,
        n: int,
        controller: str | None = notes.NOT_GIVEN,
        set: Mapping[str, str | float] | None = None,  # noqa: A002
        vary: Mapping[str, tuple[Sequence[float], str]] | None = None,
        time: float | None = None,
        q0: Any = None,
        v0: Any = None,
        threads: int | None = None,
        progress: Callable[[int, int, float], None] | None = None,
        **options: Any,
    ) -> Copies:
        """``n`` copies of one run (``run``'s ``controller``, ``set``, ``time`` and options),
        each with its own values of the inputs, parameters and actuator settings in ``vary``
        (a name and its ``n`` values with their unit: ``{"speed": (speeds, "m/s")}``) and its
        own start (``q0``, ``v0``: ``n`` rows of coordinates), run in C in ``threads`` threads
        at once (default: one per core; ``legdsl.pipeline.batch``); ``progress(done, n,
        seconds_left)`` is called about every 0.2 s. ``copies[k]`` is copy k's ``Run``; at
        Ctrl-C the copies stop and the ones cut short say ``interrupted``."""
        from legdsl.api.copies_words import check_copies, copies_words
        from legdsl.pipeline.batch import Batch

        asked = controller is not notes.NOT_GIVEN
        with copies_words(vary):  # a refusal in the words of set= and vary=, not --set's
            plan = session_args(self.model, controller if asked else None, set, time, **options)
            check_copies(plan, progress, vary)
            check_vary(set, vary or {}, plan["controller"])
            batch = Batch(self.session, n, plan["controller"], plan["settings"], vary, q0, v0,
                          plan["paths"], plan["options"])  # fmt: skip
        self._before(plan, asked)  # once nothing is refused: a refusal is told alone, as run()'s
        copies = batch.run(thread_count(threads), progress)
        notes.after_copies(self.session, copies)
        return Copies(self, copies)

    def _before(self, plan: dict[str, Any], passive_asked: bool) -> None:
        unreached = plan.pop("unreached")  # told here, and no argument of the run
        notes.before_run(self.session, plan, passive_asked, unreached)

    def _after(self, done: Any) -> None:
        self.session.tell_after(done)

    def _wrap(self, done: Any) -> Run:
        return Run(self.model, done.result.trajectory, done.info(), self.session.dynamics, done)

    def __reduce__(self) -> tuple[Any, ...]:  # pickle: the file, checked again on arrival
        return pickling.creature_again, pickling.creature_state(self.session)

    def __repr__(self) -> str:
        return f"<legdsl creature '{self.name}': {self.model.nv} DOF, controllers {list(self.controllers)}>"


class Copies:
    """A batch's copies (``Creature.run_copies``): ``status`` and ``sim_time`` over them, and
    each copy's ``Run`` by its index. Through pickle it goes as its runs, every copy's ``Run``
    made then: the batch's memory (``copies``, C structs that point into this process) cannot
    travel, and is None on arrival."""

    def __init__(self, creature: Creature, copies: Any):
        self._creature, self.copies = creature, copies
        self.status, self.sim_time = read_only(copies.status), read_only(copies.sim_time)
        self._runs: list[Run] | None = None  # a Copies that came through pickle: its runs

    def __len__(self) -> int:
        return len(self.copies) if self._runs is None else len(self._runs)

    def __getitem__(self, k: int) -> Run:
        if self._runs is not None:
            return self._runs[k]
        return self._creature._wrap(self.copies.run(k))

    def __reduce__(self) -> tuple[Any, ...]:
        runs = [self[k] for k in range(len(self))]
        return (_arrived_copies, (self._creature, runs, self.status, self.sim_time))

    def __repr__(self) -> str:
        counts = {s: int((self.status == s).sum()) for s in dict.fromkeys(self.status.tolist())}
        how = ", ".join(f"{s} {k}" for s, k in counts.items())
        return f"<legdsl copies of '{self._creature.name}': {len(self)} ({how})>"


def _arrived_copies(creature: Creature, runs: list[Run], status: Any, sim_time: Any) -> Copies:
    """A ``Copies`` as pickle brings it: its runs, with no batch behind them."""
    copies = Copies.__new__(Copies)
    copies._creature, copies.copies, copies._runs = creature, None, runs
    copies.status, copies.sim_time = read_only(status), read_only(sim_time)
    return copies


class Run:
    """A run: its samples as named arrays, its run.json, and what can be made of it."""

    def __init__(
        self,
        model: Model,
        trajectory: Trajectory,
        info: dict[str, Any],
        dynamics: Any,
        session_run: Any = None,
        directory: Path | None = None,
    ):
        self.model = model
        self.trajectory = read_only_trajectory(trajectory)  # as its samples: the run's own
        self.info = info
        self._dynamics = dynamics
        self._session_run = session_run
        self.directory = directory

    @property
    def status(self) -> str:
        """ok, fell, diverged or interrupted (run.json's word; interrupted: cut short by
        Ctrl-C, or a copy of ``run_copies`` stopped so)."""
        return str(self.info.get("status", "ok"))

    @property
    def samples(self) -> dict[str, np.ndarray]:
        """Every recorded series by name: ``t``, ``q.NAME``, ``v.NAME``, ``com.x``...,
        ``com_vel.x``..., ``root.x``..., ``root.roll``..., ``contact.NAME`` (1 touching),
        ``force.NAME.x``..., ``leg_length.LEG``, ``state`` (an index into ``state_names``),
        ``speed_command``, ``energy.kinetic``..., ``work_positive.ACTUATOR`` and
        ``work_negative.ACTUATOR`` (each actuator's work since the start) (SI units), read-only
        (``.copy()`` one to change it)."""
        tr = self.trajectory
        out: dict[str, np.ndarray] = {"t": tr.t}
        out |= {f"q.{n}": tr.q[:, i] for i, n in enumerate(tr.q_names)}
        out |= {f"v.{n}": tr.v[:, i] for i, n in enumerate(tr.v_names)}
        for k, axis in enumerate("xyz"):
            out[f"com.{axis}"] = tr.com[:, k]
            out[f"com_vel.{axis}"] = tr.com_vel[:, k]
            out[f"root.{axis}"] = tr.root_pos[:, k]
        for k, angle in enumerate(("roll", "pitch", "yaw")):
            out[f"root.{angle}"] = tr.root_rpy[:, k]
        for i, n in enumerate(tr.contact_names):
            out[f"contact.{n}"] = tr.contact[:, i]
            for k, axis in enumerate("xyz"):
                out[f"force.{n}.{axis}"] = tr.force[:, i, k]
        out |= {f"leg_length.{n}": tr.leg_length[:, i] for i, n in enumerate(tr.leg_names)}
        out |= {"state": tr.state, "speed_command": tr.speed_command}
        for name in ("kinetic", "potential", "elastic"):
            out[f"energy.{name}"] = getattr(tr, name)
        for i, n in enumerate(tr.actuator_names):
            out[f"work_positive.{n}"] = tr.work_positive[:, i]
            out[f"work_negative.{n}"] = tr.work_negative[:, i]
        return out  # views of read_only_trajectory's read-only arrays

    @property
    def state_names(self) -> tuple[str, ...]:
        return tuple(self.trajectory.state_names)

    def __getitem__(self, name: str) -> np.ndarray:
        samples = self.samples
        if not isinstance(name, str):  # did_you_mean would fail on it
            raise KeyError(f"no series {name!r}: a series is named by a text, e.g. run['com.x']")
        if name not in samples:
            raise KeyError(f"no series '{name}'{did_you_mean(name, samples)}")
        return samples[name]

    def unit(self, name: str) -> str:
        """The SI unit of series ``name``: 'rad' for a hinge's ``q.``, 'm/s' for ``com_vel.x``,
        '' for a pure number (a quaternion's component, ``contact.``, ``state``)."""
        self[name]  # a name that is no series: its KeyError, with the nearest name
        return series_unit(self.model, name) or ""

    def __len__(self) -> int:
        return len(self.trajectory)

    # without these two, Python tries run[0] for 'in', list() and dict(): "no series 0"
    def __contains__(self, name: object) -> bool:
        return isinstance(name, str) and name in self.samples

    def __iter__(self) -> Iterator[str]:  # over names, it would disagree with len(run)
        raise TypeError(
            "a Run is not iterated: its series are run.samples, a dict (for name in "
            "run.samples, dict(run.samples)); len(run) is its number of samples"
        )

    def to_pandas(self) -> Any:
        """The samples as a pandas DataFrame indexed by time (pandas must be installed)."""
        try:
            pd = import_held("pandas")
        except ImportError:
            raise UsageError("to_pandas() needs pandas: pip install pandas") from None
        samples = self.samples
        t = samples.pop("t")
        return pd.DataFrame(samples, index=pd.Index(t, name="t"))

    def metrics(
        self,
        start: float = 0.0,
        end: float | None = None,
        leg: str | None = None,
        groups: Mapping[str, Sequence[str]] | Sequence[str] = (),
        min_stance: float | str | None = None,
        friction_edge: float | str = "10 ms",
        joint: str | None = None,
        against: str | None = None,
    ) -> GaitMetrics:
        """The gait metrics of Table 2 (as ``legdsl metrics --from START --to END``);
        ``groups={"front": ["fl", "fr"]}`` (or ``["front=fl,fr"]``) measures legs together;
        ``min_stance="20 ms"`` as ``--min-stance`` (its ``scuff_note`` otherwise);
        ``friction_edge`` as ``--friction-edge``; ``joint="tail_base"`` a coordinate's
        magnitude per stride and ``against="hip"`` its correlation with another, as
        ``--joint`` and ``--against``. Its ``path_reports`` (and ``path_table()``, the
        command's "path following" rows) say how the run followed each path it was given, over
        the same window."""
        self._recorded("metrics()")
        metrics = run_metrics(self.model, self.trajectory, self.info, self._dynamics_module,
                              start, end, leg, groups, min_stance, friction_edge, joint, against)  # fmt: skip
        if note := metrics.ending_note("this run"):  # it fell, diverged or was interrupted
            notes.warn(note)
        return metrics

    def save(self, directory: str | Path) -> Path:
        """Write the run directory (trajectory.npz, trajectory.csv, run.json)."""
        from legdsl.pipeline.options import check_output_dir

        self._recorded("save()")  # every reader refuses a run directory without a sample
        out = check_output_dir(a_path("save()", directory), "save()")
        if self._session_run is not None:
            self._session_run.write(out)
        else:
            import json

            out.mkdir(parents=True, exist_ok=True)
            with writing_alone(out):
                self.trajectory.save(out)
                write_atomic(out / "run.json", json.dumps(self.info, indent=2) + "\n")
        self.directory = out
        return out

    def plot(self, path: str | Path | None = None, start: float = 0.0) -> Path:
        """Figure 6 of the paper for this run, drawn from what it holds, as a PNG, SVG or PDF
        as ``path``'s name says (a PNG in the run's directory by default: ``save``'s, else a
        temporary one holding its pictures only)."""
        from legdsl.api.drawing import draw_figure6, pictures_directory
        from legdsl.pipeline.outputs import PICTURES  # as legdsl plot -o

        self._recorded("plot()")
        t_from = window_time("start", start)
        out = None if path is None else an_output("plot()", path, PICTURES, "a PNG, SVG or PDF")
        out = out or pictures_directory(self) / "figure6.png"
        draw_figure6(self, out, t_from)
        return out

    def animate(self, path: str | Path | None = None, fps: float = 60.0) -> Path:
        """The self-contained HTML player of this run (in the run's directory by default),
        ``fps`` frames a second stored (a rate giving one frame of a run that moves is refused)."""
        from legdsl.api.drawing import pictures_directory
        from legdsl.export.animate import frame_rate
        from legdsl.export.player import write_player

        self._recorded("animate()")
        motion = self._motion(frame_rate(fps, "animate(): fps=") or DEFAULT_FPS)
        player = "the HTML player (a video: legdsl animate DIR --video FILE.mp4)"
        out = (
            an_output("animate()", path, (".html", ".htm"), player)
            if path is not None
            else pictures_directory(self) / "animation.html"
        )
        write_player(motion, out)
        if motion.note:  # a stance of few keyframes, as legdsl animate notes it
            notes.warn(motion.note.removeprefix("legdsl: note: "))
        return out

    def _repr_html_(self) -> str:
        """Jupyter shows the player inline (in an iframe, so its script runs on its own)."""
        from legdsl.export.player import player_html

        if not len(self):
            return f"<p>legdsl run of {html.escape(self.model.name)}: no samples</p>"
        try:
            page = player_html(self._motion())
        except UsageError as refused:  # a still picture of a run that moves: said, as animate()
            return (
                f"<p>legdsl run of {html.escape(self.model.name)}: {html.escape(str(refused))}</p>"
            )
        return (
            f'<iframe srcdoc="{html.escape(page, quote=True)}" width="100%" height="480" '
            'style="border:0"></iframe>'
        )

    def __repr__(self) -> str:
        t = self.trajectory.t
        end = f" to {float(t[-1]):.3f} s" if len(t) else ""  # a copy stopped before it started
        return f"<legdsl run of '{self.model.name}': {self.status}, {len(self)} samples{end}>"

    def __getstate__(self) -> dict[str, Any]:  # pickle: the module goes as its file
        return pickling.picklable(self.__dict__)

    def __setstate__(self, state: dict[str, Any]) -> None:  # its arrays arrive writeable
        self.__dict__.update(state, trajectory=read_only_trajectory(state["trajectory"]))

    def _recorded(self, call: str) -> None:
        """A run without a sample (a copy stopped before it started) has nothing to show."""
        if not len(self):
            raise UsageError(f"{call}: this run of '{self.model.name}' recorded no samples "
                             f"(it ended {self.status} before its first); run it again")  # fmt: skip

    def _dynamics_module(self) -> Any:
        if self._dynamics is None:  # came through pickle
            self._dynamics = pickling.dynamics_again(self.model, self.__dict__["_dynamics_file"])
        return self._dynamics

    def _motion(self, fps: float = DEFAULT_FPS) -> Any:
        return motion_from(
            self.model,
            self.trajectory,
            self._dynamics_module(),
            events=self.info.get("events"),
            status=self.status,
            message=str(self.info.get("message") or ""),
            fps=fps,
            flag="fps=",
            every_step=recorded_every_step(self.info.get("steps"), self.info.get("samples")),
        )


def load(
    path: str | Path, creature: str | None = None, generated: str | Path = "generated"
) -> Creature:
    """Check a ``.leg`` file and load its creature (the one named, if it has several),
    compiling its generated code into ``generated/`` when missing or stale."""
    if not isinstance(path, str | Path):
        raise UsageError(f"load(): give the path of a .leg file, not {path!r}")
    if creature is not None and not isinstance(creature, str):
        raise UsageError(
            f"load(): creature= is the name of a creature in the file, not {creature!r}"
        )
    return Creature(RunSession.from_file(path, creature, a_generated("load()", generated)))


def open_run(
    directory: str | Path, source: str | Path | None = None, generated: str | Path | None = None
) -> Run:
    """Read a run directory back (its run.json names the ``.leg`` file, or give ``source``);
    the creature's kinematics come from ``generated`` if given, else from the folder the run
    was made with, which run.json records, where it holds them (as ``legdsl metrics`` reads
    them), else from ``generated/``; compiled there when missing or stale (as ``load`` does)."""
    if not isinstance(directory, str | Path):
        raise UsageError(f"open_run(): give the path of a run directory, not {directory!r}")
    folder = a_generated("open_run()", generated) if generated is not None else None
    given = a_path("open_run()", source) if source is not None else None
    give = f"source=, as in open_run({str(directory)!r}, source='path/to/the.leg')"
    found = read_run(Path(directory), given, give)
    if folder is None:  # a run made with load(generated=...) left ./generated alone
        made = recorded_candidates(Path(directory), found.info)
        held = [g for g in made if (g / found.model.name / "dynamics.py").is_file()]
        folder = next(iter(held), Path("generated"))
    dynamics = load_dynamics(found.model, found.source, folder)
    return Run(found.model, found.trajectory, found.info, dynamics, directory=Path(directory))
