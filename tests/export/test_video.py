"""Videos of runs: GIF through Pillow, mp4 through ffmpeg; the creature is in the picture."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import numpy as np
import pytest
from anim_runs import creature_motion
from external_tools import ffmpeg
from pixels import hue_mask

from legdsl.export.motion import Motion
from legdsl.export.video import render_video
from legdsl.lang.errors import UsageError


@pytest.fixture(scope="module")
def kangaroo(tmp_path_factory) -> Motion:
    return creature_motion("kangaroo", tmp_path_factory.mktemp("kangaroo") / "run")


@pytest.fixture(scope="module")
def quadruped(tmp_path_factory) -> Motion:
    return creature_motion("quadruped", tmp_path_factory.mktemp("quadruped") / "run")


def test_a_gif_of_a_planar_creature(kangaroo: Motion, tmp_path: Path) -> None:
    from PIL import Image

    path = tmp_path / "k.gif"
    seen: list[float] = []
    result = render_video(
        kangaroo, path, fps=10, size=(320, 180), progress=lambda t, _: seen.append(t)
    )
    times = list(np.arange(0.0, kangaroo.duration + 1e-9, 0.1))  # the kangaroo falls before 1 s
    assert result.frames == len(times) > 4 and result.size == path.stat().st_size
    assert seen == pytest.approx(times)
    with Image.open(path) as gif:
        assert gif.size == (320, 180) and gif.n_frames == len(times)
        assert gif.info["duration"] == 100
        frames = []
        for k in range(gif.n_frames):
            gif.seek(k)
            frames.append(np.asarray(gif.convert("RGB")).astype(float) / 255)
    trunk = kangaroo.bodies[0].color or ""
    assert hue_mask(frames[0], trunk).sum() > 200  # the brown body, a few hundred pixels
    assert np.abs(frames[-1] - frames[0]).max(axis=2).mean() > 0.002


def test_an_mp4_of_a_3d_creature(quadruped: Motion, tmp_path: Path) -> None:
    ffmpeg()
    path = tmp_path / "q.mp4"
    result = render_video(quadruped, path, fps=10, size=(320, 180))
    probe = subprocess.run(
        ["ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0", "-show_entries",
         "stream=codec_name,width,height,nb_read_frames", "-of", "json", str(path)],
        capture_output=True, text=True, check=True,
    )  # fmt: skip
    (stream,) = json.loads(probe.stdout)["streams"]
    assert stream["codec_name"] == "h264"
    assert (stream["width"], stream["height"]) == (320, 180)
    assert int(stream["nb_read_frames"]) == result.frames == 10  # samples to 0.9984 s, at 10 fps
    first = subprocess.run(
        ["ffmpeg", "-v", "error", "-i", str(path), "-frames:v", "1", "-f", "rawvideo",
         "-pix_fmt", "rgb24", "-"],
        capture_output=True, check=True,
    ).stdout  # fmt: skip
    image = np.frombuffer(first, dtype=np.uint8).reshape(180, 320, 3).astype(float) / 255
    assert hue_mask(image, quadruped.bodies[0].color or "").sum() > 300  # the green trunk


def test_mp4_without_ffmpeg_says_how_to_install_it(
    quadruped: Motion, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr("legdsl.export.video.shutil.which", lambda name: None)
    monkeypatch.setitem(__import__("sys").modules, "imageio_ffmpeg", None)  # no wheel either
    with pytest.raises(UsageError, match="apt-get install -y ffmpeg"):
        render_video(quadruped, tmp_path / "q.mp4")
    assert not list(tmp_path.iterdir())
    with pytest.raises(UsageError, match=r"\.mp4 or \.gif"):
        render_video(quadruped, tmp_path / "q.avi")


def test_an_ffmpeg_that_fails_is_told_as_ffmpegs_trouble(
    kangaroo: Motion, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """An ffmpeg that cannot start (a missing shared library) was legdsl's internal error."""
    broken = tmp_path / "bin" / "ffmpeg"
    broken.parent.mkdir()
    broken.write_text(
        '#!/bin/sh\necho "ffmpeg: error while loading shared libraries" >&2\nexit 127\n'
    )
    broken.chmod(0o755)
    monkeypatch.setattr("legdsl.export.video.shutil.which", lambda name: str(broken))
    with pytest.raises(UsageError, match=r"failed with exit status 127 \(it said: ffmpeg: error "
                       r"while loading shared libraries\); check that it runs"):  # fmt: skip
        render_video(kangaroo, tmp_path / "k.mp4", fps=10, size=(160, 96))
    assert not (tmp_path / "k.mp4").exists()


def test_a_force_arrow_longer_than_the_frame_is_clipped_not_dropped(kangaroo: Motion) -> None:
    """The side view's ground-force arrow stays drawn, its head at the frame's edge."""
    import dataclasses

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from legdsl.export.player import OVERLAYS
    from legdsl.export.video_views import SideView, clip_segment

    assert clip_segment((0.0, 0.0), (0.5, 3.0), (-1.0, -1.0, 1.0, 1.0)) == pytest.approx(
        (1 / 6, 1.0)
    )
    assert clip_segment((0.0, 0.0), (0.2, 0.3), (-1.0, -1.0, 1.0, 1.0)) == (0.2, 0.3)
    assert clip_segment((2.0, 0.0), (2.0, 0.3), (-1.0, -1.0, 1.0, 1.0)) is None

    stance = np.flatnonzero(kangaroo.forces[:, 0, 2] > 0)
    assert len(stance)
    strong = dataclasses.replace(kangaroo, forces=kangaroo.forces * 50.0)  # far past the frame
    fig = plt.figure(figsize=(3.2, 1.8), dpi=100)
    try:
        ax = fig.add_axes((0, 0, 1, 1))
        view = SideView(strong, ax, OVERLAYS, 320 / 180)
        view.update(strong.at(float(strong.times[stance[len(stance) // 2]])))
        arrow = view.arrows[0]
        assert arrow.get_visible()
        (x0, x1), (z0, z1) = ax.get_xlim(), ax.get_ylim()
        x, z = arrow.xy
        assert x0 <= x <= x1 and z0 <= z <= z1
        assert z == pytest.approx(z1 - 0.02 * (z1 - z0), rel=1e-6)  # at the top edge's margin
        fig.canvas.draw()
        image = np.asarray(fig.canvas.buffer_rgba())[..., :3].astype(float) / 255
        assert hue_mask(image, "#d2401e").sum() > 20  # the arrow's colour is on the picture
    finally:
        plt.close(fig)


def test_mp4_with_only_the_imageio_ffmpeg_wheel(
    kangaroo: Motion, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """No system ffmpeg: the binary in the imageio-ffmpeg wheel encodes the mp4."""
    imageio_ffmpeg = pytest.importorskip("imageio_ffmpeg")
    monkeypatch.setattr("legdsl.export.video.shutil.which", lambda name: None)
    path = tmp_path / "k.mp4"
    result = render_video(kangaroo, path, fps=5, size=(160, 90))
    assert result.frames > 2 and path.stat().st_size > 1000
    assert path.read_bytes()[4:8] == b"ftyp"
    assert "imageio_ffmpeg" in imageio_ffmpeg.get_ffmpeg_exe()
