"""What animate and export-motion tell a file named for the other command, and a frame rate
given as an angular velocity.

* ``export-motion runs/k -o x.htm`` said 'this writes GLB ...; name it x.glb': an .html or .htm
  name is the player's, which ``legdsl animate DIR -o x.htm`` writes (an .mp4 or .gif name:
  ``animate --video``); ``animate --video x.html`` is pointed to ``-o x.html``, and
  ``animate -o x.glb`` to ``export-motion``. The command told carries the run, --source and
  --generated given, quoted for a shell.
* ``--fps 3600rev/min`` was told 'write e.g. --fps 3600Hz': 3600 rev/min is 60 turns a
  second, so 60 Hz (any frequency option's advice: --record-rate too).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.cli import main
from legdsl.export.animate import frame_rate
from legdsl.lang.errors import UsageError
from legdsl.pipeline.options import RUN_NUMERIC, read_numeric


def refused(capsys: pytest.CaptureFixture[str], *argv: str) -> str:
    assert main(list(argv)) == 2
    return capsys.readouterr().err


def test_an_html_name_for_export_motion_points_to_animate(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    run = str(tmp_path / "sp ace")
    for name in ("x.htm", "x.html", "x.HTML"):
        out = str(tmp_path / name)
        said = refused(capsys, "export-motion", run, "-o", out, "--generated", "gen")
        assert f"legdsl animate '{run}' -o {out} --generated gen writes the HTML player" in said
        assert "name it" in said and said.count("\n") <= 3
    out = str(tmp_path / "x.mp4")
    said = refused(capsys, "export-motion", run, "-o", out)
    assert f"legdsl animate '{run}' --video {out} writes the video" in said


def test_a_video_named_html_points_to_the_players_option(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = str(tmp_path / "x.html")
    said = refused(capsys, "animate", "runs/k", "--video", out)
    assert f"write an .mp4 or a .gif (e.g. {tmp_path / 'x.mp4'})" in said
    assert f"the HTML player is written with -o {out}" in said
    out = str(tmp_path / "x.glb")
    said = refused(capsys, "animate", "runs/k", "--video", out)
    assert f"GLB is written by legdsl export-motion runs/k -o {out}" in said


def test_a_player_named_glb_points_to_export_motion(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = str(tmp_path / "x.glb")
    said = refused(capsys, "animate", "runs/k", "-o", out)
    assert (
        f"name it {tmp_path / 'x.html'}, or write GLB with legdsl export-motion runs/k -o {out}"
        in said
    )
    said = refused(capsys, "animate", "runs/k", "-o", str(tmp_path / "x.png"))
    assert f"name it {tmp_path / 'x.html'}" in said and "export-motion" not in said


def test_a_frame_rate_given_as_an_angular_velocity_is_converted() -> None:
    for given, told in (
        ("3600rev/min", "--fps 60Hz (3600rev/min is 60 turns a second)"),
        ("360deg/s", "--fps 1Hz (360deg/s is 1 turn a second)"),
        ("1rad/s", "--fps 0.159155Hz (1rad/s is 0.159155 turns a second)"),
    ):
        with pytest.raises(UsageError) as error:
            frame_rate(given)
        assert f"write e.g. {told}" in str(error.value)
    with pytest.raises(UsageError) as error:
        read_numeric("--record-rate", "12000rev/min", RUN_NUMERIC["record_rate"][1])
    assert "write e.g. --record-rate 200Hz (12000rev/min is 200 turns a second)" in str(error.value)
