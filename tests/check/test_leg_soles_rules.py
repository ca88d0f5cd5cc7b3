"""A leg that stands on several contacts, ``foot sole, heel``: the first is its foot point,
all are its soles. Each listed contact must exist, be listed once, be the sole of one leg
and sit on the first one's body; each mistake is a file:line:col error that says the fix.
The leg's clock (what touchdown(leg) and liftoff(leg) read) follows all its soles."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.cli import main
from legdsl.pipeline.session import RunSession

TWO_LEGS = """
creature flat {
  planar
  gravity 9.81 m/s^2
  body trunk free { mass 10 kg  inertia 0.1 kg*m^2  initial z = 0.6 m }
  body shank on trunk via prismatic leg { length 0.5 m  mass 0.5 kg  inertia 0.01 kg*m^2 }
  body foot on shank via revolute ankle at tip {
    direction (1, 0)  length 0.1 m  mass 0.2 kg  inertia 0.001 kg*m^2
  }
  body shank2 on trunk via prismatic leg2 { length 0.5 m  mass 0.5 kg  inertia 0.01 kg*m^2 }
  contact toe on foot at tip
  contact heel on foot at (-0.05 m, 0 m)
  contact knee on shank at (0 m, -0.2 m)
  contact tip2 on shank2 at tip
  leg main { joints leg, ankle  foot FEET }
  leg other { joints leg2  foot OTHER }
  ground { normal spring(k = 1e4 N/m, b = 100 N*s/m)  tangent spring(k = 1e4 N/m, b = 100 N*s/m) }
}
"""


def _check(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], feet: str, other: str = "tip2"
) -> tuple[int, str, Path]:
    src = tmp_path / "flat.leg"
    src.write_text(TWO_LEGS.replace("FEET", feet).replace("OTHER", other), encoding="utf-8")
    code = main(["check", str(src)])
    return code, capsys.readouterr().err, src


def test_a_leg_lists_its_soles_foot_first(tmp_path: Path) -> None:
    src = tmp_path / "flat.leg"
    src.write_text(TWO_LEGS.replace("FEET", "toe, heel").replace("OTHER", "tip2"), "utf-8")
    model = RunSession.from_file(src, generated=tmp_path / "gen").model
    main_leg, other = model.legs
    assert (main_leg.foot, main_leg.soles, main_leg.more_soles) == (
        "toe",
        ("toe", "heel"),
        ("heel",),
    )
    assert (other.foot, other.soles) == ("tip2", ("tip2",))


def test_an_unknown_sole_is_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code, err, src = _check(tmp_path, capsys, "toe, hele")
    assert code == 2
    assert f"{src}:15:43: error: unknown contact 'hele'" in err and "did you mean 'heel'" in err


def test_a_sole_listed_twice_is_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code, err, src = _check(tmp_path, capsys, "toe, heel, toe")
    assert code == 2
    assert (
        f"{src}:15:49: error: contact 'toe' is listed twice in the foot of leg 'main'; list it once"
        in err
    )


def test_a_sole_of_two_legs_is_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code, err, src = _check(tmp_path, capsys, "toe, heel", other="tip2, heel")
    assert code == 2
    assert f"{src}:16:39: error: contact 'heel' is already a foot contact of leg 'main'" in err
    assert "a contact is the sole of one leg" in err


def test_a_sole_on_another_body_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code, err, src = _check(tmp_path, capsys, "toe, knee")
    assert code == 2
    assert (
        f"{src}:15:43: error: contact 'knee' is on 'shank', not on 'foot' with the foot 'toe': "
        "the soles of a leg are on one foot body (declare 'knee' on 'foot' or leave it out of "
        "the foot)"
    ) in err


def test_show_lists_the_soles(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    src = tmp_path / "flat.leg"
    src.write_text(TWO_LEGS.replace("FEET", "toe, heel").replace("OTHER", "tip2"), "utf-8")
    assert main(["show", str(src)]) == 0
    assert "main: joints leg, ankle; foot toe, heel;" in capsys.readouterr().out


def test_the_leg_clock_runs_from_the_first_sole_down_to_the_last_up(tmp_path: Path) -> None:
    """touching, stance_time and flight_time of a leg on toe and heel: down at the heel strike,
    up when the last sole leaves; a contact's own clock keeps its own times."""
    from types import SimpleNamespace

    from legdsl.sim.sensors import Sensors

    src = tmp_path / "flat.leg"
    src.write_text(TWO_LEGS.replace("FEET", "toe, heel").replace("OTHER", "tip2"), "utf-8")
    model = RunSession.from_file(src, generated=tmp_path / "gen").model
    sensors = Sensors(model)
    names = [c.name for c in model.contacts]
    sim = SimpleNamespace()
    keys = ["leg.main.touching", "leg.main.stance_time", "leg.main.flight_time"]
    # (t, contacts down): heel strike, toe down, heel up, toe up, heel strike again
    for t, down in [(0.0, ()), (0.1, ("heel",)), (0.12, ("heel", "toe")), (0.2, ("toe",)),
                    (0.3, ()), (0.6, ("heel",))]:  # fmt: skip
        sensors.observe(t, [n in down for n in names])
        if t == 0.2:
            assert sensors.read(sim, keys)["leg.main.touching"] == 1.0
    assert sensors.leg_clocks["main"].touchdown == 0.6
    assert sensors.read(sim, keys) == {
        "leg.main.touching": 1.0,
        "leg.main.stance_time": pytest.approx(0.3 - 0.1),
        "leg.main.flight_time": pytest.approx(0.6 - 0.3),
    }
    assert sensors.clocks["toe"].stance == pytest.approx(0.3 - 0.12)
