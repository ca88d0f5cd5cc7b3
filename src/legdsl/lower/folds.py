"""What the lowering tells of a controller expression that sympy's folding makes no finite
number of, or that a fold would hide: messages only (``legdsl.lower.control`` finds them)."""

from __future__ import annotations

from typing import Any

import sympy

from legdsl.ir import controller as ir

NO_VALUE = (
    "this gives no finite real number, whatever the creature's state (sympy makes an infinity, "
    "NaN or a complex number of it: a division by something that is always 0, or a function "
    "outside its domain); write it otherwise"
)


def past_double(number: Any, operands: tuple[Any, ...]) -> str:
    """What to tell of a product or power whose numbers, gathered into one, pass a double."""
    shown = ", ".join(f"{float(f):g}" for x in operands for f in _floats(x))
    return (
        f"this gives no finite real number as compiled: the compiler gathers the numbers of a "
        f"product or power into one ({shown} make {str(sympy.Float(number, 3))}), past a double "
        "(1.8e308), whatever the creature's state; write it with smaller numbers (one factor, "
        "or a unit that keeps the values within a double)"
    )


def _floats(x: Any) -> list[Any]:
    if isinstance(x, sympy.Float):
        return [x]
    if isinstance(x, sympy.Mul):
        return [a for a in x.args if isinstance(a, sympy.Float)]
    return []


def dropped(e: ir.Binary | ir.Call, result: Any, operands: tuple[Any, ...]) -> str:
    """What to tell of a part of ``operands`` that folding ``e`` to ``result`` leaves out,
    and that has no value with the parameters and inputs as declared."""
    names = sorted(
        repr(str(s).split("_", 1)[1])
        for s in set().union(*(getattr(x, "free_symbols", set()) for x in operands))
        if str(s).startswith(("param_", "input_"))
    )
    because = {
        "*": "a factor of it is 0",
        "/": "it divides 0",
        "^": "its power is 0",
        "-": "its terms cancel",
        "+": "its terms cancel",
    }
    how = because.get(e.op, "it folds") if isinstance(e, ir.Binary) else f"{e.func}() folds"
    declared = f" with {', '.join(names)} as declared" if names else ""
    return (
        f"a part of this gives no finite real number{declared} (a division by 0, or a "
        "function outside its domain), and the compiled code leaves it out: this is always "
        f"{float(result):g} as compiled ({how}), so a run does not fault on it as it does "
        f"without the fold; remove that part, or give {' and '.join(names) or 'it'} a value "
        "where it has one"
    )
