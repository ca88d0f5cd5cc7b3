"""A long chain's velocities: a sum over every coordinate is built once, not re-sorted each
time a term is added (cubic in the chain's length: an 80-link snake spent seconds there)."""

from __future__ import annotations

from types import SimpleNamespace

import pytest
from sympy import Add, Symbol

from legdsl.lower import symbolic
from legdsl.lower.straightline import Block


def test_a_velocity_sums_its_terms_at_once(monkeypatch: pytest.MonkeyPatch) -> None:
    n = 60
    v = [Symbol(f"v{k}") for k in range(n)]
    cols = [(Symbol(f"a{k}"), Symbol(f"b{k}"), Symbol(f"c{k}")) for k in range(n)]
    sums = 0
    flatten = Add.flatten.__func__  # type: ignore[attr-defined]

    def counted(cls: type, seq: list[object]) -> object:
        nonlocal sums
        sums += 1
        return flatten(cls, seq)

    monkeypatch.setattr(Add, "flatten", classmethod(counted))
    tree = SimpleNamespace(block=Block())
    out = symbolic._times(cols, v, tree)  # type: ignore[arg-type]
    monkeypatch.undo()
    assert sums <= 3  # one sum per component; was one per term (180)
    assigned = {st.target: st.value for st in tree.block._statements}
    for k in range(3):
        assert assigned[out[k]] == Add(*(c[k] * x for c, x in zip(cols, v, strict=True)))
