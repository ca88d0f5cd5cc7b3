"""A controller extending a used file's controller is compiled as one of its own file:
tests/good/outside/dachs_extends.leg (its trot ``extends`` the shipped quadruped's) gives
the controllers of dachs.leg (its trot a copy of that table, with dachs's values)."""

from __future__ import annotations

from conftest import OUTSIDE, outside_session

from legdsl.pipeline.compile import compile_model
from legdsl.sim.run_loop import RunOptions


def _code(text: str) -> str:
    """A generated module without the lines that name where in a .leg file a thing was."""
    return "\n".join(line for line in text.splitlines() if ".leg" not in line)


def test_a_trot_extending_the_used_quadrupeds_is_dachss_copied_trot() -> None:
    extended = compile_model(OUTSIDE / "dachs_extends.leg")
    copied = compile_model(OUTSIDE / "dachs.leg")
    assert [name for name, _ in extended.files] == [name for name, _ in copied.files]
    controls = [name for name, _ in copied.files if name.startswith("control_")]
    assert {"control_trot.py", "control_trot.c", "control_pace.py"} <= set(controls)
    for name in controls:
        assert _code(extended.text(name)) == _code(copied.text(name)), name
    # its values are dachs's, its parameters' order the shipped trot's
    params = {p.name: p.value for p in extended.model.controller("trot").params}
    assert params["leg_k"] == 5946.19 and params["k_path"] == 1.0


def test_dachs_extends_runs() -> None:
    session = outside_session("dachs_extends.leg")
    result = session.run("trot", [], options=RunOptions(duration=0.4)).result
    assert result.status == "ok", result.message
    assert result.sim_time >= 0.39
