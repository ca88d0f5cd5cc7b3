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


def test_a_controller_that_extends_the_tuned_one_keeps_its_values(tmp_path: Path) -> None:
    """Tuning `run` retuned `fast` and `quick` (they extend it, taking its kp and lead) with no
    note: the tuned file changed run's declarations, which they take. An outside user's
    `controller flip extends run` ran the tuned k_speed, never scored by the tune."""
    source = knee_file(tmp_path)
    model = check_model(source)
    out = write_tuned(source, model.controller("run"), {"kp": 600.0, "lead": 0.2},
                      tmp_path / "out" / "k.leg", model.controllers)  # fmt: skip
    assert params(out, "run")["kp"] == pytest.approx(600.0)
    assert params(out, "run")["lead"] == pytest.approx(0.2)
    assert params(out, "fast") == params(source, "fast")
    assert params(out, "quick") == params(source, "quick")  # its own lead, run's kp kept
    quick = out.read_text().partition("controller quick")[2]
    assert "param kp = 510 N*m/rad" in quick and quick.count("param lead") == 1  # its own


def test_a_controller_named_as_another_creatures_is_tuned_in_its_own_body(tmp_path: Path) -> None:
    """An outside user's file of two creatures, each with its `controller hop for ...`: tuning
    heavy's kp added `param kp` to both controllers named hop (the first taken as the tuned
    one), and the tuned file, kp declared twice in each, did not load."""
    head, _, control = (ROOT / "creatures" / "hopper.leg").read_text().partition("controller hop {")
    body = head[head.index("creature hopper") :].replace("creature hopper", "creature heavy")
    source = tmp_path / "two.leg"
    source.write_text(f"{head}{body}controller hop for hopper {{{control}\n"
                      f"controller hop for heavy {{{control}")  # fmt: skip
    model = check_model(source, "heavy")
    out = write_tuned(source, model.controller("hop"), {"kp": 162.5}, tmp_path / "out" / "two.leg",
                      model.controllers)  # fmt: skip
    kp = {c: check_model(out, c).controller("hop").params for c in ("hopper", "heavy")}
    assert {p.name: p.value for p in kp["heavy"]}["kp"] == 162.5
    assert {p.name: p.value for p in kp["hopper"]}["kp"] == 150.0
    assert out.read_text().count("param kp") == source.read_text().count("param kp")
