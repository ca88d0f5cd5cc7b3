"""Animate, export-motion and replay on odd creatures and odd run directories, as people
outside the team make them: a fixed-base arm, runs of another creature, damaged runs."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from legdsl.cli import main

ARM = """creature arm {
  planar
  body base fixed at (0 m, 1 m) {
    mass 1 kg  inertia 0.1 kg*m^2
  }
  body a on base via revolute j1 {
    length 0.3 m  com 0.15 m  mass 0.5 kg  inertia 0.01 kg*m^2  initial 30 deg
  }
  body b on a via revolute j2 at tip {
    length 0.3 m  com 0.15 m  mass 0.5 kg  inertia 0.01 kg*m^2
  }
  contact tip on b at tip
}
"""


@pytest.fixture(scope="module")
def arm_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A short run of a fixed-base two-link arm (no ground, no legs, no controller)."""
    home = tmp_path_factory.mktemp("arm")
    (home / "arm.leg").write_text(ARM)
    run = home / "run"
    argv = ["run", str(home / "arm.leg"), "--time", "0.2", "--out", str(run)]
    assert main([*argv, "--backend", "python", "--generated", str(home / "generated")]) == 0
    return run


def test_a_run_of_another_creature_with_as_many_coordinates_is_refused(
    arm_run: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # an older run.json has no fingerprint: the same coordinates but another contact set
    # was drawn with the wrong forces, and the video stopped with an internal error
    other = tmp_path / "arm2.leg"
    other.write_text(
        ARM.replace("creature arm", "creature arm2").replace(
            "contact tip on b at tip", "contact tip on b at tip\n  contact elbow on a at tip"
        )
    )
    info = json.loads((arm_run / "run.json").read_text())
    del info["creature_fingerprint"]
    info["source"], info["creature"] = str(other), "arm2"
    run = tmp_path / "run"
    run.mkdir()
    for name in ("trajectory.npz", "trajectory.csv"):
        (run / name).write_bytes((arm_run / name).read_bytes())
    (run / "run.json").write_text(json.dumps(info))
    gen = ["--generated", str(tmp_path / "generated")]
    for argv in (
        ["animate", str(run), "-o", str(tmp_path / "a.html")],
        ["export-motion", str(run), "-o", str(tmp_path / "a.glb")],
    ):
        assert main(argv + gen) == 2
        err = capsys.readouterr().err
        assert "the run's contacts (tip) are not those of" in err
        assert "--source FILE" in err
    assert not (tmp_path / "a.html").exists() and not (tmp_path / "a.glb").exists()
