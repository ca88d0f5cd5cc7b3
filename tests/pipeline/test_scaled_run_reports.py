"""What a ``legdsl run --scale L`` run reports beside its trajectory: its times and heights are
the scaled creature's, as those of the file ``legdsl scale`` writes are."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from conftest import CREATURES

from legdsl.cli import main

# a fixed-base planar arm whose servo drives its elbow into a stop (no contacts, no controller)
ARM = """\
creature arm {
  planar
  gravity 9.81 m/s^2
  body base fixed at (0 m, 1 m) { mass 5 kg  inertia 0.1 kg*m^2 }
  body upper on base via revolute shoulder at (0 m, 0 m) {
    length 0.4 m  com 0.2 m  mass 1 kg  inertia 0.01 kg*m^2
  }
  body fore on upper via revolute elbow at tip {
    length 0.3 m  com 0.15 m  mass 0.5 kg  inertia 0.005 kg*m^2
    limits -90 deg to 90 deg
    stop k = 2000 N*m/rad, b = 20 N*m*s/rad
  }
  actuator elbow_servo on elbow servo(kp = 100 N*m/rad, kv = 2 N*m*s/rad, setpoint = 150 deg, max = 10 N*m)
}
"""


def _run_json(out: Path) -> dict:
    return json.loads((out / "run.json").read_text(encoding="utf-8"))


def test_the_time_on_joint_stops_of_a_scaled_run_is_the_scaled_creatures(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """It was the unscaled model's: 1/sqrt(L) of the scaled file's run (0.398 s for 0.562 s)."""
    source = tmp_path / "arm.leg"
    source.write_text(ARM, encoding="utf-8")
    scaled = tmp_path / "arm_x2.leg"
    assert main(["scale", str(source), "--by", "2", "-o", str(scaled)]) == 0
    common = ["--time", "1", "--generated", str(tmp_path / "gen"), "--backend", "python"]
    assert main(["run", str(scaled), *common, "--out", str(tmp_path / "file")]) == 0
    assert main(["run", str(source), *common, "--scale", "2", "--out", str(tmp_path / "run")]) == 0
    by_file = _run_json(tmp_path / "file")["time_on_stops"]["elbow"]
    by_run = _run_json(tmp_path / "run")["time_on_stops"]["elbow"]
    assert by_file > 0.3
    assert by_run == pytest.approx(by_file, abs=0.01)
    assert f"elbow {by_file:.3f} s" in capsys.readouterr().out


def test_a_scaled_run_that_falls_says_the_heights_of_the_scaled_creature(
    generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--fall-height 5 at L = 2 said 'the limit is 2.5 m' (the unscaled model's, of its root
    at 0.95 m) while the recorded root stands at 1.9 m. (A limit above the start is refused
    now: this one is passed as the root sinks on landing; its digits tell the two apart.)"""
    out = tmp_path / "run"
    args = ["run", str(CREATURES / "hopper.leg"), "--controller", "hop", "--time", "1",
            "--fall-height", "1.8", "--scale", "2", "--generated", str(generated),
            "--backend", "python", "--out", str(out)]  # fmt: skip
    assert main(args) == 4
    said = "the root fell to 1.7997 m above the ground (the limit is 1.8 m)"  # the scaled file's
    assert said in capsys.readouterr().err
    info = _run_json(out)
    assert info["message"] == info["cause"] == said


def test_a_scaled_runs_fall_heights_are_the_scaled_files_to_the_digit(
    generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The heights were the unscaled model's, rounded, then multiplied: 3.496 m at L = 4 where
    the scaled file's run (bit for bit the same run: L = 4 scales time by 2) says 3.497 m
    (0.8741 m rounded before it was scaled). They are rounded once, scaled."""
    hopper = CREATURES / "hopper.leg"
    scaled = tmp_path / "hopper_x4.leg"
    assert main(["scale", str(hopper), "--by", "4", "-o", str(scaled)]) == 0
    common = ["--controller", "hop", "--time", "1", "--fall-height", "3.5", "--backend", "python"]
    told = []
    for source, more in ((hopper, ["--scale", "4", "--generated", str(generated)]),
                         (scaled, ["--generated", str(tmp_path / "gen")])):  # fmt: skip
        capsys.readouterr()
        assert main(["run", str(source), *common, *more, "--out", str(tmp_path / "r")]) == 4
        told.append(_run_json(tmp_path / "r")["message"])
    assert told[0] == told[1] == "the root fell to 3.497 m above the ground (the limit is 3.5 m)"


def test_a_scaled_run_keeps_the_path_it_was_given_for_metrics_and_the_top_view(
    generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """run.json held the unscaled model's path (radius 5 m for the 10 m given at L = 2), so
    'legdsl metrics' measured the scaled track against it: 0.25 m RMS off where the run itself
    said 0.04 m."""
    from legdsl.analysis.plot import run_paths
    from legdsl.pipeline.measure import measure_run

    out = tmp_path / "run"
    shape = "circle(center = (0, 10) m, radius = 10 m, turn = left)"
    args = ["run", str(CREATURES / "biped.leg"), "--controller", "run", "--path", shape,
            "--time", "1.5", "--scale", "2", "--generated", str(generated),
            "--backend", "python", "--out", str(out)]  # fmt: skip
    assert main(args) == 0
    capsys.readouterr()
    (spec,) = run_paths(out)
    assert (spec.center, spec.radius, spec.lookahead) == ((0.0, 10.0), 10.0, 2.0)  # 1 m x L
    (at_run,) = _run_json(out)["path_reports"]
    _, (measured,) = measure_run(out, t_from=0.5, generated=generated)
    assert measured["length"] == at_run["length"] == pytest.approx(20 * 3.141592653589793)
    assert measured["lateral_rms"] < 0.1
    # the progress of --from 0.5 is made from 0.5 s; without --from, from the start, as the run's
    _, (whole,) = measure_run(out, generated=generated)
    assert whole["progress"] == pytest.approx(at_run["progress"], rel=1e-9)
    assert 0 < measured["progress"] < whole["progress"]


def test_a_scaled_run_is_not_drawn_on_the_unscaled_bodies_and_a_damaged_scale_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """'legdsl run --scale --animate' is refused (the player would draw the unscaled bodies with
    the scaled motion), but 'legdsl animate DIR', export-motion and replay of that run drew just
    that. A run.json whose 'scale' is not a positive number was an internal error in metrics."""
    source = tmp_path / "arm.leg"
    source.write_text(ARM, encoding="utf-8")
    run = tmp_path / "run"
    gen = ["--generated", str(tmp_path / "gen")]
    args = ["run", str(source), "--time", "0.2", "--scale", "2", *gen, "--backend", "python"]
    assert main([*args, "--out", str(run)]) == 0
    for command in (["animate", str(run), "-o", str(tmp_path / "a.html"), *gen],
                    ["export-motion", str(run), "--format", "bvh", "-o", str(tmp_path / "a.bvh")]):  # fmt: skip
        assert main(command) == 2
        err = capsys.readouterr().err
        assert f"{run} was run with --scale 2: drawn, its creature would be" in err
        assert f"'legdsl scale {source} --by 2 -o OUT.leg', run OUT.leg and draw that run" in err
    assert not (tmp_path / "a.html").exists() and not (tmp_path / "a.bvh").exists()
    info = _run_json(run)
    for damaged in ("abc", -2, [1], True, 0):
        (run / "run.json").write_text(json.dumps({**info, "scale": damaged}), encoding="utf-8")
        assert main(["metrics", str(run), *gen]) == 2
        assert "run.json: 'scale' is not a positive number" in capsys.readouterr().err


def test_a_scaled_run_that_diverges_or_is_interrupted_says_the_scaled_creatures_times(
    generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """They said the unscaled model's time (0.285 s for 0.57 s at L = 4); a divergence's
    step and stiffness are the scaled creature's too (tests/pipeline/test_scaled_run_advice.py)."""
    from legdsl.pipeline.scaled import scale_message

    out = tmp_path / "run"
    args = ["run", str(CREATURES / "hopper.leg"), "--controller", "hop", "--time", "1",
            "--dt", "10ms", "--scale", "4", "--generated", str(generated),
            "--backend", "python", "--out", str(out)]  # fmt: skip
    assert main(args) == 3
    err = capsys.readouterr().err
    assert "the simulation diverged at t = 0.5700 s: " in err
    assert _run_json(out)["ended_at"] == pytest.approx(0.57)
    said = "interrupted by SIGTERM at t = 0.5000 s of 1.5 s; what was recorded up to then is kept"
    assert scale_message(said, 4.0) == (
        "interrupted by SIGTERM at t = 1.0000 s of 3 s; what was recorded up to then is kept"
    )


SCENES = """
scene faster {
  controller hop
  set speed = 0.5 m/s
  at 0.3 s set speed = 1 m/s
  time 0.6 s
}

scene switching {
  controller hop
  at 0.3 s switch hop
}
"""


def test_a_scene_run_with_scale_is_the_scaled_files_scene(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The scene is the file's creature's; run with --scale L it is the scene of the file
    'legdsl scale' writes (values and times scaled), not its values divided by their factors."""
    import numpy as np

    leg = tmp_path / "hopper.leg"
    leg.write_text((CREATURES / "hopper.leg").read_text(encoding="utf-8") + SCENES)
    scaled = tmp_path / "hopper4.leg"
    assert main(["scale", str(leg), "--by", "4", "-o", str(scaled)]) == 0
    common = ["--scene", "faster", "--backend", "python", "--generated", str(tmp_path / "gen")]
    assert main(["run", str(scaled), *common, "--out", str(tmp_path / "file")]) == 0
    assert main(["run", str(leg), *common, "--scale", "4", "--out", str(tmp_path / "flag")]) == 0
    by_file = np.load(tmp_path / "file" / "trajectory.npz")
    by_flag = np.load(tmp_path / "flag" / "trajectory.npz")
    assert _run_json(tmp_path / "flag")["sim_time"] == pytest.approx(1.2)  # 0.6 s times sqrt 4
    assert np.allclose(by_flag["t"], by_file["t"])
    assert np.allclose(by_flag["speed_command"], by_file["speed_command"])  # 1 m/s, then 2
    assert set(np.round(by_flag["speed_command"], 9)) == {1.0, 2.0}
    assert np.allclose(by_flag["q"], by_file["q"], atol=1e-6)
    capsys.readouterr()
    argv = ["run", str(leg), "--scene", "switching", "--scale", "4", "--out", str(tmp_path / "s")]
    assert main(argv) == 2
    assert "--scene switching switches controllers, which --scale does not support" in (
        capsys.readouterr().err
    )


def test_animate_with_scale_is_refused_with_the_command_to_run(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """`run --scale 2 --animate` said "animate the run of 'legdsl scale's file": a quote left
    open and, unlike the other --scale refusals, no command. It gives the command now, before
    anything is compiled or run."""
    leg = str(CREATURES / "hopper.leg")
    out = tmp_path / "h"
    argv = ["run", leg, "--controller", "hop", "--scale", "2", "--animate", "--out", str(out)]
    assert main(argv) == 2
    said = capsys.readouterr().err
    assert "--animate with --scale is not supported" in said
    assert f"write the scaled file with 'legdsl scale {leg} --by 2 -o OUT.leg' and run it" in said
    assert said.count("'") % 2 == 0 and not out.exists()
