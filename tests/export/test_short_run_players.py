"""A run too short for two of the player's frames: `legdsl run --animate` and the API's
`run.animate()` refuse it as `legdsl animate` does (both wrote a one-frame player, a still
picture of a run that moved, without a word)."""

from __future__ import annotations

import base64
import json
import re
from pathlib import Path

import pytest
from anim_runs import generated_dir
from conftest import CREATURES

import legdsl
from legdsl.cli import main
from legdsl.lang.errors import UsageError

TIME = 0.01  # s: one frame at the player's 60 a second (recorded at 1000 Hz: 11 samples)


def stored_frames(page: Path) -> int:
    data = re.search(r'id="legdsl-data">(.*?)</script>', page.read_text(), re.S)
    assert data is not None
    return len(base64.b64decode(json.loads(data.group(1))["times"])) // 4


def test_run_animate_of_a_short_run_writes_no_one_frame_player(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "short"
    argv = ["run", str(CREATURES / "hopper.leg"), "--time", f"{TIME:g}", "--out", str(out)]
    argv += ["--record-rate", "1000Hz"]
    assert main([*argv, "--animate", "--generated", str(generated_dir())]) == 0
    said = capsys.readouterr().out
    advice = re.search(r"animation: not written .* two frames need --fps (\S+) or more", said)
    assert advice and f"legdsl animate {out}" in said, said
    assert not (out / "animation.html").exists()
    argv = ["animate", str(out), "--fps", advice.group(1), "--generated", str(generated_dir())]
    assert main(argv) == 0 and stored_frames(out / "animation.html") == 2  # as it advised


def test_the_apis_animate_refuses_a_short_run_and_takes_a_rate() -> None:
    run = legdsl.load(CREATURES / "hopper.leg", generated=generated_dir()).run(
        controller=None, time=TIME, record_rate="1000 Hz"
    )
    with pytest.raises(UsageError, match=r"fps=60 gives one frame .* need fps=\S+ or more") as no:
        run.animate()
    advice = re.search(r"need fps=(\S+) or more", str(no.value))
    assert advice is not None
    assert stored_frames(run.animate(fps=float(advice.group(1)))) == 2
    assert "two frames need fps=" in run._repr_html_()  # Jupyter's inline player says so
