"""A batch's copies as asked, checked before any runs (``legdsl.pipeline.batch``): the run
set up once as ``RunSession.prepare`` sets it up (the template), and each copy's own values of
the inputs, parameters and actuator settings in ``vary`` and its own start (``q0``, ``v0``),
each checked as a single run's would be."""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from copy import copy

import numpy as np

from legdsl.lang.errors import UsageError
from legdsl.lang.units import UnitError, parse_unit, unknown_unit
from legdsl.pipeline.backend import CUnavailable
from legdsl.pipeline.batch_memory import check_recordings
from legdsl.pipeline.session import RunSession
from legdsl.pipeline.settings import Settings, sort_settings
from legdsl.pipeline.start_pose import check_fall_height, check_start
from legdsl.pipeline.suggested_values import setting_unit
from legdsl.sim.c_backend import CSimulation
from legdsl.sim.machine import overwritten
from legdsl.sim.run_loop import RunOptions
from legdsl.sim.sizes import too_fast

Values = tuple[Sequence[float] | np.ndarray, str]  # numbers and their unit ("m/s"; "" if none)


class BatchSetup:
    """``n`` copies of one run as asked, checked: the run set up once (the template), each
    copy's own values and start (``legdsl.pipeline.batch`` runs them)."""

    def __init__(
        self,
        session: RunSession,
        n: int,
        controller: str | None = None,
        settings: Sequence[str] = (),
        vary: Mapping[str, Values] | None = None,
        q0: np.ndarray | None = None,
        v0: np.ndarray | None = None,
        paths: Sequence[str] = (),
        options: RunOptions | None = None,
    ):
        if isinstance(n, bool) or not isinstance(n, int | np.integer):
            raise UsageError(f"a batch of {n!r} copies: give their number as a whole number")
        if n < 1:
            raise UsageError(f"a batch of {n} copies: give at least one")
        for name, given in (vary or {}).items():  # each a pair, or its values read wrongly
            if not isinstance(name, str) or any(c in name for c in "@= "):
                raise UsageError(
                    f"vary {name!r}: name an input, a parameter or an actuator setting "
                    "(ACTUATOR.KEY) alone; its values are each copy's from the start (a change "
                    "during the run is a set= 'NAME@T', the same for every copy)"
                )
            if not (isinstance(given, tuple | list) and len(given) == 2
                    and isinstance(given[1], str)):  # fmt: skip
                own = setting_unit(session.model, controller, name)
                raise UsageError(
                    f"vary {name}: give its {n} values and their unit as a pair, e.g. "
                    f"{{{name!r}: (values, {'m/s' if own is None else own!r})}}"
                    + (" ('' for a number without one)" if own is None else "")
                )
        self.session, self.n = session, n
        self.controller, self.settings, self.paths = controller, list(settings), list(paths)
        self.options = options or RunOptions()
        try:
            self.plan = session.prepare(controller, settings, paths, self.options, backend="c")
        except CUnavailable as no_c:  # said as the API's run_copies() can act on it
            raise UsageError(f"run_copies() runs in C: {no_c.why}; {no_c.fix}or run them with "
                             "run_many()") from None  # fmt: skip
        if not isinstance(self.plan.sim, CSimulation):
            raise UsageError(
                "a batch runs on the C backend, and this run would go on the Python backend: "
                "the C runtime mirrors an older Python runtime (legdsl/sim/c_mirrors.py)"
            )
        self.sim: CSimulation = self.plan.sim
        check_recordings(session.model, self.sim.options, n)
        self._given: dict[str, tuple[np.ndarray, str]] = {}
        self.vary = {name: self._values(name, *given) for name, given in (vary or {}).items()}
        model = session.model
        self.q0 = self._start(q0, "q0", model.nq)
        self.v0 = self._start(v0, "v0", model.nv)
        self.start_heights = self._start_heights()
        self._check_speeds()
        self._check_stiffness()
        self._note_overwritten()  # once nothing is refused: a refusal is told alone

    # ------------------------------------------------------------ the copies' values
    def _values(self, name: str, numbers: Sequence[float] | np.ndarray, unit: str) -> np.ndarray:
        """The copies' values of ``name`` in SI, checked as ``--set name=VALUE`` is (with the
        smallest and the largest value: a check of sign or dimension holds for all between)."""
        try:
            values = np.asarray(numbers, dtype=float)
        except (TypeError, ValueError):
            raise UsageError(f"vary {name}: its values are not all numbers") from None
        except OverflowError:  # a whole number past a double's range (was an internal error)
            raise UsageError(f"vary {name}: a value is too large for a double") from None
        if values.shape != (self.n,):
            raise UsageError(
                f"vary {name}: give {self.n} values (one per copy), not {values.shape}"
            )
        if not np.all(np.isfinite(values)):
            raise UsageError(f"vary {name}: every value must be finite")
        unit = self._unit(name, unit)
        for probe in (values.min(), values.max(), 1.0):
            found = self._sorted([f"{name}={float(probe)!r}{unit}"])
        one = {**found.inputs, **found.params, **found.actuators}.get(name)
        if one is None:  # CONTROLLER.NAME: a switching run's, which a batch is not
            raise UsageError(f"vary {name}: name an input or parameter of {self.controller} alone")
        self._given[name] = (values, unit)
        return values * one  # ``one`` is 1 unit in SI (units scale; none is affine)

    def _unit(self, name: str, unit: str) -> str:
        """``vary``'s unit read as a unit alone ('N * m' as 'N*m'): it is written after each
        value as ``--set`` takes it, and a unit '1 m/s' made 2.0 a copy's 2.01 m/s, recorded
        as 2.0 (a number in the unit is refused, as any text that is not a unit)."""
        text = re.sub(r"\s*([*/^])\s*", r"\1", unit.strip())
        if not text:
            return ""
        try:
            parse_unit(text)
            return text
        except UnitError:
            pass
        own = setting_unit(self.session.model, self.controller, name)
        example = f"vary={{{name!r}: (values, {'m/s' if own is None else own!r})}}"
        if re.match(r"[-+]?(?:\d|\.\d|[eE][-+]?\d)", text):  # '1 m/s', 'e-1 m/s'
            why = (f"{unit!r} is not a unit: the unit is read alone, each copy's value is one "
                   "of the values; scale the values themselves and give the unit alone, e.g. "
                   f"{example}")  # fmt: skip
        else:
            why = unknown_unit(text).replace("write the value in", "give the values in")
            why = f"{why}; give e.g. {example}"
        raise UsageError(f"vary {name}: {why}")

    def _sorted(self, texts: list[str]) -> Settings:
        return sort_settings(texts, self.session.model, self.controller)

    def _start(self, given: np.ndarray | None, what: str, size: int) -> np.ndarray:
        if given is None:
            start = np.array(self.sim.q if what == "q0" else self.sim.v, dtype=float)
            return np.broadcast_to(start, (self.n, size))
        try:
            values = np.asarray(given, dtype=float)
        except (TypeError, ValueError):
            raise UsageError(f"{what}: its values are not all numbers") from None
        except OverflowError:  # a whole number past a double's range (was an internal error)
            raise UsageError(f"{what}: a value is too large for a double") from None
        if values.shape != (self.n, size):
            raise UsageError(
                f"{what}: give {self.n} rows of {size} (one per copy), not {values.shape}"
            )
        if not np.all(np.isfinite(values)):
            raise UsageError(f"{what}: every value must be finite")
        if what == "q0" and self.sim.free3d:  # q[3:7]: the root's orientation, a unit quaternion
            names = ", ".join(self.session.model.q_names[3:7])
            norms = np.sqrt(np.sum(values[:, 3:7] ** 2, axis=1))
            for k in np.flatnonzero(~(np.abs(norms - 1.0) <= 1e-6)):
                raise UsageError(
                    f"q0 of copy {k}: the root's orientation ({names}) is a unit quaternion, "
                    f"and its norm is {norms[k]:.6g}; divide it by its norm"
                )
        return values

    def _check_speeds(self) -> None:
        """A copy's ``v0`` past the divergence limit (``legdsl.sim.sizes.too_fast``, its own
        start's) would end it diverged before its first step, told as the file's velocity
        (which it is not): refused as the row's mistake, as a ``q0`` under the ground is."""
        if self.v0.strides[0] == 0:  # the file's start: a single run's rule tells it
            return
        sim = self.sim
        for k in range(self.n):
            fast = too_fast(self.v0[k], self.start_heights[k], sim.size_scale, sim.v_factors)
            if fast is None:
                continue
            i, speed, most = fast
            unit = "rad/s" if self.session.model.v_angular[i] else "m/s"
            name = self.session.model.v_names[i]
            raise UsageError(
                f"v0 of copy {k}: {name} = {float(self.v0[k, i]):.4g} {unit} is past the "
                f"divergence limit for a creature of its size ({most:.4g} {unit}; "
                "docs/runtime.md#divergence-and-falls): the copy would end diverged before its "
                f"first step; give v0[{k}, {i}] a speed under {most:.4g} {unit}"
            )

    def _check_stiffness(self) -> None:
        """The template's stiffness check (``RunSession._check_stiffness``) again with each
        varied actuator setting at its largest (the stiffer and the more damped, the worse)."""
        settings = {name: v for name, v in self.vary.items() if "." in name}
        if not settings:
            return
        sim, saved = self.sim, [copy(a) for a in self.sim.actuators.states]
        try:
            for name, values in settings.items():
                actuator, _, key = name.partition(".")
                sim.actuators.by_name[actuator].set(key, float(values.max()))
            controls = [self.session.control(self.controller)] if self.controller else []
            self.session._check_stiffness(sim, controls, set(settings))
        finally:
            for a, old in zip(sim.actuators.states, saved, strict=True):
                a.__dict__.update(old.__dict__)

    def _note_overwritten(self) -> None:
        """A varied actuator setting the controller writes itself is noted, as ``set=``'s is
        (``legdsl.sim.machine.overwritten``): from its first tick, the copies vary nothing."""
        if self.controller is None:
            return
        module = self.session.control(self.controller)
        for name in self.vary:
            if said := overwritten(name, self.controller, module, self.session.model):
                self.session.tell("note", f"vary {name}: {said}")

    def start_of(self, k: int) -> dict[str, dict[str, float]] | None:
        """Copy ``k``'s own start by coordinate (run.json's ``start``), None when the copies
        start from the file's (neither ``q0`` nor ``v0`` given: broadcast, no row their own)."""
        if self.q0.strides[0] == 0 and self.v0.strides[0] == 0:
            return None
        model = self.session.model
        return {
            "q": dict(zip(model.q_names, map(float, self.q0[k]), strict=True)),
            "v": dict(zip(model.v_names, map(float, self.v0[k]), strict=True)),
        }

    def texts(self, k: int) -> list[str]:
        """Copy ``k``'s ``--set`` texts: the batch's, then its own values as given."""
        own = [
            f"{name}={float(numbers[k])!r}{unit}" for name, (numbers, unit) in self._given.items()
        ]
        return self.settings + own

    def _start_heights(self) -> np.ndarray:
        """Each copy's standing height (the fall rule's); each start checked as a single
        run's is (``RunSession._check_start``) when the copies start apart."""
        sim = self.sim
        if self.q0.strides[0] == 0:
            return np.full(self.n, sim.standing_height())
        heights = np.empty(self.n)
        saved, saved_v = sim.q, sim.v
        try:
            for k in range(self.n):
                sim.move_to(self.q0[k].tolist(), saved_v)
                try:  # as RunSession._check_start, the fix told in the row's numbers
                    check_start(self.session.model, sim, self.session.source, row=k)
                    check_fall_height(sim)
                except UsageError as e:
                    raise UsageError(f"q0 of copy {k}: {e}") from None
                heights[k] = sim.standing_height()
        finally:
            sim.move_to(saved, saved_v)
        return heights
