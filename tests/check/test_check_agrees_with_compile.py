"""``legdsl check`` and ``legdsl compile`` cannot disagree: whatever checks also lowers.

The checker resolves every name of a controller once, into the controller IR, and
lowering reads only that IR; so a file that passes ``check`` must lower and print every
controller without any error. Run over every good file, every shipped creature and the
mutants of the front end's property test (which reach the controller checker's corners).
"""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings

from legdsl.check.source import check_file
from legdsl.cli import main
from legdsl.codegen.python.control import render_control
from legdsl.lang.errors import LegError
from legdsl.lower.control import lower_controller
from legdsl.pipeline.compile import compile_file
from tests.lang.test_mutants import mutants

ROOT = Path(__file__).resolve().parents[2]
# the shipped creatures' controllers are lowered and printed by tests/codegen/test_goldens.py
FILES = [ROOT / "tests" / "good" / "hopper.leg"]  # actions.leg, beside it, has no creature


def compile_controllers(path: Path) -> int:
    """Check ``path``, then lower and print every controller; the number printed."""
    printed = 0
    for model in check_file(path):
        for controller in model.controllers:
            lowered = lower_controller(model, controller)
            events = {s.name: s.event_text for s in controller.states}
            assert render_control(lowered, path.name, events, "0" * 16)
            printed += 1
    return printed


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.name)
def test_every_good_file_compiles(path: Path) -> None:
    assert compile_controllers(path) >= 1


@settings(
    max_examples=15,  # each mutant that checks is lowered and printed: about a second each
    derandomize=True,
    database=None,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)
@given(text=mutants)
def test_a_mutant_that_checks_compiles(tmp_path_factory: pytest.TempPathFactory, text: str) -> None:
    workdir = tmp_path_factory.getbasetemp() / "agree"
    workdir.mkdir(exist_ok=True)
    (workdir / "actions.leg").write_text((ROOT / "tests/good/actions.leg").read_text())
    path = workdir / "mutant.leg"
    path.write_bytes(text.encode("utf-8"))
    try:
        check_file(path)
    except LegError:
        return  # rejected by check: nothing to compile
    compile_controllers(path)


def test_what_sympy_makes_infinite_is_an_error_at_its_line(tmp_path: Path) -> None:
    """The checker refuses constants with no finite value (``2 ^ 2000``); a product that only
    sympy folds (``x * 1e300 * 1e300``) or a division by a difference that is always 0 is
    lowering's error, at the line, with the line shown (it was ``inf`` in the generated code:
    a NameError in Python, a C compile error, both internal errors). So is one inside min, max,
    clamp or a comparison, which sympy refused with an internal error ('zoo' is not comparable),
    and so is one there that sympy knows is never real."""
    text = (ROOT / "tests" / "bad" / "ctl_constant_without_value.leg").read_text()
    zero = "(exp(log(trunk.z / 1 m)) * 1 m - trunk.z)"  # its terms cancel in sympy alone
    for value in (
        "trunk.pitch * 1e300 * 1e300",
        f"trunk.pitch * trunk.z / {zero}",
        f"min(1 rad * trunk.z / {zero}, trunk.pitch)",
        f"clamp(1 rad / ({zero} / 1 m), -1 rad, 1 rad)",
        f"select(trunk.z / {zero} > 0, 1 rad, 0 rad)",
        "max(1 rad * sqrt(min(trunk.z / 1 m, -1)), trunk.pitch)",  # never real
        "select(sqrt(min(trunk.z / 1 m, -1)) > 0, 1 rad, 0 rad)",
    ):
        table = "table {\n    state A on time > 0 s: hip_servo.setpoint = " + value + "\n  }"
        path = tmp_path / "c.leg"
        path.write_text(text.split("controller c {")[0] + "controller c {\n  " + table + "\n}\n")
        with pytest.raises(LegError) as info:
            compile_file(path)
        (d,) = info.value.diagnostics
        assert (d.span.line, d.span.col) == (11, 28)
        assert "no finite real number" in d.message
        assert "hip_servo.setpoint = " + value[:60] in info.value.render()  # (a long line cut)


def test_legdsl_check_refuses_what_only_sympy_sees(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """``legdsl check`` lowers the controllers too (the checker alone accepted a division by
    a difference that is always 0, which compile then refused), at the line, exit 2. (The
    checker finds terms that cancel as written, as in ``trunk.z - trunk.z``; sympy also
    knows that ``exp(log(x))`` is ``x``.)"""
    text = (ROOT / "tests" / "bad" / "ctl_constant_without_value.leg").read_text()
    zero = "(exp(log(trunk.z / 1 m)) * 1 m - trunk.z)"
    table = (
        f"table {{\n    state A on time > 0 s: hip_servo.setpoint = 1 rad * trunk.z / {zero}\n  }}"
    )
    path = tmp_path / "c.leg"
    path.write_text(text.split("controller c {")[0] + "controller c {\n  " + table + "\n}\n")
    check_file(path)  # the checker alone sees nothing wrong
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err
    assert f"{path}:11:28: error: this gives no finite real number" in err
    assert "Traceback" not in err


def test_a_whole_constant_power_written_as_a_sum_or_a_function(tmp_path: Path) -> None:
    """A constant exponent that leaves whole powers of the units is taken however it is
    written (``x ^ (1 + 1)``, ``x ^ abs(-2)``), not only as a number or a product, and the
    power lowers to the square it is."""
    text = (ROOT / "tests" / "bad" / "ctl_constant_without_value.leg").read_text()
    for exponent in ("(1 + 1)", "(3 - 1)", "abs(-2)", "(4 / 2)", "max(2, 1)"):
        value = f"1 rad * (trunk.z ^ {exponent}) / 1 m^2"
        table = "table {\n    state A on time > 0 s: hip_servo.setpoint = " + value + "\n  }"
        path = tmp_path / "p.leg"
        path.write_text(text.split("controller c {")[0] + "controller c {\n  " + table + "\n}\n")
        (model,) = check_file(path)
        lowered = lower_controller(model, model.controllers[0])
        printed = render_control(lowered, path.name, {"A": "x"}, "0" * 16)
        assert "hip_servo_setpoint = body_trunk_z*body_trunk_z" in printed
    path.write_text(path.read_text().replace("max(2, 1)", "(1 + 0.5)"))
    with pytest.raises(LegError, match="whole powers"):
        check_file(path)
