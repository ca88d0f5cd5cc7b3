"""A run's terms and bookkeeping: the options it is asked with (``RunOptions``), how far its
loop got (``RunLoop``, with the recording it grows as it goes), what ends it early from outside
(``Interrupted``), what ends it from inside (``ControlFault``) and what it gives back (``RunResult``). ``legdsl.sim.simulate`` runs it."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Literal

from legdsl.lang.errors import Span
from legdsl.sim.recorder import recording_budget
from legdsl.sim.trajectory import Trajectory

CONTROL_DT = 0.002  # s: the control interval, "usually a few ms" (Figure 2)


def default_control_dt(dt: float) -> float:
    """The control interval when none is asked for: 2 ms, or the step where that is longer
    (the controller runs at most once a step; a shorter interval asked for is refused)."""
    return max(CONTROL_DT, dt)


FALL_OFF: Literal["off"] = "off"  # --fall-height off: the fall rule's height is turned off


@dataclass
class RunOptions:
    duration: float = 5.0
    dt: float = 0.0004  # the paper's integration interval
    integrator: str = "euler"  # semi-implicit Euler, or "rk4"
    control_dt: float = CONTROL_DT  # with another dt: default_control_dt(dt)
    record_rate: float = 200.0  # samples per second; 0 records every step
    # root below this is a fall; None: 30% of its height over its feet; FALL_OFF ("off"):
    # no height is a fall (a creature that crawls or lies on the ground)
    fall_height: float | Literal["off"] | None = None
    fall_tilt: float = math.radians(60.0)  # root tilted beyond this is a fall (pi: none is)
    drop: float | None = None  # start with the lowest contact this high above the ground


def steps_per_control(options: RunOptions) -> int:
    """The controller runs every this many steps: its interval over the step, rounded to the
    nearest whole number, at least one (1.1 ms at 0.4 ms: every 3 steps, 1.2 ms)."""
    return max(1, int(round(options.control_dt / options.dt)))


def last_tick(options: RunOptions) -> float:
    """When the controller runs for the last time (s): at the last multiple of its interval
    before the run's last step ends it; an input changed after it never acts."""
    steps, every = int(round(options.duration / options.dt)), steps_per_control(options)
    return max(0, steps - 1) // every * every * options.dt


def intervals_as_run(options: RunOptions) -> dict[str, float]:
    """run.json's record and control intervals: the options' rounded to whole steps."""
    return {
        "record_interval": round(steps_per_sample(options) * options.dt, 12),
        "control_interval": round(steps_per_control(options) * options.dt, 12),
    }


def steps_per_sample(options: RunOptions) -> int:
    """Samples are taken every this many steps: one fixed interval, the record rate's
    rounded up to a whole number of steps (at 200 Hz and 0.4 ms, 12.5 steps: every 13, 5.2 ms),
    so never more often than asked. An interval within 0.1% of a step of a whole number is
    that number (a rate and step printed to six digits, as a scaled file does, agree with
    the exact ones). A record rate of 0 records every step."""
    if options.record_rate <= 0:
        return 1
    return max(1, math.ceil(1.0 / (options.record_rate * options.dt) - 1e-3))


CHECK_INTERVAL = 0.002  # s: the fall and divergence rules are looked at at least this often


def steps_per_check(
    options: RunOptions, control_every: int, interval: float = CHECK_INTERVAL
) -> int:
    """The fall and divergence rules are looked at at every control tick, but at least every
    ``interval`` (a run's last step is looked at too): with a longer control interval,
    or one longer than the run, a creature lay fallen below the ground with status ok."""
    most = max(1, int(round(interval / options.dt)))
    return min(control_every, most)


def run_samples(options: RunOptions) -> int:
    """The most samples a run of these options records (its recording's full length)."""
    return int(round(options.duration / options.dt)) // steps_per_sample(options) + 1


@dataclass
class RunResult:
    trajectory: Trajectory
    events: list[dict[str, Any]]
    status: str  # ok | diverged | fell | interrupted
    message: str
    steps: int
    wall_time: float
    sim_time: float
    cause: str = ""  # why a run ended early: a signal, the fall, the divergence
    stop_time: dict[str, float] = field(default_factory=dict)  # s on each joint stop
    # where an energy rise without a source ended, for a run told diverged after it ran on
    diverged_at: float | None = None
    # the .leg statement of a control law that failed (its line is shown with a caret)
    fault_span: Span | None = None

    @property
    def real_time_factor(self) -> float:
        return self.sim_time / self.wall_time if self.wall_time > 0 else math.inf


class Interrupted(BaseException):
    """A signal that ends a run early, as Ctrl-C does (the CLI raises it on SIGTERM): the run
    stops, keeps what it recorded and reports ``interrupted``."""

    def __init__(self, signal: str):
        super().__init__(signal)
        self.signal = signal


def signal_of(stop: BaseException) -> str:
    """The signal a run's ``KeyboardInterrupt`` or ``Interrupted`` stands for."""
    return stop.signal if isinstance(stop, Interrupted) else "SIGINT (Ctrl-C)"


class ControlFault(Exception):
    """A control law that failed at run time; the message says where and why
    (``legdsl.sim.control_faults`` makes it), ``span`` is the law's in the ``.leg`` file."""

    def __init__(self, message: str, span: Span | None = None):
        super().__init__(message)
        self.span = span

    def __reduce__(self) -> tuple[type[ControlFault], tuple[str, Span | None]]:
        return (ControlFault, (str(self), self.span))


INITIAL_ROWS = 1024  # samples the recorder holds before it first grows


def grow_recording(loop: RunLoop) -> None:
    """Double the recording (to the run's samples at most), unless the old arrays and the new
    ones together (while it is copied) would take more than ``recording_budget``, or the
    system refuses the memory: then the run stops, keeping what it recorded, where the system
    would have killed it later with nothing written (``--time 1e9`` runs until stopped). The
    rest of the memory is left to the writing of the run directory, and to what else runs."""
    rows = min(loop.capacity, 2 * len(loop.traj))
    budget = recording_budget()
    size = f"{budget / 2**30:.3g} GiB; " if budget is not None else ""
    full = f"its recording filling half of the memory the run may take ({size}a lower "
    full += "--record-rate runs longer)"
    if budget is not None and (len(loop.traj) + rows) * loop.traj.row_bytes() > budget:
        raise Interrupted(full)
    try:
        loop.traj = loop.traj.grown(rows)
    except MemoryError:  # the system refused even that: what was recorded is kept
        raise Interrupted(full) from None


@dataclass
class RunLoop:
    """How far a run's loop got: what ``Simulation.run`` reports once it stops."""

    n_steps: int
    record_every: int  # steps per sample (steps_per_sample)
    capacity: int  # most samples the run records
    traj: Trajectory  # the recording, grown as it fills
    control_every: int  # steps per control interval
    check_every: int  # steps between looks at the fall and divergence rules (steps_per_check)
    start_height: float  # the root over its feet at the start (the fall rule)
    recorded: int = 0
    steps: int = 0  # the loop's step index when it stopped
    status: str = "ok"
