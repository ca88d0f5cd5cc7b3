"""The command given to run again a run of a changed creature makes the same run: it kept
only --time and the controller, scene and switches, so that running it overwrote the run
directory with another run (no --drop, another integrator, sample rate and fall rules)."""

from __future__ import annotations

import json
import math
import shlex
from pathlib import Path
from typing import Any

import pytest

from legdsl.analysis.rerun import rerun_command
from legdsl.cli import main
from legdsl.pipeline.path_option import parse_path_option

ROOT = Path(__file__).resolve().parents[2]

SCENE = """
scene hopping {
  controller hop
  set speed = 0.8 m/s
  at 0.2 s set speed = 1.2 m/s
  time 0.3 s
}
"""


def _given(info: dict[str, Any]) -> dict[str, Any]:
    """What a run was given, as its run.json records it."""
    return {k: info.get(k) for k in ("controller", "scene", "scale", "options", "settings",
                                     "paths", "switches")}  # fmt: skip


def _close(a: Any, b: Any) -> bool:
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(_close(a[k], b[k]) for k in a)
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(_close(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, float) and isinstance(b, float):
        return math.isclose(a, b, rel_tol=1e-9)
    return bool(a == b)


def _again(run: Path, capsys: pytest.CaptureFixture[str]) -> list[str]:
    """The command ``plot`` gives for ``run`` (refused), as its words."""
    capsys.readouterr()
    assert main(["plot", str(run)]) == 2
    err = capsys.readouterr().err
    assert "run it again (legdsl " in err, err
    return shlex.split(err.split("run it again (", 1)[1].rstrip().removesuffix(")"))


def test_the_command_to_run_again_makes_the_same_run(
    tmp_path: Path, generated: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    leg = tmp_path / "hopper.leg"
    leg.write_text((ROOT / "creatures" / "hopper.leg").read_text() + SCENE)
    scene, scaled = tmp_path / "scene", tmp_path / "scaled"
    runs = {
        scene: ["--scene", "hopping", "--set", "kp=140N*m/rad", "--set", "hip_servo.kv=5N*m*s/rad",
                "--switch", "0.15s=hop", "--set", "hop.kv=14N*m*s/rad", "--drop", "5cm",
                "--integrator", "rk4", "--record-rate", "500Hz", "--dt", "0.2ms",
                "--control-dt", "1ms", "--fall-tilt", "80deg", "--fall-height", "0.1m"],
        scaled: ["--controller", "hop", "--scale", "2", "--set", "speed=0.5m/s",
                 "--set", "speed=1m/s@0.1s", "--time", "0.3", "--drop", "0.1"],
    }  # fmt: skip
    for out, argv in runs.items():
        assert main(["run", str(leg), *argv, "--out", str(out), "--generated", str(generated)]) == 0
    before = {out: _given(json.loads((out / "run.json").read_text())) for out in runs}
    assert before[scene]["settings"]["schedule"] and before[scene]["switches"]  # the scene's
    leg.write_text(leg.read_text().replace("mass 10 kg", "mass 10.5 kg", 1))
    for out in runs:
        words = _again(out, capsys)
        assert words[:3] == ["legdsl", "run", str(leg)] and words[-2:] == ["--out", str(out)]
        if out == scene:  # the scene's own values and switch are the scene's to give
            assert "speed=0.8m/s" not in " ".join(words) and words.count("--switch") == 1
        assert main([*words[1:], "--generated", str(generated)]) == 0
        after = _given(json.loads((out / "run.json").read_text()))
        assert _close(after, before[out]), (words, after, before[out])


def test_a_path_given_is_given_again_and_the_files_own_is_not(tmp_path: Path) -> None:
    from legdsl.check.source import check_model

    leg = tmp_path / "biped.leg"
    own = "circle(center = (0, 5) m, radius = 5 m, turn = left)"
    text = (ROOT / "creatures" / "biped.leg").read_text()
    leg.write_text(text.replace("  path route\n", f"  path route = {own}\n", 1))
    model = check_model(leg)
    given = parse_path_option("route=circle(center = (0, 5) m, radius = 4 m, turn = right)")
    info = {"controller": "run", "options": {"duration": 2.0},
            "paths": [given.as_json() | {"followed": [[0.0, 1.0]]}]}  # fmt: skip
    words = shlex.split(rerun_command(leg, Path("runs/b"), info, model))
    assert words.count("--path") == 1
    assert parse_path_option(words[words.index("--path") + 1]) == given
    info["paths"] = [parse_path_option(f"route={own}").as_json()]
    assert "--path" not in rerun_command(leg, Path("runs/b"), info, model)
