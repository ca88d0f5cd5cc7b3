"""``legdsl replay DIR --mujoco``: a recorded run played in MuJoCo's viewer, or rendered by
MuJoCo's offscreen renderer to an mp4 (``legdsl.export.mjreplay``); the command-line side.

Importing it is cheap (MuJoCo is imported when the command runs)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from legdsl.export.animate import Command, frame_rate, parse_size, video_fps
from legdsl.lang.errors import UsageError
from legdsl.pipeline.outputs import made_note, messages_for, new_directory, not_a_stream


def _cmd_replay(args: argparse.Namespace) -> int:
    from legdsl.export import mjreplay

    if not args.mujoco:
        raise UsageError("replay: say where: --mujoco (the only player for now)")
    args.fps = frame_rate(args.fps)
    source = Path(args.source) if args.source else None
    run = Path(args.run)
    if args.output is None and mjreplay.has_display():
        mjreplay.view(run, video_fps(args.fps, 60.0), source)
        return 0
    out = Path(args.output) if args.output else run / "mujoco.mp4"
    not_a_stream(out, "-o")
    if out.suffix.lower() != ".mp4":  # ffmpeg's format is the name's
        better = out.with_suffix(".mp4") if out.suffix else f"{out}.mp4"
        raise UsageError(f"-o {out}: MuJoCo's frames are written as an .mp4; name it {better}")
    if args.output is None:
        print(
            "legdsl: no display for MuJoCo's viewer: rendering offscreen instead", file=sys.stderr
        )
    made = new_directory(out)
    frames = mjreplay.render_mp4(
        run, out, video_fps(args.fps, 30.0), parse_size(args.size or "960x540"), source
    )
    if made is not None:
        print(f"legdsl: {made_note(made, out)}", file=messages_for(out))
    counted = f"{frames} frame{'s' if frames != 1 else ''}"  # a one-sample run: "1 frame"
    print(f"legdsl: wrote {out} ({counted}, MuJoCo's renderer)", file=messages_for(out))
    return 0


def add_replay_parser(sub: Any) -> Command:
    r = sub.add_parser(
        "replay",
        help="play a recorded run in MuJoCo's viewer (or render it with MuJoCo to an mp4)",
        description="Play a run directory on the creature's MJCF export in MuJoCo: each frame "
        "sets MuJoCo's joint positions from the run (MuJoCo simulates nothing). With a display "
        "and no -o, MuJoCo's interactive viewer plays it in real time, looping; otherwise "
        "MuJoCo's offscreen renderer (MUJOCO_GL=egl by default) draws it into an mp4 (ffmpeg).",
        epilog="Example: legdsl replay runs/biped --mujoco -o biped-mujoco.mp4",
    )
    r.add_argument("run", metavar="DIR", help="a run directory written by legdsl run")
    r.add_argument("--mujoco", action="store_true", help="play it in MuJoCo")
    r.add_argument("-o", "--output", metavar="FILE.mp4", help="render to this mp4 instead")
    r.add_argument(
        "--fps",
        default=None,
        metavar="N",
        help="frames per second, or 30Hz (default 30 in an mp4, 60 in the viewer)",
    )
    r.add_argument("--size", metavar="WxH", help="mp4 size in pixels (default 960x540)")
    r.add_argument(
        "--source", metavar="FILE", help="the .leg file, if run.json's path is not found from here"
    )
    return _cmd_replay
