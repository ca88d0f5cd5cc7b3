"""``controller B extends A``: A's items with B's own in their places, the rest after them."""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

import pytest

from legdsl.check.source import check_file, check_model
from legdsl.codegen.fingerprints import _clean
from legdsl.ir.controller import Controller
from legdsl.lang.errors import LegError

ROOT = Path(__file__).resolve().parents[2]
CREATURE = (ROOT / "tests" / "bad" / "ctl_dim_comparison.leg").read_text().split("controller")[0]
HOP = """controller hop {
  input speed = 1 m/s
  param kp = 50 N*m/rad
  param kv = 2 N*m*s/rad
  action stiffen(leg) { leg.hip_servo.kp = kp }
  table {
    state FLIGHT on liftoff(main): stiffen(main); hip_servo.kv = kv
    state STANCE on touchdown(main): hip_servo.kp = 0 N*m/rad
  }
}
"""


def _same(a: Controller, b: Controller) -> bool:
    """Equal but for the name and where each part was written."""

    def bare(c: Controller) -> Any:
        return _clean(dataclasses.replace(c, name="x"))  # without its spans

    return bare(a) == bare(b)


def test_a_derived_controller_is_the_one_written_out(tmp_path: Path) -> None:
    derived = tmp_path / "derived.leg"
    derived.write_text(
        CREATURE + HOP + "controller stiff extends hop {\n  param kv = 5 N*m*s/rad\n"
        "  param extra = 1 s\n  action stiffen(leg) { leg.hip_servo.kp = 2 * kp }\n}\n"
    )
    by_hand = tmp_path / "by_hand.leg"
    by_hand.write_text(
        CREATURE
        + HOP.replace("controller hop", "controller stiff")
        .replace("kv = 2 N", "kv = 5 N")
        .replace("kv = 5 N*m*s/rad\n", "kv = 5 N*m*s/rad\n  param extra = 1 s\n")
        .replace("hip_servo.kp = kp }", "hip_servo.kp = 2 * kp }")
    )
    stiff = check_model(derived).controller("stiff")
    # in the base's order, with the derived values; the new one after them
    assert [(c.name, c.value) for c in stiff.params] == [("kp", 50.0), ("kv", 5.0), ("extra", 1.0)]
    assert _same(stiff, check_model(by_hand).controller("stiff"))
    assert not _same(stiff, check_model(derived).controller("hop"))


def test_a_chain_of_bases_and_a_table_of_its_own(tmp_path: Path) -> None:
    path = tmp_path / "chain.leg"
    path.write_text(
        CREATURE + HOP + "controller soft extends hop {\n  param kp = 10 N*m/rad\n}\n"
        "controller softer extends soft {\n  param kv = 1 N*m*s/rad\n  table {\n"
        "    state ONLY on liftoff(main): hip_servo.kv = kv\n  }\n}\n"
    )
    model = check_model(path)
    softer = model.controller("softer")
    assert [(c.name, c.value) for c in softer.params] == [("kp", 10.0), ("kv", 1.0)]
    assert softer.state_names == ("ONLY",)
    assert model.controller("soft").state_names == ("FLIGHT", "STANCE")


def test_the_quadrupeds_pace_is_the_trot_with_its_own_pairs_and_gains() -> None:
    model = check_model(ROOT / "creatures" / "quadruped.leg")
    trot, pace = model.controller("trot"), model.controller("pace")
    assert [c.name for c in trot.params] == [c.name for c in pace.params]
    differ = {a.name for a, b in zip(trot.params, pace.params, strict=True) if a.value != b.value}
    assert {"kp_roll", "kv_roll", "k_side_trim"} <= differ
    assert differ == {"kp_roll", "kv_roll", "k_side_trim", "kp", "kv", "k_speed", "stroke",
                      "leg_k", "leg_b"}  # fmt: skip
    assert trot.state_names == pace.state_names
    assert trot.bindings[0] != pace.bindings[0]


TWO_CREATURES = """\
creature a { planar body b free { mass 1 kg inertia 1 kg*m^2 }
  body c on b via revolute j { mass 1 kg inertia 1 kg*m^2 }  actuator s on j servo(kp = 1 N*m/rad) }
creature z { planar body b free { mass 1 kg inertia 1 kg*m^2 }
  body c on b via prismatic j { mass 1 kg inertia 1 kg*m^2 }  actuator s on j servo(kp = 1 N/m) }
controller c for a { table { state A on time > 0 s: s.setpoint = 1 deg } }
controller c for z { table { state A on time > 0 s: s.setpoint = 1 cm } }
"""


def test_two_creatures_may_each_have_a_controller_of_one_name(tmp_path: Path) -> None:
    """Each is its own controller (the second was taken for the first: 'defined twice',
    reported twice, at the first)."""
    path = tmp_path / "two.leg"
    path.write_text(TWO_CREATURES)
    models = {m.name: m for m in check_file(path)}
    assert [c.name for c in models["a"].controllers] == ["c"]
    assert [c.name for c in models["z"].controllers] == ["c"]


def test_a_controller_defined_twice_is_reported_at_the_second(tmp_path: Path) -> None:
    path = tmp_path / "twice.leg"
    path.write_text(CREATURE + HOP + "\n" + HOP.replace("hip_servo.kv = kv", "hip_servo.kv = x"))
    with pytest.raises(LegError) as info:
        check_file(path)
    second = CREATURE.count("\n") + HOP.count("\n") + 2
    messages = [(d.span.line, d.message) for d in info.value.diagnostics]
    first = f"{path}:{CREATURE.count(chr(10)) + 1}:12"
    assert (second, f"controller 'hop' is defined twice (first at {first})") in messages


def test_a_controller_extends_the_base_of_its_own_creature(tmp_path: Path) -> None:
    """With a controller 'c' for each creature, 'd for z extends c' is z's c (it took a's)."""
    path = tmp_path / "two.leg"
    path.write_text(
        TWO_CREATURES.replace("1 deg } }", "1 deg } param k = 1 s }").replace(
            "1 cm } }", "1 cm } param k = 2 s }"
        )
        + "controller d for z extends c { param extra = 1 m }\n"
    )
    d = {m.name: m for m in check_file(path)}["z"].controller("d")
    assert [(p.name, p.value) for p in d.params] == [("k", 2.0), ("extra", 1.0)]


def test_a_base_of_two_creatures_without_for_is_ambiguous(tmp_path: Path) -> None:
    path = tmp_path / "two.leg"
    path.write_text(TWO_CREATURES + "controller d extends c { }\n")
    with pytest.raises(LegError) as info:
        check_file(path)
    assert [d.message for d in info.value.diagnostics] == [
        "creatures a, z each have a controller 'c'; say which one to extend with "
        "'controller d for CREATURE extends c'"
    ]


def test_the_base_for_its_creature_is_preferred_to_one_for_none(tmp_path: Path) -> None:
    """'c' without 'for' (a mistake in a file of two creatures) is not z's 'c': d's table is
    z's c's, in cm, not the other's in degrees (a unit mistake on z's slide)."""
    path = tmp_path / "two.leg"
    text = TWO_CREATURES.replace("controller c for a", "controller c")
    path.write_text(text + "controller d for z extends c { }\n")
    with pytest.raises(LegError) as info:
        check_file(path)
    (only,) = info.value.diagnostics
    assert only.message.startswith("this file has several creatures (a, z)")


def test_a_derived_controllers_include_beats_its_base_and_its_own_items_beat_both(
    tmp_path: Path,
) -> None:
    """``controller e extends hop { include more }``: the include is e's own text, so more's
    kp replaces hop's (in the include's place); a kp e writes itself beats both."""
    path = tmp_path / "derived.leg"
    more = "shared more {\n  param kp = 70 N*m/rad\n  param extra = 1 s\n}\n"
    path.write_text(
        CREATURE + HOP + more + "controller e extends hop {\n  include more\n}\n"
        "controller f extends hop {\n  include more\n  param kp = 90 N*m/rad\n}\n"
    )
    models = check_model(path)
    params = {c: [(p.name, p.value) for p in models.controller(c).params] for c in "ef"}
    assert params["e"] == [("kv", 2.0), ("kp", 70.0), ("extra", 1.0)]
    assert params["f"] == [("kv", 2.0), ("kp", 90.0), ("extra", 1.0)]
    assert [(p.name, p.value) for p in models.controller("hop").params] == [
        ("kp", 50.0), ("kv", 2.0),
    ]  # fmt: skip
