"""Many copies of one run, each with its own values and start, run in C in one call per thread.

    batch = Batch(session, 256, "hop", settings=["speed=2m/s"],
                  vary={"speed": (np.linspace(2, 5, 256), "m/s")},
                  options=RunOptions(duration=0.5))
    copies = batch.run(threads=2)           # default: one thread per core
    copies.status, copies.sim_time          # arrays over the copies
    copies.trajectory(k), copies.run(k)     # copy k as a single run would give it

One run is set up as ``RunSession.prepare`` sets it up (the template) and the copies' values
and starts are checked (``legdsl.pipeline.batch_setup``). Each array of its C struct is then laid out once per copy, in one block (a structure of arrays: copy k's array in
row k), the template's values in every row, and each copy's own values written into its rows
with numpy: the inputs, parameters and actuator settings named in ``vary`` (an array of
values and their unit, checked as ``--set`` checks one value) and the start (``q0``, ``v0``).
``runtime/batch.c`` runs the copies, each from start to end exactly as a single run, in
``threads`` threads that share them; Python is entered once per thread, not once per copy.
All samples land in one trajectory of ``n * capacity`` rows (copy k's from row
``k * capacity``); a copy's ``RunResult`` and ``Run`` are made only when asked for
(``Copies``).

A copy that needs Python on the way (a controller with no C twin, a tick the C state machine
hands over, more contact events than its buffer holds) stops in C and is run again through
``RunSession.prepare`` with its own values, on the C backend with Python's help, after the
others (``Copies.rerun`` counts them). Ctrl-C stops the copies where they are: each keeps
what it recorded and says ``interrupted`` (a Ctrl-C in a copy's run again leaves the copies
after it where C left them, interrupted too).
"""

from __future__ import annotations

import ctypes
import math
import os
import threading
import time
from collections.abc import Callable
from copy import copy
from threading import Event
from typing import Any

import numpy as np

from legdsl.pipeline.batch_memory import check_copies_memory, lined_up
from legdsl.pipeline.batch_setup import BatchSetup
from legdsl.pipeline.session import Plan, Run
from legdsl.signals import signals_held
from legdsl.sim.c_backend import (
    CHECK,
    CONTROL,
    DONE,
    ERRORS,
    FULL,
    NONFINITE,
    RAISED,
    STEP_BUDGET,
    YIELD,
    CSimulation,
)
from legdsl.sim.c_library import address
from legdsl.sim.c_machine import pull_machine, state_events
from legdsl.sim.energy_check import held_in_copies, told, unexplained_rise
from legdsl.sim.machine import StateMachine
from legdsl.sim.recorder import Divergence, empty_trajectory
from legdsl.sim.run_loop import Interrupted, RunLoop, RunResult, signal_of
from legdsl.sim.trajectory import ARRAYS, Trajectory

Progress = Callable[[int, int, float], None]  # (copies done, copies, seconds left)

EVENTS_PER_SECOND = 200  # contact events a copy's buffer holds per contact per second of run
ACTUATOR_ARRAYS = ("gain", "damping", "target", "force", "last")  # act_gain, ... of leg_sim


class Batch(BatchSetup):
    """``n`` copies of one run (see the module docstring), run."""

    def run(self, threads: int | None = None, progress: Progress | None = None) -> Copies:
        """Run every copy, ``threads`` at once (default: one per core); ``progress`` is called
        about every 0.2 s. At Ctrl-C (or SIGTERM) the copies stop at their next 20000 steps
        and none starts after: the copies say how they ended, as single runs do."""
        sim, lib, n = self.sim, self.sim.library, self.n
        loop = sim.new_loop(rows=1 << 62)  # the recording holds the whole run
        blocks, table, traj = self._lay_out(loop)
        structs = lined_up(n, ctypes.sizeof(lib.Sim), np.uint8)
        codes = np.full(n, -1, dtype=np.int64)
        taken, stop = np.zeros(1, dtype=np.int64), np.zeros(1, dtype=np.int64)
        args = (ctypes.byref(sim.c), address(table), len(table), structs.ctypes.data,
                structs.strides[0], address(codes), n, address(taken), address(stop))  # fmt: skip
        start, interrupted = time.perf_counter(), ""
        # each thread says when its C call has returned: Python 3.11's Thread.join, cut short
        # by a Ctrl-C, marks a thread still running as ended, and the joins after it returned
        # at once while C ran on, writing the copies' memory as it was read (a copy said 32 s
        # and 80000 steps, its samples stopping at 24.86 s)
        ended = [Event() for _ in range(max(1, threads or os.cpu_count() or 1))]
        workers = [threading.Thread(target=_run_copies, args=(lib.lib.leg_run_copies, args, e))
                   for e in ended]  # fmt: skip
        try:
            with signals_held():  # every thread started and known, or none
                for w in workers:
                    w.start()
            while not all(e.is_set() for e in ended):
                next(e for e in ended if not e.is_set()).wait(0.2)
                if progress is not None:
                    done = int(np.count_nonzero(codes >= 0))
                    spent = time.perf_counter() - start
                    progress(done, n, spent / done * (n - done) if done else math.nan)
        except (KeyboardInterrupt, Interrupted) as sig:  # the copies stop; what ran is kept
            interrupted = signal_of(sig)
        finally:
            # Whatever ends this (Ctrl-C, a progress callback's error), the C threads stop and
            # are joined before the arrays they write can go: a Ctrl-C among the starts, past
            # this, left them running on freed memory (a segfault; random API interrupts, seed
            # 20013). Held, so that a second Ctrl-C cannot cut the joins short.
            stop[0] = 1  # read by C between budgets; the copies already done are unaffected
            try:
                with signals_held():
                    for w, e in zip(workers, ended, strict=True):
                        if w.ident is not None:  # started
                            e.wait()
                            w.join()
            except (KeyboardInterrupt, Interrupted) as sig:  # held until joined, then raised:
                interrupted = interrupted or signal_of(sig)  # the copies came back all the same
        wall = time.perf_counter() - start
        return Copies(self, loop.capacity, traj, blocks, structs, codes, wall, interrupted)

    def _lay_out(self, loop: RunLoop) -> tuple[dict[str, np.ndarray], np.ndarray, Trajectory]:
        """The template's struct set up for ``loop``, each of its arrays laid out once per
        copy with the copy's own values in (by field), the table of fields ``leg_run_copies``
        moves per copy, and the recording of every copy."""
        sim, lib, n = self.sim, self.sim.library, self.n
        arrays = sim.lay_out(loop)
        ticks = loop.n_steps // loop.control_every + 16  # a tick enters one state at most
        seconds = loop.n_steps * sim.options.dt
        events = max(16, int(EVENTS_PER_SECOND * seconds) + 16) * max(1, len(sim.contact_names))
        sim.c.step_budget, sim.c.event_cap = STEP_BUDGET, events  # C looks at `stop` between
        sizes = {"event_t": events, "event_kind": events, "event_contact": events,
                 "ctl_event_t": ticks, "ctl_event_state": ticks}  # fmt: skip
        laid = {name: (sizes.get(name, arrays[name].size), arrays[name].dtype)
                for name in lib.pointee  # not rec_, nor a field this run lacks (no controller)
                if not name.startswith("rec_") and name in arrays}  # fmt: skip
        check_copies_memory(self.session.model, sim.options, n, laid, ctypes.sizeof(lib.Sim))
        blocks: dict[str, np.ndarray] = {}
        for name, (size, dtype) in laid.items():
            own = arrays[name]
            blocks[name] = lined_up(n, size, dtype)
            blocks[name][:, : min(size, own.size)] = own[:size]
        self._write_values(blocks)
        traj = empty_trajectory(sim, n * loop.capacity)
        fields = [self._field(name, block, block.strides[0]) for name, block in blocks.items()]
        for name in ARRAYS:
            array = getattr(traj, name)
            fields.append(self._field(f"rec_{name}", array, array.strides[0] * loop.capacity))
        heights = self.start_heights
        fields.append([lib.Sim.start_height.offset, heights.strides[0], 0, address(heights)])
        return blocks, np.array(fields, dtype=np.int64), traj

    def _field(self, name: str, array: np.ndarray, stride: int) -> list[int]:
        lib = self.sim.library
        if array.dtype.type is not lib.pointee[name]:
            raise TypeError(f"leg_sim.{name} points to {lib.pointee[name]}, not {array.dtype}")
        return [getattr(lib.Sim, name).offset, stride, 1, array.ctypes.data]

    def _write_values(self, blocks: dict[str, np.ndarray]) -> None:
        """Each copy's own values into its rows of the struct's arrays."""
        sim, m = self.sim, self.sim.machine_in_c
        blocks["q"][:, : self.q0.shape[1]] = self.q0
        blocks["v"][:, : self.v0.shape[1]] = self.v0
        for name, values in self.vary.items():
            if "." in name:
                actuator, _, key = name.partition(".")
                k = [a.name for a in sim.actuators.states].index(actuator)
                blocks[_actuator_array(sim.actuators.states[k], key)][:, k] = values
            elif m is None:
                continue  # the machine runs in Python: every copy runs again there
            elif name in m.input_names:
                blocks["ctl_inputs"][:, m.input_names.index(name)] = values
            else:
                blocks["ctl_params"][:, m.param_names.index(name)] = values


def _run_copies(run: Any, args: tuple[Any, ...], ended: Event) -> None:
    """A batch thread's C call (``leg_run_copies``), ``ended`` set when it returns."""
    try:
        run(*args)
    finally:
        ended.set()


def _actuator_array(state: Any, key: str) -> str:
    """The struct's array that ``ActuatorState.set(key, ...)`` changes (act_gain, ...)."""
    probe = copy(state)
    probe.set(key, math.nan)
    changed = [f for f in ("gain", "damping", "target", "force") if math.isnan(getattr(probe, f))]
    return f"act_{changed[0]}"


class Copies:
    """A batch's copies after their run: arrays over the copies, and each copy's run."""

    def __init__(self, batch: Batch, capacity: int, traj: Trajectory,
                 blocks: dict[str, np.ndarray], memory: np.ndarray, codes: np.ndarray,
                 wall: float, interrupted: str = ""):  # fmt: skip
        """``memory``: the copies' structs, one a row (``lined_up``); ``interrupted``: the
        signal that stopped the batch, if one did."""
        self.batch, self.capacity, self.traj, self.blocks = batch, capacity, traj, blocks
        self._memory, self.codes, self.wall_time = memory, codes, wall
        self.interrupted = interrupted
        n, sim_type = batch.n, batch.sim.library.Sim
        self.structs = structs = [sim_type.from_address(memory.ctypes.data + k * memory.strides[0])
                                  for k in range(n)]  # fmt: skip
        self.steps = np.array([s.steps for s in structs], dtype=np.int64)
        self.sim_time = np.array([s.t for s in structs])
        self.recorded = np.array([s.recorded for s in structs], dtype=np.int64)
        self._results: dict[int, RunResult] = {}
        self._reruns: dict[int, Run] = {}
        needs_python = np.isin(codes, [CONTROL, FULL, YIELD]) & (not interrupted)
        self.rerun = int(np.count_nonzero(needs_python))
        for index in np.flatnonzero(needs_python):
            k = int(index)
            try:
                done = self._reruns[k] = self._run_in_python(k)
            except (KeyboardInterrupt, Interrupted) as sig:  # in its setup: as in a run
                self.interrupted = signal_of(sig)
                break
            self.steps[k], self.sim_time[k] = done.result.steps, done.result.sim_time
            self.recorded[k] = len(done.result.trajectory)
            if done.status == "interrupted":  # a Ctrl-C: the copies left stay where C left them
                self.interrupted = done.result.cause
                break
        status, held = np.full(n, "ok", dtype=object), held_in_copies(self.batch.sim, self.blocks)
        for k in range(n):
            if k in self._reruns:
                status[k] = self._reruns[k].status
            elif codes[k] != DONE or unexplained_rise(self.trajectory(k), held[k]) is not None:
                status[k] = self.result(k).status  # one that ran to its end may have diverged
        self.status = status.astype(str)

    def __len__(self) -> int:
        return self.batch.n

    def index(self, k: object) -> int:
        """Copy ``k``'s place, 0 to n - 1 (a negative ``k`` counts from the end, as in a list):
        a copy's rows are found from it, so any other number would read another copy's."""
        n = self.batch.n
        if isinstance(k, bool) or not isinstance(k, int | np.integer):
            raise TypeError(f"copy {k!r}: a copy is found by its index, a whole number")
        if not -n <= k < n:
            raise IndexError(f"copy {k}: the batch has {n} copies (0 to {n - 1})")
        return int(k) % n

    def trajectory(self, k: int) -> Trajectory:
        """Copy ``k``'s samples (views into the batch's arrays)."""
        k = self.index(k)
        if k in self._reruns:
            return self._reruns[k].result.trajectory
        start = k * self.capacity
        return self.traj.rows(start, start + int(self.recorded[k]))

    def result(self, k: int) -> RunResult:
        """Copy ``k``'s ``RunResult``, as ``Simulation.run`` gives a single run's."""
        k = self.index(k)
        if k in self._reruns:
            return self._reruns[k].result
        if k not in self._results:
            self._results[k] = self._result(k)
        return self._results[k]

    def run(self, k: int) -> Run:
        """Copy ``k`` as ``RunSession.run`` gives a single run (its settings and machine)."""
        k = self.index(k)
        if k in self._reruns:
            return self._reruns[k]
        b = self.batch
        settings = b._sorted(b.texts(k))
        if b.controller is not None:
            settings.inputs, settings.params = settings.for_controller(
                b.session.model.controller(b.controller)
            )
        machine = None
        if b.plan.machine is not None:
            m = b.plan.machine
            assert isinstance(m, StateMachine)  # a batch does not switch controllers
            machine = StateMachine(b.session.model, m.module, settings.inputs, settings.params,
                                   settings.schedule, m.paths)  # fmt: skip
            if b.sim.machine_in_c is not None:  # as the copy's C machine left it
                rows = {name: block[k] for name, block in self.blocks.items()}
                pull_machine(machine, self.structs[k], rows, machine.schedule)
        done = b.plan.finish(self.result(k), settings, machine)
        done.start = b.start_of(k)
        return done

    # ------------------------------------------------------------ one copy
    def _state_events(self, k: int) -> list[dict[str, Any]]:
        m = self.batch.sim.machine_in_c
        if m is None:
            return []
        n = int(self.structs[k].n_ctl_events)
        times, states = self.blocks["ctl_event_t"][k, :n], self.blocks["ctl_event_state"][k, :n]
        return state_events(times, states, m.state_names)

    def _contact_events(self, k: int) -> list[dict[str, Any]]:
        names, n = self.batch.sim.contact_names, int(self.structs[k].n_events)
        rows = zip(self.blocks["event_t"][k, :n], self.blocks["event_kind"][k, :n],
                   self.blocks["event_contact"][k, :n], strict=True)  # fmt: skip
        return [{"t": round(float(t), 9), "kind": "touchdown" if kind == 1 else "liftoff",
                 "contact": names[int(i)]} for t, kind, i in rows]  # fmt: skip

    def _result(self, k: int) -> RunResult:
        sim = self.batch.sim
        start, saved = (sim.q, sim.v, sim.t), [copy(a) for a in sim.actuators.states]
        try:
            rows = [self.blocks[f"act_{f}"][k] for f in ACTUATOR_ARRAYS]
            for i, a in enumerate(sim.actuators.states):  # as the copy's controller left them
                a.gain, a.damping, a.target, a.force, a.last_force = (float(r[i]) for r in rows)
            return self._result_at_end(k)  # its message names a setting too stiff, as alone
        finally:  # the template as it starts: a batch run again starts from it
            sim.move_to(*start)
            for a, old in zip(sim.actuators.states, saved, strict=True):
                a.__dict__.update(old.__dict__)

    def _result_at_end(self, k: int) -> RunResult:  # the template moved to copy k's end
        sim, s, code = self.batch.sim, self.structs[k], int(self.codes[k])
        model = sim.model
        q, v = self.blocks["q"][k, : model.nq], self.blocks["v"][k, : model.nv]
        sim.move_to(q.tolist(), v.tolist(), float(s.t))
        trajectory = self.trajectory(k)
        status, cause, sim.message = "ok", "", ""
        try:
            if self.interrupted and code not in (DONE, CHECK, NONFINITE, RAISED):
                status, cause = "interrupted", self.interrupted  # as Simulation.run says it
                sim.message = (
                    f"interrupted by {cause} at t = {sim.t:.4f} s of {sim.options.duration:g} "
                    "s; what was recorded up to then is kept"
                )
            elif code == CHECK:
                status = sim.fall_check(float(self.batch.start_heights[k])) or "ok"
                if status == "ok":
                    raise RuntimeError("C and Python disagree on the fall check (a legdsl bug)")
                cause = sim.message
            elif code == NONFINITE:
                raise Divergence("the state is no longer finite (NaN or infinity)")
            elif code == RAISED:
                raise ERRORS[int(s.err)]()
        except (Divergence, OverflowError, ZeroDivisionError, ValueError) as err:
            status, cause = "diverged", sim.diverged(err, trajectory)
        events = sorted(self._contact_events(k) + self._state_events(k), key=lambda e: e["t"])
        stops = self.blocks["stop_time"][k]
        result = RunResult(
            trajectory=trajectory,
            events=events,
            status=status,
            message=sim.message,
            steps=int(s.steps),
            wall_time=self.wall_time / len(self),
            sim_time=float(s.t),
            cause=cause,
            stop_time={dof: round(float(stops[i]), 9) for i, dof in enumerate(sim.stop_dofs)},
        )
        return told(sim, result)  # an energy rise without a source: as a single run tells it

    def _run_in_python(self, k: int) -> Run:
        """Copy ``k`` run as a single run (it needed Python on the way)."""
        b = self.batch
        plan: Plan = b.session.prepare(b.controller, b.texts(k), b.paths, b.options, backend="c")
        assert isinstance(plan.sim, CSimulation)  # as the template's
        plan.sim.move_to(b.q0[k].tolist(), b.v0[k].tolist())
        done = plan.finish(plan.sim.run())
        done.start = b.start_of(k)
        return done
