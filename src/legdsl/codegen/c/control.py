"""Lay out ``generated/NAME/control_CONTROLLER.c``: the controller of ``control_CONTROLLER.py`` in C.

The functions are the Python target's (``legdsl.codegen.python.control.control_programs``: the
same straight-line code, names and order), printed by ``CPrinter``; the tables are the same
tables, flattened to arrays indexed by ``binding * n_states + state``; ``read_sensors`` reads
the SENSORS in order through the runtime's sensor functions (``runtime/legdsl_control.h``).
The state machine that uses them is ``runtime/machine.c``. Each action function is headed by
the ``.leg`` line of each statement it computes.

A controller that reads a path (``path.NAME...``: the path tracker stays in Python) is printed
as a stub that says so, and runs on the Python state machine.
"""

from __future__ import annotations

from legdsl.codegen.c.dynamics import first_line, statements_text
from legdsl.codegen.c.printer import CPrinter, UnsupportedInC
from legdsl.codegen.python.control import (
    PARAMS,
    ControlPrograms,
    control_programs,
    origin,
    origins,
)
from legdsl.ir.controller import TERRAIN_MEMBERS
from legdsl.ir.model import Model
from legdsl.ir.paths import MEMBERS
from legdsl.lower.control import LoweredController
from legdsl.lower.symbolic import Function

AXES = ("x", "y", "z", "vx", "vy", "vz")
ACT_MEMBERS = {"k": 0, "kp": 0, "b": 1, "kv": 1, "rest": 2, "setpoint": 2, "force": 3}
SET_KEYS = {"k": 0, "kp": 0, "b": 1, "kv": 1, "rest": 2, "setpoint": 2, "force": 3}
BODY_MEMBERS = ("x", "y", "z", "vx", "vy", "vz", "roll", "pitch", "yaw", "roll_rate",
                "pitch_rate", "yaw_rate")  # fmt: skip
# leg_sense_terrain's member numbers (machine.c)
TERRAIN = tuple(TERRAIN_MEMBERS)
LEG_MEMBERS = ("touching", "stance_time", "flight_time", "length", "rate", "hip_x", "hip_y",
               "hip_z", "foot_x", "foot_y", "foot_z")  # fmt: skip


def sensor_call(model: Model, key: str, controller: str | None = None) -> str:
    """The C expression of one sensor key (``Sensors._value``)."""
    kind, _, rest = key.partition(".")
    name, _, member = rest.rpartition(".")
    if kind == "time":
        return "s->t"
    if kind == "coord":
        dof = next(d for d in model.dofs if d.name == name)
        return f"s->q[{dof.q_index}]" if member == "value" else f"s->v[{dof.v_index}]"
    if kind == "com":
        axis = "xyz".index(member[-1])
        return f"leg_sense_com(s, {axis}, {int(member.startswith('v'))}, err)"
    if kind == "contact":
        i = [c.name for c in model.contacts].index(name)
        code = (
            0 if member == "touching" else "xyz".index(member[-1]) + (4 if member[0] == "v" else 1)
        )
        return f"leg_sense_contact(s, {i}, {code}, err)"
    if kind == "act":
        a = [x.name for x in model.actuators].index(name)
        return f"leg_sense_act(s, {a}, {ACT_MEMBERS[member]})"
    if kind == "body" and member in BODY_MEMBERS:
        b = [x.name for x in model.bodies].index(name)
        return f"leg_sense_body(s, {b}, {BODY_MEMBERS.index(member)}, err)"
    if kind == "leg" and member in (*LEG_MEMBERS, "foot_vx", "foot_vy", "foot_vz"):
        leg = next(x for x in model.legs if x.name == name)
        code = LEG_MEMBERS.index(member) if member in LEG_MEMBERS else 11 + "xyz".index(member[-1])
        return f"leg_sense_leg(s, {model.legs.index(leg)}, {code}, err)"
    if kind == "path" and controller is not None and member in MEMBERS:
        names = [p.name for p in model.controller(controller).paths]
        if len(names) <= 64:
            return f"leg_sense_path(s, {names.index(name)}, {MEMBERS.index(member)}, err)"
    if kind == "integral" and controller is not None:  # Integral.value (legdsl.sim.machine)
        i = [c.name for c in model.controller(controller).inputs].index(rest)
        return (f"(s->ctl_integral[{2 * i}] + s->ctl_inputs[{i}] * "
                f"(s->t - s->ctl_integral[{2 * i + 1}]))")  # fmt: skip
    if kind == "terrain" and member in TERRAIN:
        return f"leg_sense_terrain(s, {TERRAIN.index(member)}, err)"
    raise UnsupportedInC(f"the sensor {key} (it stays in Python)")


def _function(fn: Function, doc: str, lines: list[str] | None = None) -> str:
    printer = CPrinter.for_function(fn)
    args = ", ".join(f"const double *{p}" for p in PARAMS[:4]) + ", double tis"
    head = [f"/* {doc} */"] + [f"/*   {line} */" for line in lines or []]
    if isinstance(fn.result, list):
        body = statements_text(fn, printer)
        outs = [f"    out[{k}] = {printer.print(v)};" for k, v in enumerate(fn.result)]
        return "\n".join([*head, f"static void {fn.name}({args}, double *out, int *err)", "{",
                          *body, *outs, "    (void)s; (void)u; (void)p; (void)r; (void)tis;",
                          "    (void)err;", "}"])  # fmt: skip
    body = statements_text(fn, printer)
    return "\n".join([*head, f"static int {fn.name}({args}, int *err)", "{", *body,
                      "    (void)s; (void)u; (void)p; (void)r; (void)tis; (void)err;",
                      f"    return {printer.print(fn.result)};", "}"])  # fmt: skip


def render_control_c(
    model: Model,
    lc: LoweredController,
    source: str,
    event_text: dict[str, str],
    stamp: str,
    programs: ControlPrograms | None = None,
) -> str:
    """The text of ``generated/NAME/control_CONTROLLER.c``; ``programs`` as for
    ``render_control``."""
    header = [
        first_line(source),
        f" * control_{lc.name}.c: controller '{lc.name}' of '{model.name}' in C, printed from the",
        f" * same functions as control_{lc.name}.py; runtime/machine.c runs it (the C backend).",
        " */",
        '#include "legdsl_math.h"\n#include "legdsl_sim.h"\n#include "dynamics.h"',
        '#include "legdsl_control.h"',
        "",
        f'const char legdsl_control_fingerprint[] = "{stamp}";',
    ]
    try:
        return _render(model, lc, header, programs or control_programs(lc, event_text), source)
    except UnsupportedInC as why:
        return "\n".join([*header, f"/* Not in C: {why}; the Python state machine runs it. */",
                          "const int64_t leg_has_c_controller = 0;",
                          "const leg_controller leg_the_controller = {0};", ""])  # fmt: skip


def _render(
    model: Model,
    lc: LoweredController,
    header: list[str],
    programs: ControlPrograms,
    source: str,
) -> str:
    sensors = [f"    out[{k}] = {sensor_call(model, key, lc.name)};  /* {key} */"
               for k, key in enumerate(lc.sensors)]  # fmt: skip
    parts = ["\n".join(header), "const int64_t leg_has_c_controller = 1;"]
    parts.append("\n".join(["static void read_sensors(leg_sim *s, double *out, int *err)", "{",
                            *sensors, "    (void)s; (void)out; (void)err;", "}"]))  # fmt: skip
    notes = _action_notes(lc, source)
    for fn, doc in programs.functions:
        parts.append(_function(fn, doc, notes.get(fn.name)))
    n_states, n_bindings = len(lc.states), len(lc.bindings)

    def table(name: str, kind: str, default: str) -> str:
        cells = [default] * (n_states * n_bindings)
        for (b, s), fn_name in programs.tables[name]:
            cells[b * n_states + s] = fn_name
        return f"static const {kind} {name}[] = {{{', '.join(cells)}}};"

    after = ["0"] * (n_states * n_bindings)
    for (b, s), then in lc.after_entry.items():
        after[b * n_states + s] = str(then)
    actuators = [a.name for a in model.actuators]
    counts = ["0"] * (n_states * n_bindings)
    lists = ["0"] * (n_states * n_bindings)
    setting_arrays = []
    for (b, s), targets in programs.settings:
        pairs = [f"{actuators.index(a)}, {SET_KEYS[k]}" for a, k in targets]
        counts[b * n_states + s] = str(len(targets))
        setting_arrays.append(
            f"static const int64_t settings_{b}_{s}[] = {{{', '.join(pairs) or '0'}}};"
        )
        lists[b * n_states + s] = f"settings_{b}_{s}"
    most = max((len(t) for _, t in programs.settings), default=0)
    n_outputs, n_places, place_i, place_d = _places(model, lc, n_states, n_bindings)
    most = max([most, *(int(x) for x in n_outputs)])
    parts += [
        f"static const int64_t after_entry[] = {{{', '.join(after)}}};",
        table("events", "leg_event_fn", "0"),
        table("entries", "leg_values_fn", "0"),
        table("actions", "leg_values_fn", "0"),
        "\n".join(setting_arrays),
        f"static const int64_t n_settings[] = {{{', '.join(counts)}}};",
        f"static const int64_t *const settings[] = {{{', '.join(lists)}}};",
        *place_i[1],
        *place_d[1],
        f"static const int64_t n_outputs[] = {{{', '.join(n_outputs)}}};",
        f"static const int64_t n_places[] = {{{', '.join(n_places)}}};",
        f"static const int64_t *const places_i[] = {{{', '.join(place_i[0])}}};",
        f"static const double *const places_d[] = {{{', '.join(place_d[0])}}};",
        "const leg_controller leg_the_controller = {\n"
        f"    {n_states}, {n_bindings}, {len(lc.sensors)}, {len(lc.inputs)}, {len(lc.records)},"
        f" {most},\n"
        "    after_entry, events, entries, actions, n_settings, settings, read_sensors,\n"
        "    n_outputs, n_places, places_i, places_d,\n};",
    ]
    return "\n\n".join(parts) + "\n"


def _places(model: Model, lc: LoweredController, n_states: int, n_bindings: int) -> tuple[
    list[str], list[str], tuple[list[str], list[str]], tuple[list[str], list[str]]
]:  # fmt: skip
    """Per (binding, state): the number of outputs, of places, and each place's data."""
    cells = n_states * n_bindings
    n_outputs, n_places = ["0"] * cells, ["0"] * cells
    ints, doubles = ["0"] * cells, ["0"] * cells
    int_arrays, double_arrays = [], []
    actuators = [a.name for a in model.actuators]
    dofs = {d.name: d for d in model.dofs}
    contacts = [c.name for c in model.contacts]
    for (b, s), body in sorted(lc.bodies.items()):
        k = b * n_states + s
        n_outputs[k] = str(len(body.settings) + sum(len(p.axes) for p in body.places))
        n_places[k] = str(len(body.places))
        if not body.places:
            continue
        i_data: list[str] = []
        d_data: list[str] = []
        for p in body.places:
            leg = next(x for x in model.legs if x.name == p.leg)
            servo_dofs = [
                dofs[next(a.dof for a in model.actuators if a.name == sv)] for sv in p.servos
            ]
            n = len(p.axes)
            i_data += [str(contacts.index(leg.foot)), str(model.legs.index(leg)), str(n)]
            i_data += [str("xyz".index(a)) for a in p.axes]
            i_data += [str(actuators.index(sv)) for sv in p.servos]
            i_data += [str(d.q_index) for d in servo_dofs] + [str(d.v_index) for d in servo_dofs]
            i_data += [str(int(d.limits is not None)) for d in servo_dofs]
            d_data += [repr(float(d.limits[0])) if d.limits else "0.0" for d in servo_dofs]
            d_data += [repr(float(d.limits[1])) if d.limits else "0.0" for d in servo_dofs]
        int_arrays.append(f"static const int64_t places_{b}_{s}_i[] = {{{', '.join(i_data)}}};")
        double_arrays.append(f"static const double places_{b}_{s}_d[] = {{{', '.join(d_data)}}};")
        ints[k], doubles[k] = f"places_{b}_{s}_i", f"places_{b}_{s}_d"
    return n_outputs, n_places, (ints, int_arrays), (doubles, double_arrays)


def _action_notes(lc: LoweredController, source: str) -> dict[str, list[str]]:
    """Per function: each value it computes and the .leg place it comes from (as the Python
    module's docstrings give them)."""
    return {name: [f"{target}: {origin(where, source)}" for target, where in rows]
            for name, rows in origins(lc).items()}  # fmt: skip
