"""A controller extending a used file's controller is compiled as one of its own file:
tests/good/outside/dachs_extends.leg (its trot ``extends`` the shipped quadruped's) gives
the controllers of dachs.leg (its trot a copy of that table, with dachs's values)."""

from __future__ import annotations

from pathlib import Path

from conftest import OUTSIDE, outside_session

from legdsl.check.source import check_model
from legdsl.codegen.manifest import source_label
from legdsl.ir.model import Model
from legdsl.pipeline.compile import controller_files
from legdsl.sim.run_loop import RunOptions


def _code(text: str) -> str:
    """A generated module without the lines that name where in a .leg file a thing was."""
    return "\n".join(line for line in text.splitlines() if ".leg" not in line)


def controller_modules(path: Path) -> tuple[Model, dict[str, str]]:
    """The model and its controllers' generated modules (the dynamics are not lowered: the
    creature is dachs in both files)."""
    model = check_model(path)
    modules = {}
    for controller in model.controllers:
        _, text, c_text = controller_files(model, controller, source_label(path))
        modules |= {f"control_{controller.name}.py": text, f"control_{controller.name}.c": c_text}
    return model, modules


def test_a_trot_extending_the_used_quadrupeds_is_dachss_copied_trot() -> None:
    extended, extended_modules = controller_modules(OUTSIDE / "dachs_extends.leg")
    copied, copied_modules = controller_modules(OUTSIDE / "dachs.leg")
    assert list(extended_modules) == list(copied_modules)
    assert {"control_trot.py", "control_trot.c", "control_pace.py"} <= set(copied_modules)
    for name, text in copied_modules.items():
        assert _code(extended_modules[name]) == _code(text), name
    # its values are dachs's, its parameters' order the shipped trot's
    params = {p.name: p.value for p in extended.controller("trot").params}
    assert params["leg_k"] == 5946.19 and params["k_path"] == 1.0


def test_dachs_extends_runs() -> None:
    session = outside_session("dachs_extends.leg")
    result = session.run("trot", [], options=RunOptions(duration=0.4)).result
    assert result.status == "ok", result.message
    assert result.sim_time >= 0.39
