"""A run that changes to a controller following another path: each path is reported over the
part of the run its controller followed it in (run.json, legdsl run, metrics and the top view),
not the first one over the whole run and the later one never."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from legdsl.cli import main

BOX = """
creature box {
  planar
  body trunk free { mass 5 kg  inertia 0.05 kg*m^2  initial x = 0 m, z = 0.2 m }
  contact front on trunk at (0.2 m, -0.1 m)
  contact back on trunk at (-0.2 m, -0.1 m)
  ground {
    normal spring(k = 2e4 N/m, b = 250 N*s/m)
    tangent spring(k = 1.2e4 N/m, b = 160 N*s/m)
  }
}
controller along {
  path route = polyline((-10, 0) m, (10, 0) m)
  table {
    state REST on trunk.z > 10 m:
  }
}
controller beside extends along {
  path route = polyline((-10, 2) m, (10, 2) m)
}
"""

# s: 3 s for a 0.81 m creature; the box stands 0.1 m, its time sqrt(0.1 / 0.81) as long
SETTLE = 1.1


@pytest.fixture(scope="module")
def switched(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A box at rest on y = 0: `along` (its path through it) for 4 s, then `beside` (2 m off)."""
    root = tmp_path_factory.mktemp("paths")
    (root / "box.leg").write_text(BOX)
    argv = ["run", str(root / "box.leg"), "--controller", "along", "--switch", "4s=beside"]
    argv += ["--time", "8", "--backend", "python", "--generated", str(root / "gen")]
    assert main([*argv, "--out", str(root / "run")]) == 0
    return root / "run"


def test_each_path_is_reported_over_its_controllers_part_of_the_run(switched: Path) -> None:
    info = json.loads((switched / "run.json").read_text())
    assert [(p["text"], p["followed"]) for p in info["paths"]] == [
        ("polyline((-10, 0) m, (10, 0) m)", [[0.0, 4.0]]),
        ("polyline((-10, 2) m, (10, 2) m)", [[4.0, 8.0]]),
    ]
    along, beside = info["path_reports"]
    assert (along["from"], along["to"], along["lateral_rms"]) == (SETTLE, 4.0, 0.0)
    assert (beside["from"], beside["to"]) == (4 + SETTLE, 8.0)  # after it took over
    assert beside["lateral_mean"] == pytest.approx(-2.0, abs=1e-6)  # right of its path


def test_metrics_and_the_top_view_read_the_same_spans(
    switched: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    capsys.readouterr()
    assert main(["metrics", str(switched), "--json"]) == 0
    reports = json.loads(capsys.readouterr().out)["path_reports"]
    assert [(r["from"], r["to"]) for r in reports] == [(SETTLE, 4.0), (4 + SETTLE, 8.0)]
    assert main(["metrics", str(switched), "--from", "3.5"]) == 0
    out = capsys.readouterr().out
    assert "(from 3.5 s to 4 s)" in out and "(from 4 s to 8 s)" in out
    assert main(["plot", str(switched), "--top"]) == 0
    assert (switched / "top.png").stat().st_size > 0


def test_a_run_following_one_path_throughout_has_no_spans(switched: Path, tmp_path: Path) -> None:
    box = switched.parent / "box.leg"
    argv = ["run", str(box), "--controller", "along", "--time", "4", "--backend", "python"]
    assert main([*argv, "--generated", str(switched.parent / "gen"), "--out", str(tmp_path)]) == 0
    (path,) = json.loads((tmp_path / "run.json").read_text())["paths"]
    assert "followed" not in path
