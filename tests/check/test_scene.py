"""Scenes: a whole run written in the .leg file, checked to the IR and run as its options."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from legdsl.check.source import check_model
from legdsl.cli import main
from legdsl.lang.errors import UsageError
from legdsl.pipeline.scenes import find_scene, scene_plan, scene_texts

ROOT = Path(__file__).resolve().parents[2]
BIPED = ROOT / "creatures" / "biped.leg"


def test_the_bipeds_scene_in_si_units() -> None:
    scene = check_model(BIPED).scene("run_gallop_run")
    assert scene.controller == "run" and scene.duration == 26.0
    assert [(w.t, w.controller) for w in scene.switches] == [(8.0, "gallop"), (16.0, "run")]
    assert [(v.name, v.value, v.at) for v in scene.values] == [
        ("speed", 2.0, None), ("speed", 1.5, 8.0), ("speed", 2.5, 16.0),
    ]  # fmt: skip
    sets, switches = scene_texts(scene)
    assert sets == ["speed=2.0m/s", "speed=1.5m/s@8.0s", "speed=2.5m/s@16.0s"]
    assert switches == ["8.0s=gallop", "16.0s=run"]


def test_a_scene_may_use_semicolons_units_of_any_size_and_actuators(tmp_path: Path) -> None:
    path = tmp_path / "biped.leg"
    path.write_text(
        BIPED.read_text()
        + "scene quick { controller run; set speed = 90 m/min; set leg_l_spring.k = 12 kN/m;"
        " at 500 ms switch gallop; at 0.5 s set turn_rate = 10 deg/s; time 1 min }\n"
    )
    scene = check_model(path).scene("quick")
    values = {(v.name, v.at): v.value for v in scene.values}
    assert values[("speed", None)] == pytest.approx(1.5)
    assert values[("leg_l_spring.k", None)] == pytest.approx(12000.0)
    assert values[("turn_rate", 0.5)] == pytest.approx(0.17453292519943295)
    assert scene.switches[0].t == 0.5 and scene.duration == 60.0
    with pytest.raises(UsageError, match="scenes: run_gallop_run, by_speed, quick"):
        find_scene(check_model(path), "quik")


def test_legdsl_run_scene_runs_it_and_the_command_line_adds_to_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "biped.leg"
    path.write_text(
        BIPED.read_text() + "scene quick { controller run; set speed = 1.5 m/s;"
        " at 0.6 s switch gallop; time 30 s }\n"
    )
    out = tmp_path / "run"
    args = ["run", str(path), "--scene", "quick", "--time", "1", "--out", str(out),
            "--generated", str(tmp_path / "generated")]  # fmt: skip
    assert main([*args, "--set", "speed=1.2m/s@0.8s"]) == 0
    info = json.loads((out / "run.json").read_text())
    assert info["sim_time"] == pytest.approx(1.0)  # --time overrides the scene's time
    assert info["controller"] == "run"
    assert [s["controller"] for s in info["segments"]] == ["run", "gallop"]
    assert info["settings"]["inputs"] == {"speed": 1.5}
    assert info["settings"]["schedule"] == [{"t": 0.8, "input": "speed", "value": 1.2}]
    capsys.readouterr()
    assert main([*args, "--controller", "gallop"]) == 2
    assert "leave out --controller" in capsys.readouterr().err
    assert main([*args[:2], "--scene", "slow", "--time", "1"]) == 2
    assert "no scene 'slow'" in capsys.readouterr().err


def test_gait_bands_choose_the_controller_with_hysteresis() -> None:
    from legdsl.ir.scene import choose_gaits

    scene = check_model(BIPED).scene("by_speed")
    assert [(b.controller, b.low, b.high) for b in scene.bands] == [
        ("gallop", None, 1.6), ("run", 1.4, None),
    ]  # fmt: skip
    assert scene.controller == "gallop" and scene.band_input == "speed"
    changes = [(6.0, 2.0), (12.0, 1.5), (18.0, 1.2)]
    first, switches, lost = choose_gaits(scene.bands, None, 1.5, changes)
    # 1.5 m/s: gallop's band is first; 2 m/s: run; 1.5 again: run kept; 1.2: gallop
    assert (first, switches, lost) == ("gallop", [(6.0, "run"), (18.0, "gallop")], [])
    assert choose_gaits(scene.bands, None, 1.5, [(3.0, 1.5)])[1] == []
    assert choose_gaits(scene.bands, "run", 1.5, [(3.0, 1.0)])[1] == [(3.0, "gallop")]
    # the command line's speeds choose too
    controller, _, planned = scene_plan(scene, check_model(BIPED), ["speed=1.45m/s@2s"], [])
    assert controller == "gallop"
    assert planned == ["6.0s=run", "18.0s=gallop"]
    controller, _, planned = scene_plan(scene, check_model(BIPED), ["speed=2m/s"], [])
    assert (controller, planned) == ("run", ["18.0s=gallop"])


def test_a_controller_line_starts_a_gait_table_only_in_its_band(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The ``controller`` line chooses between the bands that hold the first command (their
    overlap); one whose band does not hold it is refused, at the line in the file and as a
    UsageError where a ``--set`` moves the first command, and ``--controller`` refused for it
    names the line, not the band, as its reason."""
    path = tmp_path / "biped.leg"
    table = "gait by speed { gallop to 1.6 m/s; run from 1.4 m/s }"
    path.write_text(BIPED.read_text() + f"scene lead {{ {table}; controller run;"
                    " set speed = 1.5 m/s; time 0.2 s }\n")  # fmt: skip
    model = check_model(path)
    scene = model.scene("lead")
    assert scene_plan(scene, model, [], [])[0] == "run"  # 1.5 m/s: gallop's band holds it too
    with pytest.raises(UsageError, match=r"starts with run \(its 'controller' line\), but no "
                       r"band of run holds the first command, speed = 1 \(SI\)"):  # fmt: skip
        scene_plan(scene, model, ["speed=1m/s"], [])
    args = ["run", str(path), "--scene", "lead", "--generated", str(tmp_path / "generated")]
    assert main([*args, "--controller", "gallop"]) == 2
    assert (
        "--scene lead starts with controller run (its 'controller' line); leave out --controller"
    ) in capsys.readouterr().err
    from legdsl.lang.errors import LegError

    path.write_text(BIPED.read_text() + f"scene lead {{ {table}; controller run;"
                    " set speed = 1 m/s }\n")  # fmt: skip
    with pytest.raises(LegError) as err:
        check_model(path)
    assert (
        "the scene starts with run, but no band of run holds the first command, speed = 1 m/s "
        "(bands: gallop to 1.6 m/s; run from 1.4 m/s): leave out this line (the table starts "
        "with gallop)"
    ) in err.value.render()


def test_a_speed_no_band_holds_is_an_error(tmp_path: Path) -> None:
    from legdsl.lang.errors import LegError

    path = tmp_path / "biped.leg"
    path.write_text(
        BIPED.read_text() + "scene gap {\n  gait by speed { gallop to 1.6 m/s; run from 2 m/s }\n"
        "  set speed = 1.2 m/s\n  at 4 s set speed = 1.8 m/s\n}\n"
    )
    with pytest.raises(LegError) as err:
        check_model(path)
    text = err.value.render()
    assert "no band of 'gait by speed' holds speed = 1.8 m/s" in text
    assert "at 4 s set speed = 1.8 m/s\n" in text and "^" in text


def test_a_scene_sets_one_controllers_own_values(tmp_path: Path) -> None:
    """``set CONTROLLER.NAME = V``: that controller's parameter or input default only, checked
    like every ``set``; a controller that does not run, a name it lacks, a time: errors at
    the word."""
    from legdsl.lang.errors import LegError

    path = tmp_path / "biped.leg"
    path.write_text(
        BIPED.read_text()
        + "scene own { controller run; at 1 s switch gallop; set gallop.k_speed = 50 ms;"
        " set gallop.height = 90 cm; time 2 s }\n"
    )
    scene = check_model(path).scene("own")
    assert [(v.name, v.value) for v in scene.values] == [
        ("gallop.k_speed", pytest.approx(0.05)), ("gallop.height", pytest.approx(0.9)),
    ]  # fmt: skip
    assert scene_texts(scene)[0] == ["gallop.k_speed=0.05s", "gallop.height=0.9m"]
    for bad, words in (
        ("set gallop_human.k_speed = 50 ms", "controller 'gallop_human' does not run in this"),
        ("set walk.k_speed = 50 ms", "no controller or actuator 'walk'"),
        ("set gallop.k_sped = 50 ms", "controller gallop has no input or parameter 'k_sped'"),
        ("set gallop.k_speed = 5 cm", "k_speed"),
        ("at 1.5 s set gallop.height = 1 m", "gallop.height is controller gallop's own value"),
    ):
        path.write_text(
            BIPED.read_text() + f"scene own {{ controller run; at 1 s switch gallop; {bad} }}\n"
        )
        with pytest.raises(LegError) as err:
            check_model(path)
        assert words in str(err.value) and "^" in str(err.value), str(err.value)


def test_the_quadrupeds_scenes_are_the_issues_transition_run() -> None:
    """Both scenes of creatures/quadruped.leg plan the command line of issue 13's run:
    trot, bound at 6 s, gallop at 12 s, trot at 18 s, each with its speed."""
    model = check_model(ROOT / "creatures" / "quadruped.leg")
    written = model.scene("trot_bound_gallop_trot")
    sets, switches = scene_texts(written)
    assert written.controller == "trot" and written.duration == 24.0
    assert switches == ["6.0s=bound", "12.0s=gallop", "18.0s=trot"]
    assert sets == ["speed=2.0m/s", "speed=2.8m/s@6.0s", "speed=4.0m/s@12.0s", "speed=2.0m/s@18.0s"]
    by_speed = model.scene("by_speed")
    controller, _, planned = scene_plan(by_speed, model, [], [])
    assert (controller, planned) == ("trot", switches)


def test_a_setting_for_a_band_never_reached_is_told() -> None:
    """``--set`` of a name only the gallop has, in a run whose speeds never reach the gallop's
    band: left out, as before, and now told (it said nothing); reached, it is kept."""
    model = check_model(ROOT / "creatures" / "quadruped.leg")
    by_speed = model.scene("by_speed")
    mine = ["lead_rear=1", "gallop.kv=1N*m*s/rad", "kp=100N*m/rad"]
    notes: list[str] = []
    _, sets, _ = scene_plan(by_speed, model, ["speed=2m/s@12s", *mine], [], notes)
    assert "lead_rear=1" not in sets and "kp=100N*m/rad" in sets
    assert [n.partition(":")[0] for n in notes] == [
        "--set lead_rear=1",
        "--set gallop.kv=1N*m*s/rad",
    ]
    assert "only gallop has it" in notes[0] and "(SI: gallop from 3.3)" in notes[0]
    reached: list[str] = []
    _, sets, _ = scene_plan(by_speed, model, mine, [], reached)  # 4 m/s at 12 s: the gallop
    assert "lead_rear=1" in sets and reached == []


def test_a_scene_for_one_of_several_creatures_runs_without_creature(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The scene's 'for' says which creature (legdsl run asked for --creature as well)."""
    path = tmp_path / "two.leg"
    path.write_text(
        "creature a { planar body b free { mass 1 kg inertia 1 kg*m^2 } }\n"
        "creature z { planar body b fixed { mass 1 kg inertia 1 kg*m^2 }\n"
        "  body c on b via revolute j { mass 1 kg inertia 1 kg*m^2 }\n"
        "  actuator s on j servo(kp = 1 N*m/rad) }\n"
        "controller hold for z { table { state A on time > 0 s: s.setpoint = 1 deg } }\n"
        "scene still for z { controller hold; time 0.05 s }\n"
    )
    out, generated = tmp_path / "run", tmp_path / "generated"
    args = ["run", str(path), "--out", str(out), "--generated", str(generated)]
    assert main([*args, "--scene", "still"]) == 0
    assert json.loads((out / "run.json").read_text())["creature"] == "z"
    assert main([*args, "--controller", "hold", "--time", "0.05"]) == 0
    capsys.readouterr()
    assert main([*args, "--time", "0.05"]) == 2  # nothing says which
    assert "choose a creature with --creature" in capsys.readouterr().err


def test_two_commands_for_one_input_at_one_time_in_a_scene_are_refused(tmp_path: Path) -> None:
    from legdsl.lang.errors import LegError

    path = tmp_path / "biped.leg"
    path.write_text(
        BIPED.read_text() + "scene twice {\n  controller run\n  at 1 s set speed = 1 m/s\n"
        "  at 1000 ms set speed = 2 m/s\n  at 1 s set height = 0.8 m\n}\n"
    )
    with pytest.raises(LegError) as caught:
        check_model(path)
    lines = len(BIPED.read_text().splitlines())
    assert (
        f"biped.leg:{lines + 4}:3: error: two commands for speed at 1 s (the other at line "
        f"{lines + 3}); an input takes one command at a time: keep one"
    ) in caught.value.render()


@pytest.mark.parametrize(
    ("lines", "only"),
    [
        # a misspelt controller: its input and own value are not told absent as well
        (
            "controller rnu\n  set speed = 1.2 m/s\n  set run.height = 0.9 m",
            "creature 'biped' has no controller 'rnu'",
        ),
        # a switch's time without its unit: the sets are still the switched-to controller's
        (
            "controller run\n  at 4 switch gallop\n  set gallop.k_speed = 50 ms\n"
            "  set k_speed = 50 ms",
            "the time after 'at' is a time (s): give its unit, e.g. 4 s",
        ),
    ],
)
def test_a_wrong_controller_line_is_the_scenes_only_error(
    tmp_path: Path, lines: str, only: str
) -> None:
    """One mistake on a scene's controller line was also told at each `set` of the scene, as
    a name no controller of the scene has (they have none): a screenful from one typo."""
    from legdsl.lang.errors import LegError

    path = tmp_path / "biped.leg"
    path.write_text(BIPED.read_text() + f"scene s {{\n  {lines}\n  time 2 s\n}}\n")
    with pytest.raises(LegError) as caught:
        check_model(path)
    assert [only in d.message for d in caught.value.diagnostics] == [True]
    path.write_text(path.read_text().replace("rnu", "run").replace("at 4 switch", "at 4 s switch"))
    check_model(path)  # the line alone was wrong


def test_a_set_no_controller_has_is_told_beside_a_switch_time_without_unit(
    tmp_path: Path,
) -> None:
    from legdsl.lang.errors import LegError

    path = tmp_path / "biped.leg"
    path.write_text(
        BIPED.read_text() + "scene s {\n  controller run\n  at 4 switch gallop\n"
        "  set k_sped = 50 ms\n  time 2 s\n}\n"
    )
    with pytest.raises(LegError) as caught:
        check_model(path)
    text = caught.value.render()
    assert "the time after 'at' is a time (s)" in text
    assert "no controller of this scene has an input or parameter 'k_sped'" in text


def test_a_negative_value_of_the_wrong_kind_keeps_its_sign_and_a_frequency_its_turns(
    tmp_path: Path,
) -> None:
    """'at 1 s set turn_rate = -1 rad' was echoed '1 rad' with the caret after the minus and the
    advice 'write e.g. 1 rad/s'; '1 Hz' for a turning rate in deg/s was told 'write e.g. 1
    deg/s', 360 times slower than the turn a second most likely meant."""
    from legdsl.lang.errors import LegError

    path = tmp_path / "biped.leg"
    path.write_text(
        BIPED.read_text() + "scene turns {\n  controller run\n"
        "  at 1 s set turn_rate = -1 rad\n  at 2 s set turn_rate = 1 Hz\n}\n"
    )
    with pytest.raises(LegError) as err:
        check_model(path)
    text = err.value.render()
    assert "but -1 rad is an angle (deg); write e.g. -1 rad/s" in text
    line = "      at 1 s set turn_rate = -1 rad\n"
    assert line + " " * line.index("-") + "^~~~~~\n" in text  # under the minus
    assert "1 Hz is one turn a second: write 360 deg/s (or 1 rev/s)" in text
