"""How deep a controller's expressions are once written out, and the order their signals are
resolved in.

Lets, signals and an action's arguments are written out where they are used, so the
generated code computes a statement as one expression, and sympy, the printers and pickling
walk it recursively: ``MAX_WRITTEN_DEPTH`` bounds it (``written_depth``), and
``MAX_WRITTEN_SIZE`` its size, each use of a let or signal a copy (``written_size``); the checker
resolves the signals an expression names before the expression (``signals_used``), so that
a chain of signals is not checked by recursing through all their expressions.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

from legdsl.ir import controller as ir
from legdsl.lang import ast

# How deep an expression may be with its lets, signals and action arguments written out, as
# lowering writes them: 400 levels met Python's recursion limit (a chain of 200 lets
# `x2 = x1 * 1.01 + speed`; the parser's own limit, 120 levels, is for one expression as
# written). 249 compile, run on both backends and go through sweeps' processes and Dask.
MAX_WRITTEN_DEPTH = 250

# How many operators and values a statement may have once written out: a let or signal used
# twice is written out twice, so a chain of lets each using the one before twice doubles at
# every let, and sympy, the printers and the fingerprints walk every copy (16 lets squaring
# the last, some 260,000, took 3 s to check, and each two more lets tripled it). The shipped
# creatures' largest is some 1,200.
MAX_WRITTEN_SIZE = 20_000

# How many actions may be called one within another: the IR nests each call's statements in
# the caller's, and the fingerprints, lowering and pickling walk them recursively, each call
# several levels (250 met Python's recursion limit, 200 passed; an expression 250 deep at
# the bottom of 50 compiles and runs). The standard library nests 3.
MAX_ACTION_DEPTH = 50


def written_too_large(
    e: ir.Expr,
    depths: dict[int, tuple[ir.Expr, int]],
    sizes: dict[int, tuple[ir.Expr, int]],
    signal_ir: Mapping[str, ir.Expr | None],
) -> str | None:
    """Why ``e``, written out, is too deep or too large for the later stages (None if not);
    ``depths`` and ``sizes`` remember the measures of the nodes seen."""
    depth = written_depth(e, depths, signal_ir)
    if depth > MAX_WRITTEN_DEPTH:
        return (
            f"written out with the lets, signals and action arguments it uses, this is "
            f"{depth} levels of operators deep (more than {MAX_WRITTEN_DEPTH}): the "
            "generated code would compute it as one expression that deep; compute it in "
            "fewer steps"
        )
    size = written_size(e, sizes, signal_ir)
    if size > MAX_WRITTEN_SIZE:
        return (
            f"written out with the lets, signals and action arguments it uses, this is "
            f"{size:,} operators and values (more than {MAX_WRITTEN_SIZE:,}): each use of a "
            "let or signal is a copy of it in the generated code; use each fewer times "
            "(x ^ 2 for x * x) or compute it in fewer steps"
        )
    return None


def written_depth(
    e: ir.Expr, memo: dict[int, tuple[ir.Expr, int]], signal_ir: Mapping[str, ir.Expr | None]
) -> int:
    """Levels of operators of ``e`` with its signals written out, as lowering writes them
    (lets and action arguments are written out in the IR already)."""
    return _written(e, memo, signal_ir, lambda parts: 1 + max(parts, default=0))


def written_size(
    e: ir.Expr, memo: dict[int, tuple[ir.Expr, int]], signal_ir: Mapping[str, ir.Expr | None]
) -> int:
    """Operators and values of ``e`` with its lets and signals written out: a let used twice
    counts twice, as sympy, the printers and the fingerprints walk it."""
    return _written(e, memo, signal_ir, lambda parts: 1 + sum(parts))


def _written(
    e: ir.Expr,
    memo: dict[int, tuple[ir.Expr, int]],
    signal_ir: Mapping[str, ir.Expr | None],
    combine: Callable[[list[int]], int],
) -> int:
    """``combine`` of the measures of ``e``'s parts, remembered per node, each built from
    nodes already measured, so that this costs a step a node however often one is used."""
    stack = [e]
    while stack:
        node = stack[-1]
        if id(node) in memo:
            stack.pop()
            continue
        parts: list[ir.Expr] = []
        if isinstance(node, ir.Unary):
            parts = [node.operand]
        elif isinstance(node, ir.Binary):
            parts = [node.left, node.right]
        elif isinstance(node, ir.Call):
            parts = list(node.args)
        elif isinstance(node, ir.Named) and node.kind == "signal":
            parts = [v] if (v := signal_ir.get(node.name)) is not None else []
        waiting = [part for part in parts if id(part) not in memo]
        if waiting:
            stack += waiting
            continue
        stack.pop()  # the node itself kept too, so that its id is not reused meanwhile
        memo[id(node)] = (node, combine([memo[id(part)][1] for part in parts]))
    return memo[id(e)][1]


def signals_used(
    e: ast.Expr, signals: Mapping[str, object], local: Mapping[str, object]
) -> list[str]:
    """The signals ``e`` names (not those a local name hides), in the order the checker meets
    them: resolved before ``e`` is checked, each from the top of the stack rather than from
    within ``e`` and the signals that name it, a chain of signals is checked without
    recursing through their expressions (a chain of some 85 met Python's recursion limit)."""
    found: list[str] = []
    stack: list[ast.Expr] = [e]
    while stack:
        node = stack.pop()
        if isinstance(node, ast.EName):
            name = node.ident.name
            if name in signals and name not in local and name not in found:
                found.append(name)
        elif isinstance(node, ast.EAttr):
            stack.append(node.base)
        elif isinstance(node, ast.EUnary):
            stack.append(node.operand)
        elif isinstance(node, ast.EBinary):
            stack += [node.right, node.left]
        elif isinstance(node, ast.ECall):
            stack += reversed(node.args)
    return found
