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
    assert (run["k_trim"], gallop["k_trim"]) == (0.1, 0.37)  # overridden where it differs
    assert (run["kp"], gallop["kp"]) == (300.0, 150.0)
    assert run["kp_roll"] == gallop["kp_roll"] == 300.0  # shared where it does not


def test_a_part_includes_another_and_its_own_values_take_their_places(tmp_path: Path) -> None:
    path = tmp_path / "hopper.leg"
    path.write_text(
        "shared gains {\n  param kp = 50 N*m/rad\n  param kv = 2 N*m*s/rad\n"
        "  param k_leg = 900 N/m\n}\n"
        "shared stiff {\n  include gains\n  param kv = 4 N*m*s/rad\n  param extra = 1 s\n}\n"
        + CREATURE
        + "controller hop {\n  include stiff\n  param k_leg = 1200 N/m\n"
        + TABLE
        + "}\n"
        # two parts reaching one part (gains) unchanged share its items: no clash
        + "shared soft {\n  include gains\n}\n"
        + "shared slow {\n  include gains\n  param lag = 2 s\n}\n"
        + "controller both {\n  include soft, slow\n"
        + TABLE
        + "}\n"
    )
    model = check_model(path)
    hop = [(c.name, c.value) for c in model.controller("hop").params]
    assert hop == [("kp", 50.0), ("kv", 4.0), ("k_leg", 1200.0), ("extra", 1.0)]
    both = [c.name for c in model.controller("both").params]
    assert both == ["kp", "kv", "k_leg", "lag"]


def test_a_part_with_roles_and_a_table_calls_actions_each_controller_writes(
    tmp_path: Path,
) -> None:
    path = tmp_path / "hopper.leg"
    path.write_text(
        "shared machine {\n  param kp = 50 N*m/rad\n  roles active = main\n  table {\n"
        "    state FLIGHT on liftoff(active): hip_servo.kp = kp; swing(active)\n"
        "    state STANCE on touchdown(active): hip_servo.kp = 0 N*m/rad\n  }\n}\n"
        + CREATURE
        + "controller soft {\n  include machine\n"
        "  action swing(leg) { leg.hip_servo.kv = 1 N*m*s/rad }\n}\n"
        + "controller stiff {\n  include machine\n  param kv = 3 N*m*s/rad\n"
        "  action swing(leg) { leg.hip_servo.kv = kv }\n}\n"
        # a table of its own replaces the part's, in its place
         + "controller other {\n  include machine\n  table {\n"
        "    state ONLY on liftoff(main): hip_servo.kp = kp\n  }\n}\n"
    )
    model = check_model(path)
    soft, stiff = model.controller("soft"), model.controller("stiff")
    assert soft.state_names == stiff.state_names == ("FLIGHT", "STANCE")
    assert soft.states[0].span == stiff.states[0].span  # the part's row, once
    assert repr(soft.states[0]) != repr(stiff.states[0])  # each with its own swing
    assert model.controller("other").state_names == ("ONLY",)


def test_the_bipeds_gallops_share_their_table() -> None:
    model = check_model(ROOT / "creatures" / "biped.leg")
    gallop, human = model.controller("gallop"), model.controller("gallop_human")
    assert gallop.state_names == human.state_names == ("FLIGHT", "SINGLE_1", "DOUBLE", "SINGLE_2")
    assert [s.span for s in gallop.states] == [s.span for s in human.states]
    assert {c.name for c in gallop.params} - {c.name for c in human.params} == {
        "stagger",
        "lead_per_speed",
    }
