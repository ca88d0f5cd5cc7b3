"""Point a failing control law home: the ``.leg`` statement, the state, the time and the values.

The generated control module computes a state's outputs in one function; when it raises
(``math.sqrt`` of a negative number, ``asin`` out of its domain, a division by zero) or
returns a value that is not finite, ``explain`` lowers the controller again (only then: it
takes a moment) and evaluates each of the state's statements, in order, with the values of
that tick, as the generated code does (only the chosen branch of a ``select``). The first
that fails names the statement (``file:line:col``, and the action calls it was inlined
through), the operation and its operands, and the values it read; where the operation is
written in a signal the statement reads (through others, perhaps), that signal's line.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from types import ModuleType
from typing import Any

import sympy

from legdsl.check.values import shown_path
from legdsl.ir import controller as ir
from legdsl.ir.controller import (
    BODY_MEMBERS,
    COM_MEMBERS,
    CONTACT_MEMBERS,
    FUNCTION_VALUES,
    LEG_MEMBERS,
    PATH_MEMBERS,
    TERRAIN_MEMBERS,
)
from legdsl.ir.model import Model, setting_kind
from legdsl.lang.errors import Span
from legdsl.lang.scaling import factor
from legdsl.lang.units import DIMENSIONLESS, KINDS, Dim, parse_unit, unit_for
from legdsl.lower.control import FUNCTIONS, EachPass, Lowerer, Where
from legdsl.sim.run_loop import ControlFault


class _Bad(Exception):
    def __init__(self, what: str, operands: Sequence[float], node: Any):
        super().__init__(what)
        self.what = what
        self.operands = tuple(operands)
        self.node = node  # the operation that failed


# the sympy functions a lowered control law is made of, and their values (sqrt is a Pow and
# clamp a Min of a Max there, so neither is a function of its own)
_MATH: dict[Any, Callable[..., Any]] = {
    f: FUNCTION_VALUES[name] for name, f in FUNCTIONS.items() if isinstance(f, type)
}


def _name(e: Any) -> str:
    func = e.func
    if func is sympy.Pow:
        exp = e.args[1]
        return "sqrt" if exp == sympy.Rational(1, 2) else "x^y" if exp != -1 else "1/x (division)"
    return getattr(func, "__name__", str(func)).lower()


def _ev(e: Any, values: dict[Any, float]) -> Any:
    """``e`` evaluated as the generated code would, raising ``_Bad`` at the failing operation."""
    if e.is_Symbol:
        return values[e]
    if e is sympy.true or e is sympy.false:
        return bool(e)
    if e.is_Number or isinstance(e, sympy.NumberSymbol):
        return float(e)
    if isinstance(e, sympy.UnevaluatedExpr):  # a select's number held from sympy (lower.control)
        return _ev(e.args[0], values)
    if isinstance(e, sympy.Piecewise):
        for value, condition in e.args:
            if condition is sympy.true or _ev(condition, values):
                return _ev(value, values)
        return math.nan
    if isinstance(e, sympy.And):
        return all(_ev(a, values) for a in e.args)
    if isinstance(e, sympy.Or):
        return any(_ev(a, values) for a in e.args)
    if isinstance(e, sympy.Not):
        return not _ev(e.args[0], values)
    if isinstance(e, sympy.ITE):  # sympy's of a comparison with a select(); one branch
        condition, then, otherwise = e.args
        return _ev(then if _ev(condition, values) else otherwise, values)
    args = [_ev(a, values) for a in e.args]
    out: Any
    try:
        if isinstance(e, sympy.core.relational.Relational):
            a, b = args
            return {"<": a < b, ">": a > b, "<=": a <= b, ">=": a >= b, "==": a == b,
                    "!=": a != b}[e.rel_op]  # fmt: skip
        if e.func is sympy.Add:
            out = math.fsum(args)
        elif e.func is sympy.Mul:
            out = math.prod(args)
        elif e.func is sympy.Pow:
            out = args[0] ** args[1]
        elif e.func in _MATH:
            out = _MATH[e.func](*args)
        else:
            out = complex(e.func(*args).evalf())
    except ZeroDivisionError:  # a division is a power -1 in sympy: Python's words tell that
        raise _Bad(f"{_call_text(e, args)} divides by 0", args, e) from None
    except OverflowError:  # Python's words for it are an errno tuple: say it plainly
        raise _Bad(_overflows(e, args), args, e) from None
    except (ValueError, TypeError) as err:
        raise _Bad(f"{_call_text(e, args)} is undefined ({err})", args, e) from None
    if isinstance(out, complex):
        if out.imag != 0:
            raise _Bad(f"{_call_text(e, args)} has no real value", args, e)
        out = out.real
    if not math.isfinite(out) and all(math.isfinite(a) for a in args):
        what = _overflows(e, args) if math.isinf(out) else f"{_call_text(e, args)} is {out}"
        raise _Bad(what, args, e)
    return out


def _as_written(lowerer: Lowerer, bad: _Bad, values: dict[Any, float]) -> str:
    """``bad``'s words with the operands of the call as the law writes it: sympy keeps an odd
    function of a negated argument as the negated function (``asin(x - 0.5)`` as
    ``-asin(0.5 - x)``), whose operand has the other sign than the one written."""
    node = bad.node
    for func, args, result in lowerer.calls():
        if FUNCTIONS[func] is not node.func or not (result == -node or result == node):
            continue
        try:
            written = [_ev(a, values) for a in args]
        except (_Bad, KeyError, TypeError):
            continue
        if len(written) == len(bad.operands):
            return bad.what.replace(_call_text(node, bad.operands), _call_text(node, written), 1)
    return bad.what


def _overflows(e: Any, args: Sequence[float]) -> str:
    """An operation of finite operands whose result is past the largest double, with the
    size it would have had (where that is simple to tell) and the way out."""
    size = ""
    try:
        if _name(e) == "x^y":
            size = f"{args[1] * math.log10(abs(args[0])):.0f}"
        elif _name(e) == "exp":
            size = f"{args[0] * math.log10(math.e):.0f}"
        elif e.func is sympy.Mul:
            size = f"{math.fsum(math.log10(abs(a)) for a in args):.0f}"
    except (ValueError, IndexError):  # an operand of 0: no size to tell
        size = ""
    would = f"it would be about 1e{size}, " if size else ""
    return (
        f"{_call_text(e, args)} overflows a double ({would}past the largest, 1.8e308); "
        f"bound what it reads, as in clamp(..., low, high)"
    )


def _call_text(e: Any, args: Sequence[float]) -> str:
    name = _name(e)
    if name == "sqrt":
        return f"sqrt({args[0]:.4g})"
    if name.startswith("1/x"):
        return f"1/{args[0]:.4g} (a division)"
    return f"{name}({', '.join(f'{a:.4g}' for a in args)})"


def _span(where: Where) -> Span | None:
    """The statement's own span, where the law failed (its line is shown with a caret)."""
    return where[0] if where and isinstance(where[0], Span) else None


def _place(at: Span | EachPass) -> str:
    """``file:line:col`` as messages name a file: the standard library as ``stdlib/NAME``, the
    same on every machine, not the absolute path of this machine's copy."""
    span = at.span if isinstance(at, EachPass) else at
    file = shown_path(span.file)
    return f"{file}:{span.line}:{span.col}" if span.line > 0 else file


def _where(where: Where) -> str:
    """'file:line:col', then the action calls and each blocks it came through, innermost
    first: ' (inlined from the action called at A, called at B; for m = fl in the each at C)'."""
    if not where:
        return "the controller"
    through, called = [], False
    for w in where[1:]:
        if isinstance(w, EachPass):
            var = w.var.partition("#")[0]  # the checker numbers each block's variable
            through.append(f"; for {var} = {w.leg} in the each at {_place(w.span)}")
            called = False
        else:
            through.append(
                f", called at {_place(w)}"
                if called
                else f"; inlined from the action called at {_place(w)}"
            )
            called = True
    first = _place(where[0])
    return f"{first} ({''.join(through)[2:]})" if through else first


def explain(
    model: Model,
    module: ModuleType,
    kind: str,  # "event", "entry", "action" or "place"
    key: tuple[int, int],
    args: tuple[Any, ...],  # (s, u, p, r, tis) as passed to the generated function
    t: float,
    state: str,
    error: str,
    index: int | None = None,  # which output was not finite, or which place failed
    scale: float = 1.0,
) -> ControlFault:
    """A ``ControlFault`` naming the statement that failed, with the values it read; its time
    and values as the creature scaled by ``scale``'s (a ``--scale L`` run's: each by its
    Table 1 factor), as the scaled file's run tells them."""
    from legdsl.lower.control import sensor_symbol

    s, u, p, r, tis = args
    head = f"the control law failed in state {state} at t = {t * math.sqrt(scale):.4f} s"
    try:
        controller = model.controller(module.CONTROLLER)
        lowerer = Lowerer(model, controller)
        lc = lowerer.lower()
    except Exception:  # pragma: no cover - explaining must never hide the fault itself
        return ControlFault(f"{head}: {error}")
    names: dict[Any, str] = {sensor_symbol(k): k for k in module.SENSORS}
    names |= {sympy.Symbol(f"input_{n}"): f"input {n}" for n in module.INPUTS}
    names |= {sympy.Symbol(f"param_{n}"): f"param {n}" for n in module.PARAMS}
    names |= {sympy.Symbol(f"record_{n}"): f"record {n}" for n in module.RECORDS}
    names[sympy.Symbol("time_in_state")] = "time_in_state"
    values: dict[Any, float] = {sensor_symbol(k): v for k, v in zip(module.SENSORS, s, strict=True)}
    values |= {sympy.Symbol(f"input_{n}"): v for n, v in zip(module.INPUTS, u, strict=True)}
    values |= {sympy.Symbol(f"param_{n}"): v for n, v in zip(module.PARAMS, p, strict=True)}
    values |= {sympy.Symbol(f"record_{n}"): v for n, v in zip(module.RECORDS, r, strict=True)}
    values[sympy.Symbol("time_in_state")] = tis
    dims = _dims(model, controller, module)
    shown = {x: v * factor(dims.get(names.get(x, "")), scale) for x, v in values.items()}
    units = _units(controller, dims)
    names = {x: _with_unit(name, units.get(name)) for x, name in names.items()}
    body = lc.bodies.get(key)
    candidates: list[tuple[str, Any, Where]] = []
    if kind == "event":
        candidates = [("its event", lc.events[key], lc.event_where.get(key, ()))]
    elif kind == "entry" and body is not None:
        candidates = [
            (f"record {name}", e, w)
            for (name, e), w in zip(body.records, body.record_where, strict=False)
        ]
    elif body is not None:
        candidates = [(f"{st.actuator}.{st.key} = ...", st.value, st.where) for st in body.settings]
        candidates += [
            (f"place {pl.leg} ({axis})", goal, pl.where)
            for pl in body.places
            for axis, goal in zip(pl.axes, pl.goals, strict=True)
        ]
        if kind == "place" and index is not None and index < len(body.places):
            pl = body.places[index]
            goals = (f"{a} = {_ev(g, values) * scale:.4g}"  # offsets from the hip: lengths
                     for a, g in zip(pl.axes, pl.goals, strict=True))  # fmt: skip
            return ControlFault(f"{_where(pl.where)}: {head}: place {pl.leg}: {error}; "
                                f"goals {', '.join(goals)}", _span(pl.where))  # fmt: skip
    if index is not None and kind != "place" and index < len(candidates):
        candidates = [candidates[index], *candidates]
    for label, expr, where in candidates:
        try:
            out = _ev(expr, values)
        except _Bad as bad:
            what = _divisor_zero(bad, names) or _as_written(lowerer, bad, values)
            if scale != 1.0 and bad.operands:  # an operand's dimension is not known here
                what += " (its operands are the unscaled file's numbers)"
            roles = dict(controller.bindings[key[0]]) if key[0] < len(controller.bindings) else {}
            found = _signal_at_fault(lowerer, controller, roles, bad.node, values)
            if found is not None:  # told where the operation is written
                signal, expr = found
                label = f"signal {signal.name} (read by {label} at {_where(where)})"
                where = (signal.span,)
            text = _message(where, head, label, what, expr, names, shown)
            return ControlFault(text, _span(where))
        except (KeyError, TypeError):
            continue
        if isinstance(out, float) and not math.isfinite(out):
            text = _message(where, head, label, f"the value is {out}", expr, names, shown)
            return ControlFault(text, _span(where))
    first = candidates[0][2] if candidates else ()
    return ControlFault(f"{_where(first)}: {head}: {error}", _span(first))


# a sensor's dimension by its key's kind (``legdsl.sim.sensors``): the member's, where fixed
_MEMBERS = {"com": COM_MEMBERS, "contact": CONTACT_MEMBERS, "terrain": TERRAIN_MEMBERS,
            "path": PATH_MEMBERS, "body": BODY_MEMBERS, "leg": LEG_MEMBERS}  # fmt: skip


def _dims(model: Model, controller: ir.Controller, module: ModuleType) -> dict[str, Dim | None]:
    """The dimension of each value a statement reads, by its name in ``explain``'s words
    (``input speed``, ``com.z``); None where it has none to scale by (a flag, a bare number)."""
    own = {c.name: c.dim for c in (*controller.inputs, *controller.params)}
    dims: dict[str, Dim | None] = {f"input {n}": own.get(n) for n in module.INPUTS}
    dims |= {f"param {n}": own.get(n) for n in module.PARAMS}
    dims |= {f"record {n}": d if isinstance(d, tuple) else None for n, d in controller.records}
    dims["time_in_state"] = KINDS["time"][0]
    motion = {d.name: d.motion for d in model.dofs}
    rotary = {a.name: a.rotary for a in model.actuators}
    for key in module.SENSORS:
        kind, _, rest = key.partition(".")
        name, _, member = rest.rpartition(".")
        dim: Dim | None = _MEMBERS.get(kind, {}).get(member)
        if kind == "time":
            dim = KINDS["time"][0]
        elif kind == "coord" and name in motion:
            angular = motion[name] == "hinge"
            kinds = ("angle", "angular velocity") if angular else ("length", "velocity")
            dim = KINDS[kinds[member == "rate"]][0]
        elif kind == "act" and name in rotary:
            dim = KINDS[setting_kind(member, rotary[name])][0]
        elif kind == "integral" and isinstance(own.get(rest), tuple):
            a, b, c, d = own[rest]  # an input's integral over time
            dim = (a, b, c + 1, d)
        dims[key] = dim
    return dims


def _units(controller: ir.Controller, dims: dict[str, Dim | None]) -> dict[str, str]:
    """The unit each value a statement reads is told in: an input's or parameter's as its
    default is written ('ms', 'deg'), else its kind's ('s', 'deg', 'm/s'); none for a flag
    or a bare number."""
    written = {f"{kind} {c.name}": c.unit for kind, constants in
               (("input", controller.inputs), ("param", controller.params))
               for c in constants if c.unit}  # fmt: skip
    units = {}
    for name, dim in dims.items():
        if name in written:
            units[name] = written[name]
        elif isinstance(dim, tuple) and dim != DIMENSIONLESS:
            units[name] = unit_for(dim)
    return units


class _Named(str):
    """A value's name in ``explain``'s words, carrying the unit it is told in: ``str`` is
    the name, ``told(value)`` the value in that unit ('tscale = 500 ms')."""

    unit: str
    per: float

    def told(self, value: float) -> str:
        if not self.unit or not math.isfinite(value):
            return f"{value:.4g}"
        return f"{value / self.per:.4g} {self.unit}"


def _with_unit(name: str, unit: str | None) -> _Named:
    named = _Named(name)
    named.unit, named.per = "", 1.0
    if unit:
        try:
            named.per = parse_unit(unit)[0]
            named.unit = unit
        except ValueError:  # pragma: no cover - the checker read it
            pass
    return named


def _divisor_zero(bad: _Bad, names: dict[Any, str]) -> str:
    """For a division by 0, the divisor as the user writes it (``last_stance``), and the way
    out; '' for any other failure. ``x / y`` is ``x * y^-1`` in sympy."""
    node = bad.node
    if node.func is not sympy.Pow or bad.operands[0] != 0 or not bad.operands[1] < 0:
        return ""
    base = node.args[0]
    shown = {x: sympy.Symbol(_written(names[x])) for x in base.free_symbols if x in names}
    text = str(base.xreplace(shown))
    if len(text) > 60:
        return "a division by 0: its divisor is 0 here"
    return (
        f"a division by 0: its divisor '{text}' is 0 here; give a value to use while it is, "
        f"as in select({text} != 0, ..., ...)"
    )


def _written(name: str) -> str:
    """A value's name as the controller writes it: ``record last_stance`` is ``last_stance``,
    the sensor ``leg.main.rate`` is ``main.rate``."""
    word = name.split(" ")[-1]
    return word.split(".", 1)[1] if word.count(".") == 2 else word


def _signal_at_fault(
    lowerer: Lowerer,
    controller: ir.Controller,
    roles: dict[str, tuple[str, ...]],
    node: Any,
    values: dict[Any, float],
) -> tuple[ir.Signal, Any] | None:
    """The signal in which the failing operation ``node`` is written, and its value: of the
    signals that hold it and fail on it, the one that reads no other such (``ts``, not the
    ``xf`` that reads ``ts``); None if it is written in the statement itself."""
    failing: dict[str, tuple[ir.Signal, Any]] = {}
    for signal in controller.signals:
        try:
            value = lowerer.expr(signal.value, roles)
            if not (isinstance(value, sympy.Basic) and value.has(node)):
                continue
            _ev(value, values)
        except _Bad as bad:
            if bad.node == node:
                failing[signal.name] = (signal, value)
        except Exception:  # noqa: BLE001 - a signal of an `each` member, or of no value: not it
            continue
    for signal, value in failing.values():
        reads = (x for x in ir.leaves(signal.value) if isinstance(x, ir.Named))
        if not any(x.kind == "signal" and x.name in failing for x in reads):
            return signal, value
    return None


def _told(name: Any, value: float) -> str:
    return name.told(value) if isinstance(name, _Named) else f"{value:.4g}"


def _message(
    where: Where,
    head: str,
    label: str,
    what: str,
    expr: Any,
    names: dict[Any, str],
    values: dict[Any, float],
) -> str:
    used = sorted(expr.free_symbols, key=lambda x: names.get(x, str(x)))
    read = ", ".join(f"{names.get(x, str(x))} = {_told(names.get(x), values[x])}"
                     for x in used[:10] if x in values)  # fmt: skip
    text = f"{_where(where)}: {head}: in {label}, {what}; it read {read or 'no values'}"
    unmeasured = [names[x] for x in used if x in names and x in values and values[x] != values[x]]
    if unmeasured:
        text += f"; {unmeasured[0]} is NaN (not measured yet)"
        if unmeasured[0].endswith(("stance_time", "flight_time")):
            sensor = _written(unmeasured[0])  # as the controller writes it: main.stance_time
            text += (
                f": give a time to use until it is, as in select({sensor} > 0 s, {sensor}, 0.3 s)"
            )
    return text
