"""Print a lowered controller as ``generated/NAME/control_CONTROLLER.py``.

One function per (state, binding) for its event, its entry records and its
per-tick settings, plus tables that ``legdsl.sim.machine.StateMachine`` reads.
The math goes through the same straight-line builder (dead code, common
subexpressions, numbered temporaries) and printer as the dynamics.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import sympy
from sympy import Expr, Symbol

from legdsl import __version__
from legdsl.check.values import stdlib_name
from legdsl.codegen.manifest import shown_used
from legdsl.codegen.python.dynamics import _environment, _names, function_body
from legdsl.lower.control import LoweredController, Where, sensor_symbol
from legdsl.lower.straightline import Block, substituted
from legdsl.lower.symbolic import Function

PARAMS = ("s", "u", "p", "r", "tis")
# What the printed laws call: a local of the same name would hide it (TypeError).
CALLED = ("math", "minimum", "maximum", "abs")


def _program(
    name: str,
    exprs: list[sympy.Basic],
    lc: LoweredController,
    let: bool = True,
    names: list[str] | None = None,
) -> Function:
    """A generated function of (s, u, p, r, tis) returning ``exprs`` (a list, or one value).

    ``names`` (one per value) are what a returned value is assigned to.
    """
    block = Block(reserved=(*PARAMS, *CALLED, name))
    subs: dict[Symbol, sympy.Basic] = {}
    arrays = {
        **{sensor_symbol(k).name: ("s", i) for i, k in enumerate(lc.sensors)},
        **{f"input_{n}": ("u", i) for i, (n, _) in enumerate(lc.inputs)},
        **{f"param_{n}": ("p", i) for i, (n, _) in enumerate(lc.params)},
        **{f"record_{n}": ("r", i) for i, n in enumerate(lc.records)},
    }
    free = set().union(*(e.free_symbols for e in exprs)) if exprs else set()
    for sym in sorted(free, key=lambda s: s.name):
        if sym.name == "time_in_state":
            subs[sym] = Symbol("tis")
        else:
            array, index = arrays[sym.name]
            wanted = sym.name.split("_", 1)[1] if array in ("u", "p", "r") else sym.name
            subs[sym] = block.input(wanted, array, index)
    memo: dict[sympy.Basic, sympy.Basic] = {}
    outs = [substituted(e, subs, memo) for e in exprs]
    if let:
        outs = [block.let(o) if isinstance(o, Expr) else o for o in outs]
    program = block.finish(outs, names=names)
    result: object = list(program.outputs) if let else program.outputs[0]
    return Function(name, PARAMS, program.statements, result, program.names, program.bases)


@dataclass(frozen=True)
class ControlPrograms:
    """A lowered controller's generated functions and tables: what both targets print."""

    functions: list[tuple[Function, str]]  # (function, its docstring)
    tables: dict[str, list[tuple[tuple[int, int], str]]]  # events, entries, actions
    settings: list[tuple[tuple[int, int], tuple[tuple[str, str], ...]]]
    places: list[tuple[tuple[int, int], tuple[tuple[str, tuple[str, ...], tuple[str, ...]], ...]]]


def control_programs(lc: LoweredController, event_text: dict[str, str]) -> ControlPrograms:
    """The functions of a control module (each event, entry and action), and its tables."""
    functions = []
    tables: dict[str, list[tuple[tuple[int, int], str]]] = {
        "events": [],
        "entries": [],
        "actions": [],
    }
    settings = []
    places: list[
        tuple[tuple[int, int], tuple[tuple[str, tuple[str, ...], tuple[str, ...]], ...]]
    ] = []
    for (b, s), event in sorted(lc.events.items()):
        state = lc.states[s]
        fn = _program(f"event_{state}_{b}", [event], lc, let=False)
        functions.append(
            (fn, f"Enter {state} (waiting under binding {b}) when: {event_text[state]}")
        )
        tables["events"].append(((b, s), fn.name))
    for (b, s), body in sorted(lc.bodies.items()):
        state = lc.states[s]
        new = dict(body.records)
        values = [new.get(name, Symbol(f"record_{name}")) for name in lc.records]
        fn = _program(
            f"entry_{state}_{b}", values, lc, names=[f"new_{name}" for name in lc.records]
        )
        done = ", ".join(new) or "none"
        functions.append(
            (fn, f"The records on entering {state} under binding {b} (changed: {done}).")
        )
        tables["entries"].append(((b, s), fn.name))
        targets = [f"{st.actuator}.{st.key}" for st in body.settings]
        targets += [f"place {p.leg} ({', '.join(p.axes)})" for p in body.places]
        goals = [g for p in body.places for g in p.goals]
        names = [f"{st.actuator}_{st.key}" for st in body.settings]
        names += [f"{p.leg}_{axis}_goal" for p in body.places for axis in p.axes]
        values = [st.value for st in body.settings] + goals
        fn = _program(f"action_{state}_{b}", values, lc, names=names)
        functions.append(
            (fn, f"Every tick in {state} under binding {b}: {', '.join(targets) or 'nothing'}.")
        )
        tables["actions"].append(((b, s), fn.name))
        settings.append(((b, s), tuple((st.actuator, st.key) for st in body.settings)))
        if body.places:
            places.append(((b, s), tuple((p.leg, p.axes, p.servos) for p in body.places)))
    return ControlPrograms(functions, tables, settings, places)


def shown_file(file: str, source: str) -> str:
    """A span's file as the generated code names it, the same on every machine: the standard
    library's as ``stdlib/NAME``, a used file's as ``manifest.shown_used`` says."""
    path = Path(file)
    if not path.is_absolute():
        return file
    library = stdlib_name(path)
    if library is not None:
        return library
    return shown_used(path, source)


def origin(where: Where, source: str) -> str:
    """Where a statement came from, the state's row first, then each action it was inlined
    through: ``creatures/hopper.leg:67:49 > stdlib/raibert.leg:196:3``."""
    return " > ".join(
        f"{shown_file(span.file, source)}:{span.line}:{span.col}" for span in reversed(where)
    )


def origins(lc: LoweredController) -> dict[str, list[tuple[str, Where]]]:
    """Per generated function, each value it returns and where it was written (both targets
    print them: the Python module in docstrings, the C one in comments)."""
    found: dict[str, list[tuple[str, Where]]] = {}
    for (b, s), where in lc.event_where.items():
        found[f"event_{lc.states[s]}_{b}"] = [("event", where)] if where else []
    for (b, s), body in lc.bodies.items():
        state = lc.states[s]
        found[f"entry_{state}_{b}"] = [
            (f"record {name}", where)
            for (name, _), where in zip(body.records, body.record_where, strict=True)
        ]
        found[f"action_{state}_{b}"] = [
            *((f"{st.actuator}.{st.key}", st.where) for st in body.settings),
            *((f"place {p.leg} ({', '.join(p.axes)})", p.where) for p in body.places),
        ]
    return found


def _doc(first: str, lines: list[tuple[str, Where]], source: str) -> str:
    """A function's docstring: what it does, then the ``.leg`` place of each value it returns."""
    if not lines:
        return first
    width = max(len(target) for target, _ in lines)
    rows = [f"        {target.ljust(width)}  {origin(where, source)}" for target, where in lines]
    return "\n".join([first, "", "    From the .leg file:", *rows, "    "])


def render_control(
    lc: LoweredController,
    source: str,
    event_text: dict[str, str],
    fingerprint: str,
    programs: ControlPrograms | None = None,
) -> str:
    """The text of ``control_CONTROLLER.py``; ``event_text`` gives each state's event as written.
    ``programs``: ``control_programs(lc, event_text)``, when the caller has them (they take
    most of a controller's printing time, and the C target prints the same ones)."""
    programs = programs or control_programs(lc, event_text)
    functions, tables = programs.functions, programs.tables
    written = origins(lc)
    settings, places = programs.settings, programs.places
    bindings = [
        "; ".join(f"{role} = {', '.join(legs)}" for role, legs in binding)
        for binding in lc.bindings
    ]
    template = _environment().get_template("control.py.j2")
    return template.render(
        version=__version__,
        sympy_version=sympy.__version__,
        source=source,
        lc=lc,
        fingerprint=fingerprint,
        states=_names(lc.states),
        sensors=_names(lc.sensors) if lc.sensors else "()",
        records=_names(lc.records) if lc.records else "()",
        inputs={n: repr(float(v)) for n, v in lc.inputs},
        params={n: repr(float(v)) for n, v in lc.params},
        bindings=bindings,
        after_entry=sorted(lc.after_entry.items()),
        functions=[
            (fn, _doc(doc, written.get(fn.name, []), source), function_body(fn))
            for fn, doc in functions
        ],  # fmt: skip
        tables=tables,
        settings=settings,
        places=places,
    )
