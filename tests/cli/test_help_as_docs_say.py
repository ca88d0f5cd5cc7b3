"""An outside user's audit of --help against the docs: README's export-motion formats left
out usdc, which --help offers; `metrics --help` gave --generated for the foot clearance at the
apex only (metrics.md: also the touchdown foot speed and the terrain margins); `replay --help`
gave no default for --fps (export.md: 30 for an mp4)."""

from __future__ import annotations

import argparse
import re
from pathlib import Path

from legdsl.cli import _parser
from legdsl.export.animate import MOTION_FORMATS

ROOT = Path(__file__).resolve().parents[2]


def _help(command: str, option: str) -> str:
    (sub,) = [a for a in _parser()._actions if isinstance(a, argparse._SubParsersAction)]
    (action,) = [a for a in sub.choices[command]._actions if option in a.option_strings]
    return " ".join(str(action.help).split())


def test_readme_lists_every_motion_format_help_offers() -> None:
    (listed,) = re.findall(
        r"legdsl export-motion DIR --format ([\w\\|]+)`", ROOT.joinpath("README.md").read_text()
    )
    assert listed.split("\\|") == list(MOTION_FORMATS)


def test_metrics_generated_help_names_every_row_it_is_for() -> None:
    said = _help("metrics", "--generated")
    assert "foot clearance at the apex" in said
    assert "foot speed at touchdown" in said and "margins to the terrain" in said


def test_replay_fps_help_gives_its_defaults() -> None:
    said = _help("replay", "--fps")
    assert "default 30 in an mp4" in said and "60 in the viewer" in said
    assert (
        "`--fps` (30 for an mp4, 60 in the viewer)" in ROOT.joinpath("docs/export.md").read_text()
    )
