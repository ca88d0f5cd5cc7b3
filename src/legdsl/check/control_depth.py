"""How deep a controller's expressions are once written out, and the order their signals are
resolved in.

Lets, signals and an action's arguments are written out where they are used, so the
generated code computes a statement as one expression, and sympy, the printers and pickling
walk it recursively: ``MAX_WRITTEN_DEPTH`` bounds it (``written_depth``), and the checker
resolves the signals an expression names before the expression (``signals_used``), so that
a chain of signals is not checked by recursing through all their expressions.
"""

from __future__ import annotations

from collections.abc import Mapping

from legdsl.ir import controller as ir
from legdsl.lang import ast

# How deep an expression may be with its lets, signals and action arguments written out, as
# lowering writes them: 400 levels met Python's recursion limit (a chain of 200 lets
# `x2 = x1 * 1.01 + speed`; the parser's own limit, 120 levels, is for one expression as
# written). 249 compile, run on both backends and go through sweeps' processes and Dask.
MAX_WRITTEN_DEPTH = 250


def written_depth(
    e: ir.Expr, memo: dict[int, tuple[ir.Expr, int]], signal_ir: Mapping[str, ir.Expr | None]
) -> int:
    """Levels of operators of ``e`` with its signals written out, as lowering writes them
    (lets and action arguments are written out in the IR already); remembered per node,
    each built from nodes already measured, so that this costs a step a node."""
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
        memo[id(node)] = (node, 1 + max((memo[id(part)][1] for part in parts), default=0))
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
