"""A control law that failed in a standard-library action was told at this machine's copy of
it ('... at /work/main/src/legdsl/stdlib/raibert.leg:145:3 (inlined from the action called at
hopper5.leg:87:69)'); docs/compiler.md shows the library as stdlib/NAME, the same on every
machine, as the generated code and the checker's messages do."""

from __future__ import annotations

from legdsl.check.values import STDLIB
from legdsl.lang.errors import Span
from legdsl.lower.control import EachPass
from legdsl.sim.control_faults import _where


def test_a_failure_in_the_standard_library_names_it_as_stdlib() -> None:
    inside = Span(str((STDLIB / "raibert.leg").resolve()), 145, 3, 145, 20)
    call = Span("hopper5.leg", 87, 69, 87, 80)
    each = EachPass(Span(str((STDLIB / "raibert.leg").resolve()), 10, 3, 10, 9), "m#1", "fl")
    told = _where((inside, call))
    assert told == "stdlib/raibert.leg:145:3 (inlined from the action called at hopper5.leg:87:69)"
    assert _where((inside, each)) == (
        "stdlib/raibert.leg:145:3 (for m = fl in the each at stdlib/raibert.leg:10:3)"
    )
