"""legdsl tune on a controller that extends another, with no item on a line of its own."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.api.tuned_file import write_tuned
from legdsl.check.source import check_model

ROOT = Path(__file__).resolve().parents[2]
KNEE = ROOT / "tests" / "good" / "outside" / "knee_biped.leg"

EXTENDED = """
controller fast extends run {
}
controller quick extends run { param lead = 0.12 s }
"""


def knee_file(tmp_path: Path) -> Path:
    """The outside knee biped with two controllers that extend its run: one with an empty body,
    one written on a single line (its `use` made absolute, so the copy finds biped.leg)."""
    text = KNEE.read_text().replace(
        'use "../../../creatures/biped.leg"', f'use "{ROOT / "creatures" / "biped.leg"}"'
    )
    source = tmp_path / "knee.leg"
    source.write_text(text + EXTENDED)
    return source


def params(path: Path, controller: str) -> dict[str, float]:
    return {p.name: p.value for p in check_model(path).controller(controller).params}


@pytest.mark.parametrize("name", ["fast", "quick"])
def test_an_inherited_parameter_is_overridden_when_the_body_has_no_item_line(
    tmp_path: Path, name: str
) -> None:
    """Tuning kp of `fast` (an empty body) or `quick` (its body on the controller's line)
    changed kp in `run`'s declaration instead: the tuned file's run changed too, unsaid."""
    source = knee_file(tmp_path)
    controller = check_model(source).controller(name)
    out = write_tuned(source, controller, {"kp": 600.0, "lead": 0.2}, tmp_path / "out" / "k.leg")
    assert params(out, name)["kp"] == pytest.approx(600.0)
    assert params(out, name)["lead"] == pytest.approx(0.2)
    assert params(out, "run") == params(source, "run")  # the controller extended is as it was
    others = {"fast": "quick", "quick": "fast"}[name]
    assert params(out, others) == params(source, others)
