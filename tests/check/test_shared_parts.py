"""Shared controller parts: declarations several controllers include, overridden in place."""

from __future__ import annotations

from pathlib import Path

from legdsl.check.source import check_model

ROOT = Path(__file__).resolve().parents[2]
CREATURE = (ROOT / "tests" / "bad" / "ctl_dim_comparison.leg").read_text().split("controller")[0]
TABLE = "  table {\n    state FLIGHT on liftoff(main): hip_servo.kp = kp; hip_servo.kv = kv\n  }\n"


def test_an_override_keeps_the_parts_order_and_takes_the_controllers_value(
    tmp_path: Path,
) -> None:
    path = tmp_path / "hopper.leg"
    path.write_text(
        "shared gains {\n  param kp = 50 N*m/rad\n  param kv = 2 N*m*s/rad\n}\n"
        + CREATURE
        + "controller soft {\n  include gains\n"
        + TABLE
        + "}\n"
        + "controller stiff {\n  param extra = 1 s\n  include gains\n"
        "  param kp = 80 N*m/rad\n" + TABLE + "}\n"
    )
    model = check_model(path)
    soft, stiff = model.controller("soft"), model.controller("stiff")
    assert [(c.name, c.value) for c in soft.params] == [("kp", 50.0), ("kv", 2.0)]
    # in the part's place (after 'extra', where the include stands), with the new value
    assert [(c.name, c.value) for c in stiff.params] == [("extra", 1.0), ("kp", 80.0), ("kv", 2.0)]
    assert stiff.params[1].span.line > soft.params[0].span.line  # the override's own line


def test_parts_come_through_use_and_file_level_actions_are_checked_where_called(
    tmp_path: Path,
) -> None:
    (tmp_path / "gains.leg").write_text(
        "shared gains {\n  param kp = 50 N*m/rad\n  param kv = 2 N*m*s/rad\n"
        "  action stiffen(leg) { leg.spring.k = k_leg }\n}\n"
    )
    path = tmp_path / "hopper.leg"
    # 'stiffen' reads k_leg, which only 'hop' has: 'idle' never calls it, so it is not an error
    path.write_text(
        'use "gains.leg"\n'
        + CREATURE
        + "controller hop {\n  include gains\n  param k_leg = 900 N/m\n"
        "  table {\n    state FLIGHT on liftoff(main): stiffen(main)\n  }\n}\n"
        + "controller idle {\n  include gains\n"
        + TABLE
        + "}\n"
    )
    model = check_model(path)
    assert {c.name for c in model.controller("idle").params} == {"kp", "kv"}


def test_the_bipeds_controllers_share_their_gains() -> None:
    model = check_model(ROOT / "creatures" / "biped.leg")
    names = [[c.name for c in model.controller(n).params][:14] for n in ("run", "gallop")]
    assert names[0] == names[1]
    run = {c.name: c.value for c in model.controller("run").params}
    gallop = {c.name: c.value for c in model.controller("gallop").params}
    assert (run["k_trim"], gallop["k_trim"]) == (0.1, 0.25)  # overridden where it differs
    assert run["kp"] == gallop["kp"] == 300.0
