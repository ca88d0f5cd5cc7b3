"""The ``simulation`` block of a creature: its defaults for running it.

    simulation { dt 0.4 ms  control_dt 2 ms  record_rate 200 Hz }

Each is optional; ``legdsl run``'s --dt, --control-dt and --record-rate override them. A file
written by ``legdsl scale`` carries its scaled values (Table 1: times scale by L^(1/2)).
"""

from __future__ import annotations

from legdsl.check.values import ValueChecker, did_you_mean
from legdsl.ir.model import SimulationDefaults
from legdsl.lang import ast

# property -> (kind, what it is called in messages)
SIMULATION_PROPS: dict[str, tuple[str, str]] = {
    "dt": ("time", "the integration step"),
    "control_dt": ("time", "the control interval"),
    "record_rate": ("frequency", "the record rate"),
}


class SimulationChecker(ValueChecker):
    def simulation(self, block: ast.BlockDecl) -> SimulationDefaults:
        values: dict[str, float] = {}
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
                self.err(p.value.span, f"{what} must be positive")
                continue
            values[key] = value
        return SimulationDefaults(**values)
