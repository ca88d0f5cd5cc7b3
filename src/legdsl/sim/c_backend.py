"""The C backend: the same simulation as ``legdsl.sim.simulate``, its steps taken in C.

``CSimulation`` is a ``Simulation`` whose run loop (``_loop``) hands the steps, the recording,
the checks and the controller's state machine to the creature's shared library
(``legdsl.codegen.c.build``: the generated ``dynamics.c`` and ``control_CONTROLLER.c`` with the
runtime ``step.c`` and ``machine.c``). C advances many steps per call and writes the recorded
samples straight into the trajectory's numpy arrays; it returns to Python only

* when the recording arrays are full (they grow as on the Python backend);
* every ``STEP_BUDGET`` steps, so that Ctrl-C and the progress line are served;
* for a control tick the C state machine hands over (where Python would raise or fault, for
  a controller with no C twin, ``leg_has_c_controller`` 0, or for a switching run's own
  business, ``SwitchingMachine.own_ticks``): the state is copied into this object and into
  the Python ``StateMachine``, which takes the tick, and back. A switching run has a library
  per controller, all of one struct layout: once Python has switched, the new controller's
  machine goes on in its library's C;
* when the run stops: at its end, at a fall or divergence (found in C by the rules of
  ``Simulation._check``, whose message Python then writes by running that same check), or
  where Python would have raised (``legdsl_math.h``'s error codes become the same exceptions).

So every status, message, event and recorded array is the Python backend's
(tests/sim/test_c_backend.py compares them bit for bit).
"""

from __future__ import annotations

import ctypes
import math
import sys
import time
from collections.abc import Callable, Mapping
from types import ModuleType
from typing import Any

import numpy as np

from legdsl.ir.model import Model, Pad
from legdsl.sim.c_library import CLibrary, address, available, load_library
from legdsl.sim.c_machine import pull_machine, push_machine
from legdsl.sim.c_mirrors import machine_matches
from legdsl.sim.contact import ContactEvent
from legdsl.sim.machine import StateMachine
from legdsl.sim.recorder import Divergence
from legdsl.sim.run_loop import RunLoop, RunOptions, grow_recording
from legdsl.sim.simulate import Controller, Simulation
from legdsl.sim.switching import SwitchingMachine
from legdsl.sim.trajectory import ARRAYS

__all__ = ["CLibrary", "CSimulation", "available", "load_library", "python_version_note"]

STEP_BUDGET = 20000  # steps per call at most (about 10 ms of C)
EVENT_CAP = 512  # contact events C keeps before Python drains them (LEG_YIELD)

DONE, CONTROL, FULL, YIELD, CHECK, NONFINITE, RAISED, STOPPED = range(8)  # legdsl_sim.h's

# legdsl_math.h's error codes as the exceptions Python raises there
ERRORS: dict[int, Callable[[], BaseException]] = {
    1: lambda: ValueError("math domain error"),
    2: lambda: ZeroDivisionError("float division by zero"),
    3: lambda: OverflowError("math range error"),
    4: lambda: ZeroDivisionError("0.0 cannot be raised to a negative power"),
    5: lambda: OverflowError(34, "Numerical result out of range"),
    6: lambda: TypeError("a negative number to a fractional power (complex in Python)"),
}

PROGRESS_EVERY = 0.2  # seconds of wall time between progress reports (as the Python loop's)


class CSimulation(Simulation):
    """A ``Simulation`` whose steps run in C (see the module docstring)."""

    def __init__(
        self,
        model: Model,
        dynamics: ModuleType,
        options: RunOptions,
        controller: Controller | None,
        libraries: Mapping[str | None, CLibrary],
    ):
        """``libraries``: the creature's library with each controller of the run (by name;
        None for a run without a controller)."""
        super().__init__(model, dynamics, options, controller)
        self.libraries = dict(libraries)
        self.library = next(iter(self.libraries.values()))
        self._running: StateMachine | None = None  # the machine C runs (_setup_machine)
        self._keep: dict[str, np.ndarray] = {}  # the arrays the struct points into
        self._pending: list[tuple[str, Any, list[Any], int]] = []  # arrays for _commit
        self.c = self.library.Sim()

    # ------------------------------------------------------------ the struct
    def _array(self, name: str, values: Any, dtype: Any = np.float64, size: int = 0) -> None:
        """An array of the struct, at least ``size`` long (and never empty), filled from
        ``values`` (numbers, or rows of them), zeros after; made and pointed to by ``_commit``."""
        if dtype is not self.library.pointee[name]:
            raise TypeError(f"leg_sim.{name} points to {self.library.pointee[name]}, not {dtype}")
        flat = list(values)
        if flat and isinstance(flat[0], list | tuple):
            flat = [x for row in flat for x in row]
        n = max(size, len(flat), 1)
        if flat:
            flat += [0] * (n - len(flat))
        self._pending.append((name, dtype, flat, n))

    def _commit(self) -> None:
        """The arrays of ``_array`` made as one block of each dtype, those with values first,
        and pointed to there: making some fifty small arrays one by one (and asking numpy for
        each one's address) took a third of a short run's setup."""
        by_type: dict[Any, list[tuple[str, list[Any], int]]] = {}
        for name, dtype, flat, n in self._pending:
            by_type.setdefault(dtype, []).append((name, flat, n))
        for dtype, arrays in by_type.items():
            arrays.sort(key=lambda a: not a[1])  # stable: the zero ones last
            values = [x for _, flat, _ in arrays for x in flat]
            block = np.zeros(sum(n for _, _, n in arrays), dtype=dtype)
            block[: len(values)] = values
            base, size, at = address(block), block.itemsize, 0
            for name, _, n in arrays:
                self._keep[name] = block[at : at + n]
                setattr(self.c, name, base + at * size)
                at += n
        self._pending = []

    def _point(self, name: str, array: np.ndarray) -> None:
        """The struct's pointer ``name`` at ``array`` (kept alive here), of the C type's dtype."""
        if array.dtype.type is not self.library.pointee[name]:
            raise TypeError(
                f"leg_sim.{name} points to {self.library.pointee[name]}, not {array.dtype}"
            )
        self._keep[name] = array
        setattr(self.c, name, address(array))

    def _setup(self, loop: RunLoop) -> None:
        c, m, opts = self.c, self.model, self.options
        c.dt, c.rk4, c.n_steps = opts.dt, int(opts.integrator == "rk4"), loop.n_steps
        c.control_every, c.has_controller = loop.control_every, int(self.controller is not None)
        c.check_every = loop.check_every
        c.record_every, c.capacity = loop.record_every, loop.capacity
        c.has_fall_height = int(opts.fall_height is not None)
        # --fall-height off (FALL_OFF): no height is below -infinity, as _check has no limit
        height = opts.fall_height
        c.fall_height = -math.inf if isinstance(height, str) else height or 0.0
        c.fall_tilt, c.start_height = opts.fall_tilt, loop.start_height
        c.size_scale, c.step_budget = self.size_scale, STEP_BUDGET
        self._array("v_factor", self.v_factors)
        c.steps, c.phase, c.steps_taken, c.t = 0, 0, self.steps_taken, self.t
        c.recorded = loop.recorded
        self._array("q", self.q)
        self._array("v", self.v)
        acts = self.actuators.states
        c.n_act = len(acts)
        self._array("act_is_force", [a.kind == "force" for a in acts], np.int64)
        self._array("act_qi", [a.q_index for a in acts], np.int64)
        self._array("act_vi", [a.v_index for a in acts], np.int64)
        self._array("act_has_limit", [a.limit is not None for a in acts], np.int64)
        self._array("act_limit", [a.limit or 0.0 for a in acts])
        self._array("act_gain", [a.gain for a in acts])
        self._array("act_damping", [a.damping for a in acts])
        self._array("act_target", [a.target for a in acts])
        self._array("act_force", [a.force for a in acts])
        self._array("act_last", [a.last_force for a in acts])
        self._array("act_work", self.actuators.positive_work + self.actuators.negative_work)
        stops = self._stops
        c.n_stops = len(stops)
        self._array("stop_qi", [st.q_index for st in stops], np.int64)
        self._array("stop_vi", [st.v_index for st in stops], np.int64)
        for name in ("low", "high", "k", "b"):
            self._array(f"stop_{name}", [getattr(st, name) for st in stops])
        self._array("stop_time", [self.stop_time[st.dof] for st in stops])
        self._setup_ground()
        nc = len(self.contact_names)
        c.n_events, c.event_cap = 0, EVENT_CAP
        self._array("event_t", [], size=EVENT_CAP)
        self._array("event_kind", [], np.int64, EVENT_CAP)
        self._array("event_contact", [], np.int64, EVENT_CAP)
        legs = m.legs
        c.n_legs = len(self._hips)
        self._array("leg_hip", [hip.body for hip in self._hips], np.int64)
        self._array("leg_hip_moved", [hip.at is not None for hip in self._hips], np.int64)
        self._array("leg_hip_at", [hip.at or (0.0, 0.0, 0.0) for hip in self._hips])
        self._array("leg_foot", self._foot, np.int64)
        # each leg's soles, a row of contact flags per leg (its clock: Sensors.leg_clocks)
        soles = [[c.name in leg.soles for c in m.contacts] for leg in legs]
        self._array("leg_soles", soles if legs else [], np.int64)
        mask = [[a.name in springs for a in acts] for springs in self._leg_springs]
        self._array("leg_spring", mask if legs else [], np.int64)
        self._sync_controller()
        self._point_recording(loop)
        c.kin_valid = 0
        self._array("kin", [], size=7 * nc)
        self._setup_machine(loop)
        self._commit()
        if c.c_control:
            self._push_machine()

    def _setup_ground(self) -> None:
        c, ground = self.c, self.ground
        nc = len(self.contact_names)
        self._array("contact_body", self._contact_body, np.int64)
        self._array("touching", ground.touching if ground else [], np.int64, nc)
        self._array("anchor", ground.anchor if ground else [], size=3 * nc)
        self._array("yaw_anchor", ground.yaw_anchor if ground else [], size=nc)
        self._array("slipping", ground.slipping if ground else [], np.int64, nc)
        self._array("contact_force", self.contact_force)
        if ground is None:
            c.has_ground = 0
            self._array("flat_is_box", [], np.int64)
            self._array("flats", [])
            return
        g = ground.ground
        c.has_ground = 1
        c.normal_pad = int(isinstance(g.normal, Pad))
        c.normal_k, c.normal_b = g.normal.k, g.normal.b
        c.pad_thickness = g.normal.thickness if isinstance(g.normal, Pad) else 0.0
        c.tangent_k, c.tangent_b = g.tangent.k, g.tangent.b
        c.has_friction = int(g.friction is not None)
        c.friction = g.friction if g.friction is not None else 0.0
        c.torsion = int(self._torsion)
        c.torsion_k = g.torsion.k if g.torsion is not None else 0.0
        c.torsion_b = g.torsion.b if g.torsion is not None else 0.0
        slope = ground._slope
        c.has_slope = int(slope is not None)
        c.slope_angle = slope.get("angle") if slope is not None else 0.0
        flats = ground._flats
        c.n_flats = len(flats)
        self._array("flat_is_box", [t.kind == "box" for t in flats], np.int64)
        rows = [
            [t.get("x"), 0.0, 0.0, 0.0, 0.0, t.get("height")]
            if t.kind == "step"
            else [0.0, t.get("x0"), t.get("x1"), t.get("y0"), t.get("y1"), t.get("height")]
            for t in flats
        ]
        self._array("flats", rows)

    def _point_recording(self, loop: RunLoop) -> None:
        traj = loop.traj
        self.c.rows = len(traj)
        for name in ARRAYS:
            self._point(f"rec_{name}", getattr(traj, name))

    def _machine(self) -> StateMachine | None:
        """The state machine that runs now: the run's, or a switching run's current one."""
        m = self.controller
        if isinstance(m, SwitchingMachine):
            return m.current
        return m if type(m) is StateMachine else None

    def _setup_machine(self, loop: RunLoop) -> None:
        """The state machine's arrays for C, when the library has the controller's (else
        c_control = 0); again after a switching run's Python tick has switched. ``_commit``
        makes them and ``_push_machine`` fills in the machine's state."""
        c, m, switching = self.c, self._machine(), self.controller
        if isinstance(switching, SwitchingMachine):
            self.library = self.libraries[switching.name]
        self._running = m
        use = m is not None and self.library.c_controller and machine_matches()
        c.c_control, c.state_offset = int(use), 0
        c.ctl_command_at = c.ctl_switch_at = c.ctl_switch_until = math.inf
        if not use:
            return
        assert m is not None
        if isinstance(switching, SwitchingMachine):
            c.state_offset = switching.state_offset
        mod, nc, ni = m.module, len(self.contact_names), len(m.inputs)
        self._schedule = list(m.schedule)
        self._array("ctl_records", m.records)
        self._array("ctl_inputs", m.inputs)
        self._array("ctl_integral", m.integral_state())
        self._array("ctl_params", m.params)
        c.sched_n = len(self._schedule)
        self._array("sched_t", [ch.t for ch in self._schedule])
        self._array(
            "sched_input", [m.input_names.index(ch.name) for ch in self._schedule], np.int64
        )
        self._array("sched_value", [ch.value for ch in self._schedule])
        self._array("hist_t", [], size=len(self._schedule) + 1)
        self._array("hist_inputs", [], size=(len(self._schedule) + 1) * ni)
        c.speed_input = m.input_names.index("speed") if "speed" in m.input_names else -1
        clocks = 5 * (nc + len(self.model.legs))  # the contacts' clocks, then the legs'
        self._array("clocks", [], size=clocks)
        # a tick enters at most one state, and Python drains them after every leg_run call
        ticks = min(STEP_BUDGET, loop.n_steps) // loop.control_every + 16
        self._array("ctl_event_t", [], size=ticks)
        self._array("ctl_event_state", [], np.int64, ticks)
        outputs = [
            len(targets) + sum(len(axes) for _, axes, _ in mod.PLACES.get(key, ()))
            for key, targets in mod.SETTINGS.items()
        ]
        most = max([len(mod.RECORDS), *outputs])
        size = len(mod.SENSORS) + 2 * most + len(mod.RECORDS) + 3 * ni + clocks
        self._array("ctl_work", [], size=size + 4 * len(self.actuators.states) + 16)
        self._setup_paths(m)

    def _setup_paths(self, m: StateMachine) -> None:
        """The paths' geometry (PathGeometry's vertices and arclengths) and trackers, for C."""
        data: list[float] = []
        at = []
        for tracker in m.sensors.paths.values():
            at.append(len(data))
            geo, spec = tracker.geometry, tracker.spec
            if geo is None or spec is None:
                data += [0.0] * 9
                continue
            shape = 1.0 if spec.shape == "circle" else 2.0
            data += [shape, float(geo.closed), *spec.center, spec.radius, float(spec.turn)]
            data += [spec.lookahead, geo.length, float(len(geo.vertices))]
            data += [c for v in geo.vertices for c in v] + list(geo.starts)
        self.c.n_paths = len(at)
        self._array("path_at", at, np.int64)
        self._array("path_data", data)
        self._array("path_state", [], size=12 * len(at))

    def _push_machine(self) -> None:
        assert self._running is not None
        if isinstance(self.controller, SwitchingMachine):
            ticks = self.controller.own_ticks(self.ground is not None)
            self.c.ctl_command_at, self.c.ctl_switch_at, self.c.ctl_switch_until = ticks
        push_machine(self._running, self.c, self._keep, self._schedule)

    def _pull_machine(self) -> None:
        assert self._running is not None
        pull_machine(self._running, self.c, self._keep, self._schedule)
        self.c.n_hist = self.c.n_ctl_events = 0  # drained: C gathers afresh

    # ------------------------------------------------------------ state between C and Python
    def _push_actuators(self) -> None:
        keep = self._keep
        for k, a in enumerate(self.actuators.states):
            keep["act_gain"][k], keep["act_damping"][k] = a.gain, a.damping
            keep["act_target"][k], keep["act_force"][k] = a.target, a.force

    def _sync_controller(self) -> None:
        controller = self.controller
        if controller is not None:
            self.c.state_index = controller.state_index
            self.c.speed_command = controller.speed_command(self.t)

    def _pull(self) -> None:
        """C's state into this object (what the controller, the checks and the result read)."""
        c, keep = self.c, self._keep
        nq, nv = self.library.nq, self.library.nv
        self.q = keep["q"][:nq].tolist()
        self.v = keep["v"][:nv].tolist()
        self.steps_taken, self.t = int(c.steps_taken), float(c.t)
        for k, a in enumerate(self.actuators.states):  # the C state machine may have set them
            a.last_force = float(keep["act_last"][k])
            a.gain, a.damping = float(keep["act_gain"][k]), float(keep["act_damping"][k])
            a.target, a.force = float(keep["act_target"][k]), float(keep["act_force"][k])
        work, n = keep["act_work"].tolist(), len(self.actuators.states)  # positive, negative
        self.actuators.positive_work, self.actuators.negative_work = work[:n], work[n : 2 * n]
        for k, st in enumerate(self._stops):
            self.stop_time[st.dof] = float(keep["stop_time"][k])
        nc = len(self.contact_names)
        if self.ground is not None:
            g = self.ground
            g.touching = [bool(x) for x in keep["touching"][:nc]]
            g.slipping = [bool(x) for x in keep["slipping"][:nc]]
            g.yaw_anchor = keep["yaw_anchor"][:nc].tolist()
            anchors = keep["anchor"][: 3 * nc].tolist()
            g.anchor = [tuple(anchors[3 * i : 3 * i + 3]) for i in range(nc)]
            forces = keep["contact_force"][: 3 * nc].tolist()
            self.contact_force = [tuple(forces[3 * i : 3 * i + 3]) for i in range(nc)]
        for n in range(int(c.n_events)):
            kind = "touchdown" if keep["event_kind"][n] == 1 else "liftoff"
            name = self.contact_names[int(keep["event_contact"][n])]
            self.events.append(ContactEvent(float(keep["event_t"][n]), kind, name))
        c.n_events = 0
        self._kinematics = None

    # ------------------------------------------------------------ for a batch of copies
    def lay_out(self, loop: RunLoop) -> dict[str, np.ndarray]:
        """The struct set up to start ``loop`` and the arrays it points to, by field
        (``legdsl.pipeline.batch`` lays them out once per copy)."""
        self._setup(loop)
        return dict(self._keep)

    @property
    def machine_in_c(self) -> StateMachine | None:
        """The state machine whose ticks C takes (None: none, or Python takes them)."""
        return self._running if self.c.c_control else None

    def move_to(self, q: list[float], v: list[float], t: float = 0.0) -> None:
        """This state (a batch's copy's), the kinematics found for the last one forgotten."""
        self.q, self.v, self.t, self._kinematics = q, v, t, None

    def fall_check(self, start_height: float) -> str | None:
        """``Simulation._check`` at the state now: None, or 'fell' (and the message); raises
        the divergence it finds."""
        return self._check(start_height)

    @property
    def stop_dofs(self) -> list[str]:
        """The coordinates with joint stops, in the order of the struct's stop arrays."""
        return [st.dof for st in self._stops]

    # ------------------------------------------------------------ the run
    def _begin(self) -> None:
        pass  # the ground's first update is C's, at the start of _loop

    def _end(self) -> None:
        if getattr(self, "_started", False):
            self._pull()
            if self.c.c_control:
                self._pull_machine()

    def _loop(self, loop: RunLoop, progress: Callable[[float, float], None] | None) -> None:
        try:
            self._run_c(loop, progress)
        except BaseException as stop:
            if getattr(self, "_started", False) and not isinstance(stop, _InternalRaise):
                # a signal lands between two C calls: the run stops where C is
                loop.steps, loop.recorded = int(self.c.steps), int(self.c.recorded)
                self._pull()
            raise

    def _run_c(self, loop: RunLoop, progress: Callable[[float, float], None] | None) -> None:
        c = self.c
        self._setup(loop)
        self._started = True
        pointer = ctypes.byref(c)
        if self.library.lib.leg_begin(pointer) == RAISED:
            self._pull()
            raise _InternalRaise(c.err)  # outside the run's handlers, as in Python
        last_report = time.perf_counter()
        while True:
            code = self.library.lib.leg_run(pointer)  # a switching run's current library
            loop.steps, loop.recorded = int(c.steps), c.recorded
            if c.c_control:
                self._pull_machine()  # its events, and its state for a tick Python takes
            if code == CONTROL:
                self._pull()
                assert self.controller is not None
                self.controller(self)  # the Python state machine: raises where C gave up
                self._push_actuators()
                self._sync_controller()
                if self._machine() is not self._running:  # a switching run switched
                    self._setup_machine(loop)
                    self._commit()
                if c.c_control:
                    self._push_machine()
                now = time.perf_counter()  # C gives way at every such tick: report here
                if progress is not None and now - last_report > PROGRESS_EVERY:
                    progress(self.t, self.options.duration)
                    last_report = now
            elif code == FULL:
                grow_recording(loop)
                self._point_recording(loop)
            elif code == YIELD:
                self._pull()
                if progress is not None:
                    progress(self.t, self.options.duration)
            elif code == DONE:
                return
            elif code == CHECK:
                self._pull()
                fell = self._check(loop.start_height)  # raises the divergence it found
                if not fell:
                    raise RuntimeError("C and Python disagree on the fall check (a legdsl bug)")
                loop.status = fell
                return
            elif code == NONFINITE:
                self._pull()
                raise Divergence("the state is no longer finite (NaN or infinity)")
            elif code == RAISED:
                self._pull()
                raise ERRORS[int(c.err)]()
            else:
                raise RuntimeError(f"leg_run returned {code}")


class _InternalRaise(RuntimeError):
    def __init__(self, code: int):
        super().__init__(f"the ground's first update raised: {ERRORS[code]()!r}")


def python_version_note() -> str | None:
    """The C runtime follows CPython 3.11's sum() and math.hypot; another Python may differ."""
    if sys.version_info[:2] != (3, 11):
        return (
            f"the C backend reproduces CPython 3.11's float sums; on Python "
            f"{sys.version_info.major}.{sys.version_info.minor} its runs may differ from the "
            "Python backend's in the last bits (tests/sim/test_c_backend.py checks)"
        )
    return None
