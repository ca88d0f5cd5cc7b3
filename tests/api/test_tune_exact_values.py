"""legdsl tune writes the tuned values so that the tuned file reads back the very values run."""

from __future__ import annotations

from pathlib import Path

from legdsl.api.tuned_file import write_tuned
from legdsl.check.source import check_model

ROOT = Path(__file__).resolve().parents[2]
KNEE = ROOT / "tests" / "good" / "outside" / "knee_biped.leg"

# a tune's best of the knee biped at 1 and 1.5 m/s, as CMA-ES gave them (SI)
BEST = {
    "k_speed": 0.08308379022695211,  # written in s
    "kp": 417.30946496423945,  # N*m/rad
    "stand": -0.9189678255187148,  # deg: read back as float(text) * pi / 180
    "balance": 3.6557487225168295,  # a bare number
}


def test_the_tuned_file_holds_the_tuned_values_exactly(tmp_path: Path) -> None:
    """The values were written to 6 digits: the tuned file ran at 1.5 m/s with a pitch of
    5.839 deg where the tune's best had 5.759 (another gait; for a legged gait, perhaps a
    fall where the tune measured none)."""
    out = tmp_path / "knee_biped.leg"
    write_tuned(KNEE, check_model(KNEE).controller("run"), BEST, out)
    tuned = {p.name: p.value for p in check_model(out).controller("run").params}
    assert {name: tuned[name] for name in BEST} == BEST  # exactly, bit for bit
    text = out.read_text()
    assert "param kp = 417.30946496423945 N*m/rad" in text  # the unit written is kept
    assert " deg " in text.split("param stand = ")[1].split("\n")[0] + " "


def test_a_value_kept_is_written_as_short_as_before(tmp_path: Path) -> None:
    """The file's own values, kept where nothing beat them, stay as the file wrote them."""
    out = tmp_path / "knee_biped.leg"
    controller = check_model(KNEE).controller("run")
    own = {p.name: p.value for p in controller.params if p.name in BEST}
    write_tuned(KNEE, controller, own, out)
    text = out.read_text()
    assert "param stand = -52 deg" in text and "param kp = 510 N*m/rad" in text
    assert "param balance = 2.4\n" in text


def test_a_parameter_of_a_used_file_is_named_with_that_file_plainly() -> None:
    """The refusal (now the note that it is overridden) named
    'tests/good/outside/../../../creatures/biped.leg'."""
    from legdsl.api.tuned_file import declared_in, used_owners

    spans = declared_in(KNEE, check_model(KNEE).controller("run"), ["k_trim"])
    assert used_owners(KNEE, spans) == {"k_trim": str(ROOT / "creatures" / "biped.leg")}
