"""A run that changed to a controller following another path (run.json's ``followed`` spans):
the player draws each path as followed only over its own spans, the others faded, and gives
the lateral error of the followed one only (before, every path was drawn followed, with its
lateral error, over the whole run)."""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path

import pytest
from anim_runs import creature_run, generated_dir
from chromium import Chromium
from external_tools import chromium

from legdsl.export.motion import Motion, load_motion
from legdsl.export.player import player_data, write_player

LINE = {"name": "route", "shape": "polyline", "points": [[0, 0], [10, 0]]}
RING = {"name": "route", "shape": "circle", "center": [0.0, 3.0], "radius": 3.0, "turn": 1}
SQUARE = {"name": "box", "shape": "polyline", "closed": True,
          "points": [[0, 0], [2, 0], [2, 2], [0, 2]]}  # fmt: skip


@pytest.fixture(scope="module")
def switched(tmp_path_factory: pytest.TempPathFactory) -> Motion:
    """The quadruped's 1 s drop, as if a controller following LINE had handed over at 0.4 s to
    one following RING, and SQUARE had been followed throughout."""
    run = creature_run("quadruped", tmp_path_factory.mktemp("switched") / "run")
    info = json.loads((run / "run.json").read_text())
    info["paths"] = [LINE | {"followed": [[0.0, 0.4]]}, RING | {"followed": [[0.4, 1.0]]}, SQUARE]
    (run / "run.json").write_text(json.dumps(info))
    return load_motion(run, generated=generated_dir())


def test_the_spans_are_in_the_motion_and_the_players_data(switched: Motion) -> None:
    assert switched.path_spans == (((0.0, 0.4),), ((0.4, 1.0),), None)
    data = player_data(switched)
    assert [p["followed"] for p in data["paths"]] == [[[0.0, 0.4]], [[0.4, 1.0]], None]


@pytest.fixture(scope="module")
def browser() -> Iterator[Chromium]:
    with Chromium(chromium(), 800, 450) as c:
        yield c


def test_each_path_is_drawn_followed_over_its_own_spans(
    browser: Chromium, switched: Motion, tmp_path: Path
) -> None:
    page = tmp_path / "animation.html"
    write_player(switched, page)
    browser.open_player(page)
    assert browser.errors() == []
    hud = "document.getElementById('hud').textContent"
    browser.evaluate("legdsl.setTime(0.2)")
    assert browser.evaluate("legdsl.pathsShown()") == [
        ["route", True], ["route", False], ["box", True]
    ]  # fmt: skip
    text = browser.evaluate(hud)
    assert "path route: not followed now (0.40 to 1.00 s)" in text
    assert text.count("lateral error") == 2  # the line's and the square's, not the ring's
    browser.evaluate("legdsl.setTime(0.8)")
    assert browser.evaluate("legdsl.pathsShown()") == [
        ["route", False], ["route", True], ["box", True]
    ]  # fmt: skip
    assert "path route: not followed now (0.00 to 0.40 s)" in browser.evaluate(hud)
    assert browser.errors() == []
