"""Python and C name a clashing local differently (a param 'err', 'sin', 'int', 'out' or
'double' stays so in control_CONTROLLER.py and is 'err_' ... in control_CONTROLLER.c), and
docs/compiler.md did not say so. It says the rule now; its examples are what the C printer
does."""

from __future__ import annotations

from pathlib import Path

from legdsl.codegen.c.printer import c_spellings
from legdsl.lower.straightline import python_name

DOC = Path(__file__).resolve().parents[2] / "docs" / "compiler.md"


def test_the_docs_rule_for_names_is_the_printers() -> None:
    doc = " ".join(DOC.read_text(encoding="utf-8").split())
    assert "**Names in the two prints.**" in doc
    assert "A param `err` is so `err` in `control_hop.py` and `err_` in `control_hop.c`" in doc
    names = ["int", "int_", "err", "out", "double", "sin", "NAN", "leg_min", "_Bool", "M_PI", "x"]
    spelled = c_spellings(names)
    assert spelled == {
        "int": "int_2", "err": "err_", "out": "out_", "double": "double_", "sin": "sin_",
        "NAN": "NAN_", "leg_min": "leg_min_", "_Bool": "u_Bool", "M_PI": "uM_PI",
    }  # fmt: skip
    for python, c in [("err", "err_"), ("sin", "sin_"), ("_Bool", "u_Bool"), ("M_PI", "uM_PI")]:
        assert f"`{c}`" in doc and python_name(python, set()) == python
    assert python_name("lambda", set()) == "lambda_" and "`lambda_`" in doc
