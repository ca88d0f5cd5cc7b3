"""Random rigs (tests/random_rigs.py) through the HTML player, in headless Chromium.

Each rig runs passively for 0.3 s (Python backend, recorded at 100 Hz; half of them with the
default fall rules, as tests/export/test_random_rig_exports.py, so some end by a fall or a
divergence), ``legdsl animate RUN -o X.html --fps F`` writes the player (F drawn from 25 to
100 per second), and the page is opened: no console error or warning from it; at four stored
frames the camera is finite, the picture holds the creature (each link recoloured in the page
to its own hue, so its pixels are known) where a link stands clear of the ground in view, and
the ground is drawn (hidden, the picture changes), at the point inside a step or box when that
is in view; a link that moved on the screen between two of those times changed its pixels;
and at the last frame (the first if the last is far out) every link in view, drawn alone (no
other link, no ground), shows. Frames at which a diverged run's links are more than ``FAR`` m out are only checked for
a finite camera (float32 poses that far out cannot place a small creature's links); seed 125's
player, its last frame 2e7 m out, is checked by default too.

``LEGDSL_RANDOM_PLAYER=N`` checks N rigs (default ``CI_RIGS``) from seed
``LEGDSL_RANDOM_PLAYER_SEED``, +1, ...; a failure names its seed and prints the rig's text.
"""

from __future__ import annotations

import math
import os
import re
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest
from chromium import Chromium
from external_tools import chromium
from pixels import hue_mask, pixels
from runtime_helpers import legdsl_in_process
from seeded import told_with_seed

from legdsl.export.motion import Motion, load_motion, quaternion_to_matrix, terrain_height
from legdsl.export.shapes import body_mesh

pytest.importorskip("mujoco")  # the rigs are placed on their ground by MuJoCo's kinematics
from random_rigs import recorded_rig, rig_shown  # noqa: E402

CI_RIGS = 1
COUNT = int(os.environ.get("LEGDSL_RANDOM_PLAYER", CI_RIGS))
FIRST_SEED = int(os.environ.get("LEGDSL_RANDOM_PLAYER_SEED", "0"))
DURATION = 0.3
WIDTH, HEIGHT = 800, 480
FAR = 1e3  # m: beyond this a diverged run's picture is not checked, only its camera
FRAME_RATES = (25.0, 30.0, 50.0, 60.0, 100.0)
OVERLAYS = ("state", "speed", "forces", "footprints", "com")


@pytest.fixture(scope="module")
def browser() -> Iterator[Chromium]:
    with Chromium(chromium(), WIDTH, HEIGHT) as c:
        yield c


def hue(k: int, n: int) -> str:
    """The k-th of n saturated colours, their hues spread round the circle."""
    import colorsys

    r, g, b = colorsys.hsv_to_rgb(k / max(n, 1), 0.9, 0.85)
    return f"#{round(r * 255):02x}{round(g * 255):02x}{round(b * 255):02x}"


def complaints(browser: Chromium) -> list[str]:
    """The page's console errors and warnings, and uncaught exceptions."""
    out = list(browser.errors())
    for e in browser.events:
        method, params = e.get("method"), e.get("params", {})
        if method == "Runtime.consoleAPICalled" and params.get("type") == "warning":
            out.append(" ".join(str(a.get("value", a.get("description"))) for a in params["args"]))
        elif method == "Log.entryAdded" and params["entry"]["level"] == "warning":
            out.append(params["entry"]["text"])
    # SwiftShader's note that the test's own screenshots read the picture back
    return [c for c in out if "GPU stall due to ReadPixels" not in c]


def recorded_run(seed: int, where: Path, fps: float | None = None) -> tuple[Motion, Path, int]:
    """The rig's 0.3 s run as the player has it, the player written for it, the run's status.

    Stored at ``fps`` frames per second, by default one drawn from ``FRAME_RATES`` (a diverged
    run's last sample, its coordinates huge, is a frame when the rate's frames fall on it)."""
    _, status = recorded_rig(seed, where, DURATION, 100.0)
    generated, run_dir = where / "generated", where / "run"
    page = where / "player.html"
    if fps is None:
        fps = float(np.random.default_rng([seed, 11]).choice(FRAME_RATES))
    argv = ["animate", str(run_dir), "-o", str(page), "--generated", str(generated)]
    done, said = legdsl_in_process([*argv, "--fps", repr(fps)])
    advice = re.search(r"two frames need --fps (\S+) or more", said)
    if done == 2 and advice:  # a run too short for two frames at the rate
        fps = float(advice.group(1))
        done, said = legdsl_in_process([*argv, "--fps", advice.group(1)])
    assert done == 0, f"legdsl animate: {done}: {said}"
    return load_motion(run_dir, fps=fps, generated=generated), page, status


def creature_pixels(image: np.ndarray, colors: list[str]) -> np.ndarray:
    masks = [hue_mask(image, c, tolerance=0.02) for c in colors]
    return np.logical_or.reduce(masks) if masks else np.zeros(image.shape[:2], bool)


def on_screen(browser: Chromium, xy: list[float]) -> bool:
    """Whether a point drawn at ``xy`` is inside the picture (not under the control bar)."""
    r = browser.evaluate("document.querySelector('#view canvas').getBoundingClientRect().toJSON()")
    inside = r["left"] + 1 < xy[0] < r["right"] - 1 and r["top"] + 1 < xy[1] < r["bottom"] - 1
    return all(math.isfinite(v) for v in xy) and inside


def drawn_centre(browser: Chromium, points: np.ndarray) -> tuple[float, float] | None:
    """The mean of where ``points`` are drawn, of those in view; None when none is."""
    if len(points) == 0:
        return None
    listed = [[float(v) for v in p] for p in points]
    xy = browser.evaluate(DRAWN.replace("POINTS", str(listed)))
    return None if xy is None else (float(xy[0]), float(xy[1]))


def visible_points(motion: Motion, frame: int) -> list[np.ndarray]:
    """Per link, its mesh's vertices at ``frame`` that stand clear of the ground (in world
    coordinates): a link under the ground plane is hidden by it."""
    out = []
    for b, body in enumerate(motion.bodies):
        turn = quaternion_to_matrix(motion.quaternions[frame, b])
        world = body_mesh(body).positions @ turn.T + motion.positions[frame, b]
        ground = np.array([terrain_height(motion.terrain, x, y) for x, y, _ in world])
        out.append(world[world[:, 2] > ground + 1e-3])
    return out


def in_view(browser: Chromium, points: np.ndarray) -> bool:
    """Whether any of ``points`` is drawn inside the picture, in front of the camera."""
    return drawn_centre(browser, points) is not None


# The mean of where the points POINTS are drawn, of those in front of the camera and inside
# the picture; null when none is.
DRAWN = """(() => {
  const e = legdsl.cameraPosition(), a = legdsl.cameraTarget();
  const r = document.querySelector("#view canvas").getBoundingClientRect();
  const seen = POINTS.filter((p) => (p[0] - e[0]) * (a[0] - e[0]) + (p[1] - e[1]) * (a[1] - e[1])
    + (p[2] - e[2]) * (a[2] - e[2]) > 0).map((p) => legdsl.project(...p))
    .filter(([x, y]) => x > r.left + 1 && x < r.right - 1 && y > r.top + 1 && y < r.bottom - 1);
  if (!seen.length) return null;
  return [0, 1].map((k) => seen.reduce((s, p) => s + p[k], 0) / seen.length);
})()"""


def feature_point(
    kind: str, p: dict[str, float], planar: bool, aim: list[float]
) -> tuple[float, float, float] | None:
    """A point inside a raised step or box (None for a slope, or a feature at the floor)."""
    if kind == "step" and p["height"] > 0:
        return (p["x"] + 0.02, aim[1], p["height"] / 2)
    if kind == "box" and p["height"] > 0:
        y = 0.0 if planar else (p["y0"] + p["y1"]) / 2
        return ((p["x0"] + p["x1"]) / 2, y, p["height"] / 2)
    return None


def check_rig(browser: Chromium, recorded: tuple[Motion, Path, int]) -> None:
    """The checks of the module's docstring on ``recorded_run``'s answer."""
    motion, page, status = recorded
    names = [b.name for b in motion.bodies]
    colors = [hue(k, len(names)) for k in range(len(names))]
    browser.events.clear()
    browser.open_player(page)
    assert complaints(browser) == [], "the page complained on opening"
    frames = browser.evaluate("legdsl.frames")
    assert frames == motion.frames  # one when the run fell at its first sample
    off = ", ".join(f"{o}: false" for o in OVERLAYS)
    browser.evaluate(
        "legdsl.setOverlays({" + off + "}); document.getElementById('hud').style.display = 'none';"
        f"const names = {names}, colors = {colors};"
        "names.forEach((n, k) => legdsl.scene.getObjectByName(n).material.color.set(colors[k]));"
    )
    links = f"{names}.map((n) => legdsl.scene.getObjectByName(n))"
    terrain = (
        "legdsl.scene.children.filter((o) => (o.isMesh && o.geometry.type === 'BoxGeometry')"
        " || (o.isGroup && o.children.length === 1 && o.children[0].geometry.type === 'PlaneGeometry'))"
    )
    previous: list[tuple[np.ndarray, tuple[float, float] | None]] | None = None
    for f in sorted({round(k * (frames - 1) / 3) for k in range(4)}):
        t = float(motion.times[f])
        browser.evaluate(f"legdsl.setTime({t!r})")
        eye = browser.evaluate("legdsl.cameraPosition()")
        aim = browser.evaluate("legdsl.cameraTarget()")
        assert all(isinstance(v, float | int) and math.isfinite(v) for v in eye + aim), (
            f"t = {t:g} s: the camera is at {eye} looking at {aim}"
        )
        if not np.abs(motion.positions[f]).max() < FAR:
            previous = None
            continue
        # and it looks at the creature (a diverged last frame once lifted it 1e7 m throughout)
        distance = browser.evaluate("legdsl.getView().distance")
        assert math.dist(aim, motion.com[f]) < 10 * distance, f"t = {t:g} s: looking at {aim}"
        image = pixels(browser.screenshot())
        clear = visible_points(motion, f)
        if any(in_view(browser, p) for p in clear):
            assert creature_pixels(image, colors).sum() > 0, f"t = {t:g} s: no link drawn"
        # where a link moved on the screen, its pixels changed
        now = [
            (hue_mask(image, c, tolerance=0.02), drawn_centre(browser, p))
            for c, p in zip(colors, clear, strict=True)
        ]
        for b, ((mask0, xy0), (mask1, xy1)) in enumerate(zip(previous or now, now, strict=True)):
            moved = xy0 is not None and xy1 is not None and math.dist(xy0, xy1) > 4
            if moved and mask0.any() and mask1.any():
                assert (mask0 != mask1).any(), (
                    f"t = {t:g} s: link {names[b]} moved, its pixels did not"
                )
        previous = now
        # the ground and terrain: hidden (the links too), the picture changes, and it changes
        # where a point inside a raised feature is drawn, when that is in view before the fog
        browser.evaluate(f"{links}.forEach((m) => (m.visible = false)); legdsl.redraw()")
        with_ground = pixels(browser.screenshot())
        browser.evaluate(f"{terrain}.forEach((o) => (o.visible = false)); legdsl.redraw()")
        bare = np.abs(pixels(browser.screenshot()) - with_ground).max(axis=2) > 0.02
        browser.evaluate(
            f"{terrain}.forEach((o) => (o.visible = true));"
            f"{links}.forEach((m) => (m.visible = true)); legdsl.redraw()"
        )
        assert bare.mean() > 0.01, f"t = {t:g} s: no ground drawn"
        fog = 1.5 * browser.evaluate("legdsl.getView().distance")
        for feature in motion.terrain:
            inside = feature_point(feature.kind, dict(feature.params), motion.planar, aim)
            if inside is None or math.dist(inside, eye) > fog:
                continue
            xy = browser.evaluate(f"legdsl.project(...{[float(v) for v in inside]})")
            if on_screen(browser, xy):
                x, y = round(xy[0]), round(xy[1])
                assert bare[max(0, y - 1) : y + 2, max(0, x - 1) : x + 2].any(), (
                    f"t = {t:g} s: the {feature.kind} at {inside} is not drawn at {xy}"
                )
    # every link in view, drawn alone (no other link, no ground to hide it), shows at the last
    # frame (the first when the last is far out)
    far = not np.abs(motion.positions[-1]).max() < FAR
    browser.evaluate(f"{terrain}.forEach((o) => (o.visible = false))")
    for f in (0,) if far else (motion.frames - 1,):
        browser.evaluate(f"legdsl.setTime({float(motion.times[f])!r})")
        for b, (name, body) in enumerate(zip(names, motion.bodies, strict=True)):
            turn = quaternion_to_matrix(motion.quaternions[f, b])
            if not in_view(browser, body_mesh(body).positions @ turn.T + motion.positions[f, b]):
                continue
            browser.evaluate(f"{links}.forEach((m, k) => (m.visible = k === {b})); legdsl.redraw()")
            alone = hue_mask(pixels(browser.screenshot()), colors[b], tolerance=0.02).sum()
            assert alone > 0, f"link {name} is not drawn at t = {motion.times[f]:g} s"
        browser.evaluate(f"{links}.forEach((m) => (m.visible = true))")
    assert complaints(browser) == [], f"the page complained (run status {status})"


SEEDS = range(FIRST_SEED, FIRST_SEED + COUNT)


@pytest.mark.parametrize("seed", SEEDS)
def test_the_player_draws_a_random_rig(browser: Chromium, seed: int, tmp_path: Path) -> None:
    rerun = f"LEGDSL_RANDOM_PLAYER_SEED={seed} LEGDSL_RANDOM_PLAYER=1"
    with told_with_seed(f"random rig of seed {seed}", rerun, lambda: rig_shown(seed, tmp_path)):
        check_rig(browser, recorded_run(seed, tmp_path))


@pytest.fixture(scope="module")
def diverged(tmp_path_factory: pytest.TempPathFactory) -> tuple[Motion, Path, int]:
    """Seed 125's run: it diverges at 0.12 s, its last sample 2e7 m out; at 50 frames per
    second that sample is the player's last frame."""
    motion, page, status = recorded_run(125, tmp_path_factory.mktemp("rig125"), fps=50.0)
    assert status == 3 and np.abs(motion.positions[-1]).max() > 1e6
    return motion, page, status


def test_a_player_of_a_diverged_run_loads_with_a_finite_camera(
    browser: Chromium, diverged: tuple[Motion, Path, int]
) -> None:
    check_rig(browser, diverged)  # every frame before the last checked in full


def test_a_diverged_frame_far_above_does_not_lift_the_camera_for_the_whole_run(
    diverged: tuple[Motion, Path, int],
) -> None:
    """A planar run whose last frame flew 1e7 m up (a diverged step) raised the camera's target
    by 1e7 m at every frame within the lift's easing window (here the whole run): the player
    and the video showed empty sky. The far frame is not followed now."""
    import dataclasses

    from legdsl.export.player import camera_hints
    from legdsl.export.player.camera import camera_lift

    motion = dataclasses.replace(diverged[0], planar=True)
    up = motion.positions[-2] + [0.0, 0.0, 1e7]
    positions = np.concatenate([motion.positions[:-1], up[None]])
    com = np.concatenate([motion.com[:-1], motion.com[-2:-1] + [0.0, 0.0, 1e7]])
    far = dataclasses.replace(motion, positions=positions, com=com)
    near = dataclasses.replace(
        motion,
        positions=positions[:-1],
        com=com[:-1],
        times=motion.times[:-1],
        quaternions=motion.quaternions[:-1],
    )
    hints = camera_hints(near)
    kept = camera_lift(near, hints["lookHeight"], hints["distance"], hints["size"])
    lift = camera_lift(far, hints["lookHeight"], hints["distance"], hints["size"])
    assert np.allclose(lift[:-1], kept, atol=hints["size"]), lift
