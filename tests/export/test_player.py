"""The HTML player file: self-contained, carries the run exactly, small."""

from __future__ import annotations

import base64
import hashlib
import json
import re
from pathlib import Path

import numpy as np
import pytest
from anim_runs import creature_motion, creature_run, generated_dir
from standin import ModelKinematics, synthetic_run

from legdsl.check.source import check_model
from legdsl.export.motion import Motion, load_motion
from legdsl.export.player import (
    THREE_VERSION,
    _inline_safe,
    player_data,
    player_html,
    three_module,
    write_player,
)


def embedded(html: str) -> dict:
    match = re.search(
        r'<script type="application/json" id="legdsl-data">(.*?)</script>', html, re.S
    )
    assert match is not None
    return dict(json.loads(match.group(1)))


def f32(text: str) -> np.ndarray:
    return np.frombuffer(base64.b64decode(text), dtype="<f4")


_RUN: list[Path] = []


@pytest.fixture(scope="module")
def quadruped(tmp_path_factory) -> Motion:
    _RUN.append(tmp_path_factory.mktemp("quadruped") / "run")
    return creature_motion("quadruped", _RUN[-1])


def quadruped_events() -> list[dict]:
    return list(json.loads((_RUN[-1] / "run.json").read_text())["events"])


def test_the_page_loads_nothing_from_outside(quadruped: Motion) -> None:
    html = player_html(quadruped)
    tags = re.findall(r"<(script|link|img|iframe)\b[^>]*>", html, re.I)
    assert tags == ["script"] * 4  # data, three.js, the import map writer, the player
    assert not re.search(r"<script[^>]*\bsrc=", html, re.I)
    assert "<link" not in html and "@import" not in html
    # Exactly one copy of the vendored three.js, verbatim.
    assert html.count(three_module()) == 1


def test_the_data_is_the_motion(quadruped: Motion) -> None:
    data = embedded(player_html(quadruped, overlays=("forces", "com")))
    frames, bodies = quadruped.frames, len(quadruped.bodies)
    poses = f32(data["poses"]).reshape(frames, bodies, 7)
    assert np.allclose(poses[..., :3], quadruped.positions, atol=1e-6)
    assert np.allclose(poses[..., 3:], quadruped.quaternions, atol=1e-6)
    assert np.allclose(f32(data["times"]), quadruped.times)
    assert np.allclose(f32(data["forces"]).reshape(frames, -1, 3), quadruped.forces, atol=1e-3)
    assert np.allclose(f32(data["com"]).reshape(frames, 3), quadruped.com, atol=1e-6)
    state = np.frombuffer(base64.b64decode(data["state"]), dtype="<i2")
    assert list(state) == list(quadruped.state)
    assert [b["name"] for b in data["bodies"]] == [b.name for b in quadruped.bodies]
    assert data["bodies"][0]["color"] == "#708040"  # the trunk's colour in quadruped.leg
    assert data["overlays"] == ["forces", "com"]
    touchdowns = [e for e in quadruped_events() if e["kind"] == "touchdown"]
    assert len(data["footprints"]) == len(quadruped.footprints) == len(touchdowns) > 0
    assert [fp[0] for fp in data["footprints"]] == pytest.approx([e["t"] for e in touchdowns])
    assert data["planar"] is False and data["size"] > 0.5


def test_three_js_is_the_pinned_release() -> None:
    text = three_module()
    assert f'const t="{THREE_VERSION.split(".")[1]}"' in text[:400]  # REVISION, e.g. "170"
    readme = (
        Path(__file__).resolve().parents[2] / "src/legdsl/export/player/vendor/three/README.md"
    ).read_text()
    assert THREE_VERSION in readme
    assert hashlib.sha256(text.encode()).hexdigest() in readme


def test_text_that_would_close_a_script_is_refused() -> None:
    with pytest.raises(ValueError, match="script"):
        _inline_safe("var s = '</script>';", "x")
    assert _inline_safe("a < b", "x") == "a < b"


def test_a_ten_second_run_stays_small(tmp_path: Path) -> None:
    # The size depends on the frames, links and contacts only: a made-up run will do.
    source = Path(__file__).resolve().parents[2] / "creatures" / "quadruped.leg"
    model = check_model(source)
    synthetic_run(model, source, tmp_path / "run", duration=10.0)
    motion = load_motion(tmp_path / "run", kinematics=ModelKinematics(model))
    size = write_player(motion, tmp_path / "player.html")
    assert size == (tmp_path / "player.html").stat().st_size
    assert motion.frames == 601  # 60 fps
    assert size < 2_000_000, f"{size} bytes"


def test_the_followed_path_is_in_the_data(tmp_path: Path) -> None:
    """A run that followed a path: the motion and the player carry it as points on the ground."""
    import math

    run = creature_run("kangaroo", tmp_path / "run")
    info = json.loads((run / "run.json").read_text())
    circle = {"name": "route", "shape": "circle", "center": [0.0, 3.0], "radius": 3.0, "turn": 1}
    square = {"name": "box", "shape": "polyline", "closed": True,
              "points": [[0, 0], [2, 0], [2, 2], [0, 2]]}  # fmt: skip
    info["paths"] = [circle, square]
    (run / "run.json").write_text(json.dumps(info))
    motion = load_motion(run, generated=generated_dir())
    assert motion.path_names == ("route", "box")
    ring, corners = motion.paths
    assert np.allclose(np.hypot(ring[:, 0], ring[:, 1] - 3.0), 3.0)
    assert np.allclose(ring[0], ring[-1]) and len(ring) > 100
    assert np.allclose(corners, [[0, 0, 0], [2, 0, 0], [2, 2, 0], [0, 2, 0], [0, 0, 0]])
    data = player_data(motion)
    points = np.frombuffer(base64.b64decode(data["paths"][0]["points"]), "<f4").reshape(-1, 3)
    assert data["paths"][0]["name"] == "route" and np.allclose(points, ring, atol=1e-6)
    assert math.isclose(float(points[:, 0].max()), 3.0, rel_tol=1e-3)
    # the lateral error of the mass centre from the circle, and the nearest point on it
    distance = np.hypot(motion.com[:, 0], motion.com[:, 1] - 3.0)
    assert np.allclose(np.abs(motion.path_lateral[0]), np.abs(distance - 3.0), atol=1e-9)
    nearest = motion.path_nearest[0]
    assert np.allclose(np.hypot(nearest[:, 0], nearest[:, 1] - 3.0), 3.0)
    lateral = np.frombuffer(base64.b64decode(data["paths"][0]["lateral"]), "<f4")
    assert np.allclose(lateral, motion.path_lateral[0], atol=1e-6)
