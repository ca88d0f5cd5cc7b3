"""Programs from outside Python that some tests need: node with gltf-validator, Chromium, ffmpeg.

``.ci/run`` installs them all (Debian packages for chromium and ffmpeg, npm
for gltf-validator). A test that needs one skips, with the reason and the
install command, only if it is missing and cannot be installed from here.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import warnings
from pathlib import Path

import pytest
from conftest import ROOT

# The Khronos glTF validator, pinned; .ci/run installs this same version.
GLTF_VALIDATOR = "gltf-validator@2.0.0-dev.3.10"
TOOLS = Path(os.environ.get("LEGDSL_TOOLS", ROOT / ".tools"))


def loud_skip(reason: str) -> None:
    warnings.warn(f"SKIPPED: {reason}", stacklevel=2)
    pytest.skip(f"!!! {reason}")


def node_modules() -> Path:
    """A node_modules folder holding gltf-validator; installs it with npm if needed."""
    modules = TOOLS / "node_modules"
    package = modules / "gltf-validator" / "package.json"
    wanted = GLTF_VALIDATOR.split("@", 1)[1]
    if package.is_file() and json.loads(package.read_text()).get("version") == wanted:
        return modules
    if shutil.which("node") is None or shutil.which("npm") is None:
        loud_skip(
            "node and npm are needed to run the Khronos glTF validator: "
            f"apt-get install -y nodejs npm && npm install --prefix .tools {GLTF_VALIDATOR}"
        )
    done = subprocess.run(
        ["npm", "install", "--prefix", str(TOOLS), "--no-audit", "--no-fund", GLTF_VALIDATOR],
        capture_output=True,
        text=True,
        timeout=300,
    )
    if done.returncode != 0 or not package.is_file():
        loud_skip(f"could not install {GLTF_VALIDATOR} with npm: {done.stderr.strip()[-500:]}")
    return modules


def validate_gltf(path: Path) -> dict:
    """The Khronos validator's report on ``path`` (a .glb or .gltf file)."""
    modules = node_modules()
    script = Path(__file__).parent / "tools" / "validate_gltf.js"
    done = subprocess.run(
        ["node", str(script), str(path)],
        capture_output=True,
        text=True,
        timeout=120,
        env={**os.environ, "NODE_PATH": str(modules)},
    )
    assert done.returncode == 0, done.stderr
    return dict(json.loads(done.stdout))


def chromium() -> str:
    from chromium import find_chromium

    path = find_chromium()
    if path is None:
        loud_skip(
            "Chromium is needed for the browser test of the HTML player: "
            "apt-get install -y chromium"
        )
    assert path is not None
    return path


def ffmpeg() -> str:
    path = shutil.which("ffmpeg")
    if path is None:
        loud_skip("ffmpeg is needed to write and check .mp4 videos: apt-get install -y ffmpeg")
    assert path is not None
    return path


def ffprobe_frames(path: Path) -> tuple[int, int, int]:
    """A video's width, height and number of frames, as ffprobe reads them."""
    probe = subprocess.run(
        ["ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0", "-show_entries",
         "stream=width,height,nb_read_frames", "-of", "csv=p=0", str(path)],
        capture_output=True, text=True, check=True,
    )  # fmt: skip
    width, height, frames = (int(x) for x in probe.stdout.strip().split(","))
    return width, height, frames
