"""The ``simulation`` block of a creature: its defaults for running it.

    simulation { dt 0.4 ms  control_dt 2 ms  record_rate 200 Hz }

Each is optional; ``legdsl run``'s --dt, --control-dt and --record-rate override them. A file
written by ``legdsl scale`` carries its scaled values (Table 1: times scale by L^(1/2)).
"""

from __future__ import annotations

from legdsl.check.values import ValueChecker, did_you_mean
from legdsl.ir.model import SimulationDefaults
from legdsl.lang import ast
from legdsl.lang.errors import Span
from legdsl.lang.scaling import COMPUTABLE_STEP, DEFAULT_DT, MOST_STEPS, SMALLEST_STEP

# property -> (kind, what it is called in messages)
SIMULATION_PROPS: dict[str, tuple[str, str]] = {
    "dt": ("time", "the integration step"),
    "control_dt": ("time", "the control interval"),
    "record_rate": ("frequency", "the record rate"),
}


class SimulationChecker(ValueChecker):
    def simulation(self, block: ast.BlockDecl) -> SimulationDefaults:
        values: dict[str, float] = {}
        spans: dict[str, Span] = {}
        for p in block.props:
            key = p.key.name
            if key not in SIMULATION_PROPS:
                self.err(
                    p.key.span,
                    f"unknown simulation property '{key}'"
                    + (
                        did_you_mean(key, list(SIMULATION_PROPS))
                        or f"; the simulation block takes {', '.join(SIMULATION_PROPS)}"
                    ),
                )
                continue
            if key in values:
                self.err(p.key.span, f"'{key}' is given twice in the simulation block")
                continue
            kind, what = SIMULATION_PROPS[key]
            value = self.one_scalar(p, kind, what)
            if value is None:
                continue
            if value < 0 or (value == 0 and key != "record_rate"):
                every = " (or 0 Hz: a sample every step)" if key == "record_rate" else ""
                self.err(p.value.span, f"{what} must be positive{every}")
                continue
            if key == "dt" and not value * value > 0:  # as --dt is refused (run refused it so)
                self.err(p.value.span, f"the integration step {value:g} s is too small to "
                         f"compute with (its square is 0 in doubles); give {COMPUTABLE_STEP:g} s or "
                         f"more (below {SMALLEST_STEP:g} s, a second of motion is more than a "
                         "billion steps)")  # fmt: skip
                continue
            values[key], spans[key] = value, p.value.span
        step = values.get("dt", DEFAULT_DT)
        if values.get("control_dt", step) < step * (1.0 - 1e-9):  # as legdsl run refuses it
            given = "this block's dt" if "dt" in values else "the default dt"
            self.err(
                spans["control_dt"],
                f"the control interval is shorter than the integration step "
                f"({step * 1e3:g} ms, {given}): the controller runs at most once a step; "
                "make control_dt at least dt",
            )
            del values["control_dt"]
        if values.get("control_dt", 0.0) / step > MOST_STEPS:
            self.err(
                spans["control_dt"], counted("the control interval", values["control_dt"], step)
            )
            del values["control_dt"]
        return SimulationDefaults(**values)


def counted(what: str, seconds: float, step: float) -> str:
    """The message of ``seconds`` too many steps of ``step`` to count (as `legdsl run`'s
    --time and --control-dt are refused: a file's value was told as those options)."""
    return (
        f"{what} {seconds:g} s is {seconds / step:.3g} steps of dt {step * 1e3:g} ms, more than "
        f"a run can count ({MOST_STEPS:.3g}); give {MOST_STEPS * step:.3g} s or less"
    )
