"""Whether a controller expression is 0 in every state: its terms cancel, as in
``trunk.z - trunk.z`` or ``2 * err - err - err``, once its signals are written out.

The expression is written as a polynomial in what it reads (sensors, inputs, records...;
a function, a division or a power of them counts as one more thing read, by what it is
made of): it is always 0 when every coefficient is. A constant 0 is ``constant_value``'s
to tell. Sympy would find these too, but a run of generated code must not wait for it
to load (tests/architecture); lowering, which uses sympy, still refuses what it finds.
"""

from __future__ import annotations

from collections.abc import Mapping

from legdsl.ir import controller as ir

# monomial (atoms, each with its power, in order) -> coefficient; {} is 0
Poly = dict[tuple[tuple[int, int], ...], float]
MAX_TERMS = 64  # a product of sums grows fast: past this the expression is left unknown
_SMALL_POWERS = range(0, 5)  # `x ^ 2` is x * x; other powers are atoms


class ZeroTest:
    """One controller's expressions, each made a polynomial once (remembered by node)."""

    def __init__(self) -> None:
        self.signal_ir: Mapping[str, ir.Expr | None] = {}
        self._atoms: dict[object, int] = {}
        self._polys: dict[int, tuple[ir.Expr, Poly | None]] = {}

    def divisor(
        self, e: ir.Expr, constant: float | None, signal_ir: Mapping[str, ir.Expr | None]
    ) -> str:
        """What to tell of a division by ``e`` (of value ``constant``, if it has one) that is
        always 0, after 'division by zero: '; '' for one that is not."""
        self.signal_ir = signal_ir
        if constant == 0:
            gravity = any(
                isinstance(x, ir.Named) and (x.kind, x.name) == ("builtin", "g")
                for x in ir.leaves(e)
            )
            if not gravity:
                return (
                    "this is 0; divide by something that is not 0 (a number, a parameter or "
                    "a reading), or leave the division out"
                )
            # 'g - g' is 0 whatever g is: blaming the creature's gravity would be false
            if self.poly(e) == {}:
                return "this is 0 (its terms cancel); divide by something that is not always 0"
            return (
                "this is 0 (the creature's gravity, g, is 0); give the creature a gravity "
                "('gravity 9.81 m/s^2'), or divide by something that is not 0"
            )
        if constant is not None or self.poly(e) != {}:
            return ""
        signals = [x.name for x in ir.leaves(e) if isinstance(x, ir.Named) and x.kind == "signal"]
        through = f" once {_listed('signal', signals)} written out" if signals else ""
        return (
            f"this is 0 whatever the creature's state (its terms cancel{through}); divide by "
            "something that is not always 0"
        )

    def poly(self, e: ir.Expr) -> Poly | None:
        """``e`` as a polynomial; None when unknown (too large, or a signal that failed).
        Made from the leaves up, without recursion (expressions are up to 250 deep)."""
        stack: list[ir.Expr] = [e]
        while stack:
            node = stack[-1]
            if id(node) in self._polys:
                stack.pop()
                continue
            waiting = [p for p in self._parts(node) if id(p) not in self._polys]
            if waiting:
                stack += waiting
                continue
            stack.pop()  # the node kept with its polynomial, so that its id is not reused
            self._polys[id(node)] = (node, self._made(node))
        return self._polys[id(e)][1]

    def _parts(self, node: ir.Expr) -> list[ir.Expr]:
        if isinstance(node, ir.Unary):
            return [node.operand]
        if isinstance(node, ir.Binary):
            return [node.left, node.right]
        if isinstance(node, ir.Call):
            return list(node.args)
        if isinstance(node, ir.Named) and node.kind == "signal":
            value = self.signal_ir.get(node.name)
            return [] if value is None else [value]
        return []

    def _made(self, node: ir.Expr) -> Poly | None:
        parts = [self._polys[id(p)][1] for p in self._parts(node)]
        if isinstance(node, ir.Num):
            return {(): node.value} if node.value else {}
        if isinstance(node, ir.Named) and node.kind == "signal":
            return parts[0] if parts else None
        if isinstance(node, ir.Named) and node.kind == "opaque":  # an argument probed: its own
            return self._atom(("opaque", id(node)))
        if isinstance(node, ir.Named | ir.Read):
            return self._atom((node.kind, node.name) if isinstance(node, ir.Named) else node)
        if any(p is None for p in parts):
            return None
        known = [p for p in parts if p is not None]
        if isinstance(node, ir.Unary) and node.op == "-":
            return {m: -c for m, c in known[0].items()}
        if isinstance(node, ir.Binary) and node.op in ("+", "-"):
            sign = 1.0 if node.op == "+" else -1.0
            return _sum(known[0], {m: sign * c for m, c in known[1].items()})
        if isinstance(node, ir.Binary) and node.op == "*":
            return _product(known[0], known[1])
        if isinstance(node, ir.Binary) and node.op == "/" and _constant(known[1]):
            return {m: c / known[1][()] for m, c in known[0].items()}
        if isinstance(node, ir.Binary) and node.op == "^" and _constant(known[1], _SMALL_POWERS):
            power: Poly | None = {(): 1.0}
            for _ in range(int(known[1].get((), 0.0))):
                power = None if power is None else _product(power, known[0])
            return power
        op = node.op if isinstance(node, ir.Unary | ir.Binary) else getattr(node, "func", "?")
        return self._atom((op, *(tuple(sorted(p.items())) for p in known)))

    def _atom(self, key: object) -> Poly:
        index = self._atoms.setdefault(key, len(self._atoms))
        return {((index, 1),): 1.0}


def _constant(poly: Poly, among: range | None = None) -> bool:
    """Whether ``poly`` is a number other than 0 (and one of ``among``, if given)."""
    if set(poly) != {()}:
        return False
    return among is None or poly[()] in among


def _sum(a: Poly, b: Poly) -> Poly | None:
    out = dict(a)
    for m, c in b.items():
        out[m] = out.get(m, 0.0) + c
        if out[m] == 0.0:
            del out[m]
    return out if len(out) <= MAX_TERMS else None


def _product(a: Poly, b: Poly) -> Poly | None:
    if len(a) * len(b) > MAX_TERMS * MAX_TERMS:
        return None
    out: Poly = {}
    for ma, ca in a.items():
        for mb, cb in b.items():
            powers = dict(ma)
            for atom, n in mb:
                powers[atom] = powers.get(atom, 0) + n
            m = tuple(sorted(powers.items()))
            out[m] = out.get(m, 0.0) + ca * cb
            if out[m] == 0.0:
                del out[m]
    return out if len(out) <= MAX_TERMS else None


def _listed(kind: str, names: list[str]) -> str:
    quoted = [f"'{n}'" for n in dict.fromkeys(names)]
    if len(quoted) == 1:
        return f"{kind} {quoted[0]} is"
    return f"{kind}s {', '.join(quoted[:-1])} and {quoted[-1]} are"
