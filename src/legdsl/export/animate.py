"""``legdsl animate`` and ``legdsl export-motion``: the command-line side of the animation exports
(``legdsl replay``'s is ``legdsl.export.replay_cli``).

* ``legdsl animate DIR [-o FILE.html]`` writes the HTML player (``legdsl.export.formats.formats.player``);
* ``legdsl animate DIR --video FILE.mp4|FILE.gif`` renders a video (``legdsl.export.formats.formats.video``);
* ``legdsl export-motion DIR --format glb|gltf|usd|usda|usdc|bvh [-o FILE]`` writes glTF 2.0, USD or BVH (``legdsl.export.gltf``, ``usd``, ``bvh``);
* ``legdsl run ... --animate`` calls ``animate_result`` after writing the run.

This module only parses arguments and reports; importing it is cheap, so the
CLI can build its parser without loading numpy, matplotlib or pygltflib.
"""

from __future__ import annotations

import argparse
import math
import re
import shlex
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

from legdsl.export.ending import ending_note
from legdsl.export.video_rates import frame_rate, most_fps, positive, video_fps
from legdsl.lang.errors import UsageError
from legdsl.pipeline.outputs import (
    is_stream,
    made_note,
    messages_for,
    named_as,
    new_directory,
    not_a_stream,
)

OVERLAY_NAMES = ("state", "speed", "forces", "footprints", "com")
Command = Callable[[argparse.Namespace], int]


def human_size(n: int) -> str:
    if n < 1024:
        return f"{n} B"
    if n < 1024 * 1024:
        return f"{n / 1024:.1f} KiB"
    return f"{n / (1024 * 1024):.2f} MiB"


def seconds_text(span: float) -> str:
    """A run's length for a summary line: 0.01 s and more to the hundredth, as before, shorter
    to three digits (a 4.5 ms clip was "0.00 s of motion")."""
    return f"{span:.2f} s" if span >= 0.01 or span == 0 else f"{span:.3g} s"


def parse_overlays(text: str) -> tuple[str, ...]:
    if text.strip().lower() == "none":
        return ()
    names = tuple(x.strip() for x in text.split(",") if x.strip())
    if "none" in (x.lower() for x in names):
        raise UsageError(
            f"--overlays {text}: 'none' stands alone (no overlay shown at first); "
            "write --overlays none, or list only the overlays to show"
        )
    unknown = [x for x in names if x not in OVERLAY_NAMES]
    if unknown:
        raise UsageError(
            f"--overlays: unknown {', '.join(unknown)}; choose from {', '.join(OVERLAY_NAMES)} or none"
        )
    return names


VIDEO_SIZE = (64, 64), (7680, 4320)  # pixels: the least, and 8K UHD, the largest


def parse_size(text: str) -> tuple[int, int]:
    match = re.fullmatch(r"\s*(\d+)\s*[xX]\s*(\d+)\s*", text)
    if not match:
        raise UsageError(f"--size {text!r}: write WIDTHxHEIGHT in pixels, e.g. 960x540")
    width, height = int(match.group(1)), int(match.group(2))
    (least_w, least_h), (most_w, most_h) = VIDEO_SIZE
    # a size well written but out of range is said so: told the format, 8192x4320 looked for a typo
    if width > most_w or height > most_h:
        raise UsageError(
            f"--size {text.strip()}: too large; a video is at most {most_w} pixels wide and "
            f"{most_h} high (--size {most_w}x{most_h}, 8K)"
        )
    if width < least_w or height < least_h:
        raise UsageError(
            f"--size {text.strip()}: too small; a video is at least {least_w}x{least_h} pixels"
        )
    if width % 2 or height % 2:  # H.264's colour planes are half size: 961x541 was drawn 960x540
        raise UsageError(
            f"--size {text}: a video's width and height are even numbers of pixels; "
            f"write --size {width + width % 2}x{height + height % 2}"
        )
    return width, height


def _load(
    args: argparse.Namespace, fps: float, video: tuple[float, float, float] | None = None
) -> Any:
    from legdsl.export.motion import load_motion

    return load_motion(
        Path(args.run),
        fps=fps,
        generated=Path(args.generated),
        source=Path(args.source) if args.source else None,
        video=video,
    )


# ---------------------------------------------------------------- legdsl animate


def _say_note(motion: Any, run: str | None = None, out: object = None) -> None:
    """The motion's note (a stance of few keyframes) on standard error, where one was made;
    with ``run`` and ``out``, also how the run ended where it did not end ok (it fell, was
    interrupted: a BVH file has no place to say it)."""
    if motion.note:
        print(motion.note, file=sys.stderr)
    if run is not None and (told := ending_note(motion, run, str(out))):
        print(told, file=sys.stderr)


def _say_made(made: Path | None, out: Path, say: Any) -> None:
    """``legdsl: made directory DIR/`` where writing ``out`` made it (``-o /new/x.glb``)."""
    if made is not None:
        print(f"legdsl: {made_note(made, out)}", file=say)


def written_by(path: str, args: argparse.Namespace) -> str | None:
    """The command that writes a file named as ``path`` is (the player, a video, a motion
    export) from the run ``args`` name (with their --source and --generated), or None for a
    name none of them writes."""
    suffix = Path(path).suffix.lower()
    if suffix in (".html", ".htm"):
        words = ["animate", args.run, "-o", path]
    elif suffix in (".mp4", ".gif"):
        words = ["animate", args.run, "--video", path]
    elif suffix[1:] in MOTION_FORMATS:
        words = ["export-motion", args.run, "-o", path]
    else:
        return None
    words += ["--source", args.source] if args.source else []
    words += ["--generated", args.generated] if args.generated != "generated" else []
    return shlex.join(["legdsl", *words])


def _player_name(output: str | None, args: argparse.Namespace) -> None:
    """``-o`` names the HTML player: a video's or another format's name would hold HTML."""
    suffix = Path(output).suffix.lower() if output else ""
    if suffix in (".mp4", ".gif"):
        raise UsageError(
            f"-o {output}: -o writes the HTML player; render a video with --video {output}"
        )
    other = written_by(output, args) if output and suffix not in (".html", ".htm") else None
    if output and other:  # a .glb: the player's name, or export-motion, which writes glTF
        better = Path(output).with_suffix(".html")
        raise UsageError(
            f"-o {output}: this writes the HTML player; name it {better}, or write "
            f"{suffix[1:].upper()} with {other}"
        )
    if output:
        named_as(output, "-o", (".html", ".htm"), "the HTML player")


def _cmd_animate(args: argparse.Namespace) -> int:
    _player_name(args.output, args)
    overlays = parse_overlays(args.overlays)
    args.fps = frame_rate(args.fps)
    run = Path(args.run)
    for flag, given in (("--slow-motion", args.slow_motion), ("--size", args.size)):
        if given is not None and not args.video:  # the player has its own speed and window
            raise UsageError(f"{flag} is for a video: add --video FILE.mp4 (or .gif)")
    if args.video:
        from legdsl.export.video import render_video, stderr_progress

        video = Path(args.video)
        not_a_stream(video, "--video")
        # GIFs compress poorly (every frame moves with the camera): smaller by default.
        size = parse_size(args.size or ("640x360" if video.suffix.lower() == ".gif" else "960x540"))
        if video.suffix.lower() not in (".mp4", ".gif"):  # ffmpeg's format is the name's
            better = video.with_suffix(".mp4") if video.suffix else f"{video}.mp4"
            other = written_by(args.video, args)  # the player's name, or a glTF's
            player = video.suffix.lower() in (".html", ".htm")
            also = (f"; the HTML player is written with -o {shlex.quote(args.video)}" if player
                    else f"; {video.suffix[1:].upper()} is written by {other}" if other else "")  # fmt: skip
            raise UsageError(f"--video {video}: write an .mp4 or a .gif (e.g. {better}){also}")
        gif = video.suffix.lower() == ".gif"
        fps = video_fps(args.fps, 30.0, gif)
        slow = args.slow_motion if args.slow_motion is not None else 1.0
        positive(slow, "--slow-motion")
        motion = _load(args, max(fps * slow, 60.0), video=(fps, slow, most_fps(gif)))
        _say_note(motion, args.run, video)
        made = new_directory(video)
        progress = stderr_progress()
        try:
            result = render_video(motion, video, fps, size, overlays, progress=progress, slow=slow)
        finally:  # a render stopped short (Ctrl-C, ffmpeg failing): its bar's line ended first
            if progress is not None:
                progress.end()
        slowed = f", {slow:g} times slower" if slow != 1.0 else ""
        _say_made(made, video, messages_for(args.output, args.video))
        # the video's own frames, every 1/(fps slow) of the run, read from keyframes 60 per
        # second at least: an --fps ends them at the last sample only above that
        named = slow if fps * slow >= 60.0 else None
        left = _end_left(motion, fps * slow, named, (result.span, result.frames))
        print(
            f"legdsl: wrote {video} ({human_size(result.size)}, {result.frames} "
            f"frame{'s' if result.frames != 1 else ''} at "
            f"{fps:g} fps, {seconds_text(result.span)} of motion{slowed}) in {result.seconds:.1f} s"
            + left,
            file=messages_for(args.output, args.video),
        )
        if not args.output:
            return 0
        motion = _load(args, 60.0)  # the player's own rate, and its own note
        said = True  # how the run ended: said once, with the video
    else:
        motion = _load(args, args.fps or 60.0)
        said = False
    from legdsl.export.player import write_player

    out = Path(args.output) if args.output else run / "animation.html"
    made = new_directory(out)
    size_bytes = write_player(motion, out, overlays)
    _say_note(motion, None if said else args.run, out)
    _say_made(made, out, messages_for(args.output))
    browse = "" if is_stream(out) else "; open it in a web browser"  # not /dev/null's
    print(
        f"legdsl: wrote {out} ({human_size(size_bytes)}, {motion.frames} frames, "
        f"{seconds_text(motion.duration)}){browse}{_end_left(motion, args.fps or 60.0)}",
        file=messages_for(args.output),
    )
    return 0


def add_animate_parser(sub: Any) -> Command:
    a = sub.add_parser(
        "animate",
        help="play a recorded run: an HTML player, or an .mp4/.gif video",
        description="Write a self-contained HTML player for a run directory (no network or server "
        "needed: open it in a browser): the creature's links as solids in their .leg shapes and "
        "colours, the ground and terrain, a following camera, play/pause, a time scrubber, "
        "playback speed from 0.1x to 2x and overlays (controller state, commanded and actual "
        "speed, ground-force arrows, footprints, mass-centre trail). With --video, render the "
        "same view to an .mp4 (needs ffmpeg) or a .gif instead.",
        epilog="Example: legdsl run creatures/kangaroo.leg --time 3 --drop 0.1 --out runs/k && "
        "legdsl animate runs/k && legdsl animate runs/k --video runs/k/hop.mp4",
    )
    a.add_argument("run", metavar="DIR", help="a run directory written by legdsl run")
    a.add_argument(
        "-o",
        "--output",
        metavar="FILE.html",
        help="the player to write (default DIR/animation.html)",
    )
    a.add_argument(
        "--video",
        metavar="FILE",
        help="render a video (.mp4 through ffmpeg, or .gif) instead of the player",
    )
    a.add_argument(
        "--fps",
        metavar="N",
        help="frames per second: stored in the player (default 60; it interpolates between "
        "them) or rendered into the video (default 30)",
    )
    a.add_argument(
        "--slow-motion",
        type=float,
        metavar="F",
        help="render the video F times slower than real time (default 1; a small creature's "
        "hops may need 10 or more: a note says so)",
    )
    a.add_argument(
        "--size",
        metavar="WxH",
        help="video size in pixels (default 960x540 for .mp4, 640x360 for .gif)",
    )
    a.add_argument(
        "--overlays",
        default=",".join(OVERLAY_NAMES),
        metavar="LIST",
        help="overlays shown at first (the player can toggle them): comma-separated from "
        f"{', '.join(OVERLAY_NAMES)}, or none (default: all)",
    )
    a.add_argument(
        "--source", metavar="FILE", help="the .leg file, if run.json's path is not found from here"
    )
    a.add_argument(
        "--generated",
        default="generated",
        metavar="DIR",
        help="where generated modules live (default generated/)",
    )
    return _cmd_animate


# ---------------------------------------------------------------- legdsl export-motion


MOTION_FORMATS = ("glb", "gltf", "usd", "usda", "usdc", "bvh")
# a .usd file holds either USD encoding; a binary one may be named .usdc
_USD_NAMES = {("usda", "usd"), ("usd", "usdc"), ("usdc", "usd")}


def motion_format(given: str | None, output: str | None) -> str:
    """``--format``, or the one ``-o``'s name says, or glb; a name that says another format
    than ``--format`` is a mistake (a USD layer named .glb), except USD in a .usd file and
    binary USD in a .usdc one. A .usdz package is refused with the USD names it can take."""
    named = Path(output).suffix[1:].lower() if output else ""
    if named == "usdz":
        raise UsageError(
            f"-o {output}: a .usdz package is not written; write the stage as "
            f"{Path(output or '').with_suffix('.usd')} (binary, or .usdc) or as .usda (text), "
            "and package it with usd-core's usdzip if a .usdz is needed"
        )
    if named not in MOTION_FORMATS:
        return given or "glb"
    if given is not None and given != named and (given, named) not in _USD_NAMES:
        raise UsageError(
            f"-o {output}: a .{named} name, but --format {given}; name the file "
            f"{Path(output or '').stem}.{given}, or leave out --format"
        )
    return given or named


def _cmd_export_motion(args: argparse.Namespace) -> int:
    args.fps = frame_rate(args.fps)
    args.format = motion_format(args.format, args.output)
    out = Path(args.output) if args.output else Path(args.run) / f"motion.{args.format}"
    if args.output and Path(args.output).suffix.lower() in (".html", ".htm", ".mp4", ".gif"):
        raise UsageError(  # the player's or a video's name: animate writes those
            f"-o {args.output}: export-motion writes glTF, USD or BVH (name it "
            f"{out.with_suffix('.' + args.format)}); {written_by(args.output, args)} "
            f"writes the {'HTML player' if out.suffix.lower() in ('.html', '.htm') else 'video'}"
        )
    named = {"usda": (".usda", ".usd"), "usd": (".usd", ".usdc"), "usdc": (".usdc", ".usd")}
    what = "binary USD" if args.format in ("usd", "usdc") else args.format.upper()
    named_as(
        out,
        "-o",
        named.get(args.format, (f".{args.format}",)),
        f"{what} (or choose it with --format)",
    )
    if args.skin and args.format not in ("glb", "gltf"):
        raise UsageError(f"--skin is for glTF (--format glb or gltf), not {args.format}")
    motion = _load(args, args.fps)
    made = new_directory(out)
    if args.format in ("usd", "usda", "usdc"):
        from legdsl.export.usd import write_usd

        size = write_usd(motion, out, args.format)
    elif args.format == "bvh":
        from legdsl.export.bvh import write_bvh

        size = write_bvh(motion, out)
    else:
        from legdsl.export.gltf import write_gltf

        size = write_gltf(motion, out, args.format, skin=args.skin)
    _say_note(motion, args.run, out)
    _say_made(made, out, messages_for(args.output))
    print(
        f"legdsl: wrote {out} ({human_size(size)}: {len(motion.bodies)} "
        f"link{'s' if len(motion.bodies) != 1 else ''}, "
        f"{motion.frames} keyframes over {seconds_text(motion.duration)}{_rate_kept(motion, args.fps)})"
        f"{_end_left(motion, args.fps)}",
        file=messages_for(args.output),
    )
    return 0


def _end_left(
    motion: Any, fps: float, slow: float | None = 1.0, video: tuple[float, int] | None = None
) -> str:
    """What the frames leave out of the run's end (frames every 1/fps stop at the last whole
    one), where over 5% of the run, with the --fps that ends at it: that rate divided by
    ``slow`` (a video's slow motion; None: no --fps does). The frames are the keyframes, or
    ``video``'s (the span from its first frame to its last, and their count), every 1/fps of
    the run, which may stop well before its keyframes do (a video at --fps 1)."""
    end, start = motion.last_sample, float(motion.times[0])
    span, frames = (motion.duration, motion.frames) if video is None else video
    if end is None or frames < 2 or end - span <= 0.05 * (end - start):
        return ""  # a few percent short (2.98 s of a 2.995 s run at 60 per second): as usual
    rate = math.ceil((end - start) * fps - 1e-9) / (end - start)  # a whole number of frames
    fix = f": --fps {rate / slow:.10g} ends at it" if slow else ""
    left = f"{seconds_text(end - span)} (to {seconds_text(end)})"
    return f"; the run's last {left} falls short of a whole frame and is left out{fix}"


def _rate_kept(motion: Any, fps: float) -> str:
    """The keyframe rate, if it is not ``--fps``: a run recorded more slowly keeps its own
    (35.1104203529 per second, written as the file's rate, for a creature scaled by 30)."""
    from legdsl.export.motion import frame_rate as keyframe_rate

    rate = keyframe_rate(motion)
    if motion.frames < 2 or rate >= fps * (1 - 1e-9):
        return ""
    return f", {rate:.10g} per second: the rate it was recorded at, below --fps {fps:g}"


def add_export_motion_parser(sub: Any) -> Command:
    e = sub.add_parser(
        "export-motion",
        help="export a recorded run as an animation (glTF, USD or BVH)",
        description="Export a run directory as an animation for other programs. glTF 2.0: one "
        "node per link (nested as the link tree) with a triangle mesh of its shape and a "
        "material of its colour, the ground as meshes, and the run as one animation with LINEAR "
        "translation and rotation keys, in seconds; y-up as glTF requires (legdsl's x forward "
        "stays x); .glb is one binary file, .gltf is JSON with the buffer embedded. USD (.usd "
        "or .usdc binary, .usda text): the same tree as Xform prims with time-sampled transforms, z-up. "
        "BVH: the link tree as a skeleton with offsets and per-frame channels, for "
        "motion-capture tools.",
        epilog="Example: legdsl export-motion runs/k --format glb -o kangaroo.glb",
    )
    e.add_argument("run", metavar="DIR", help="a run directory written by legdsl run")
    e.add_argument(
        "--format",
        choices=MOTION_FORMATS,
        default=None,
        help="glb, gltf, usd (binary; also usdc), usda (text) or bvh (default: as -o's name "
        "says, else glb)",
    )
    e.add_argument("-o", "--output", metavar="FILE", help="default DIR/motion.FORMAT")
    e.add_argument(
        "--skin",
        action="store_true",
        help="glTF: one skinned mesh over the link nodes as joints (an armature in Blender) "
        "instead of a mesh on each link node",
    )
    e.add_argument(
        "--fps", default=60.0, metavar="N", help="keyframes per second, or 60Hz (default 60)"
    )
    e.add_argument(
        "--source", metavar="FILE", help="the .leg file, if run.json's path is not found from here"
    )
    e.add_argument(
        "--generated",
        default="generated",
        metavar="DIR",
        help="where generated modules live (default generated/)",
    )
    return _cmd_export_motion


# ---------------------------------------------------------------- legdsl run --animate


def animate_result(out: Path, model: Any, result: Any, dynamics: Any) -> Path:
    """Write ``out/animation.html`` for a run that was just simulated."""
    from legdsl.export.motion import motion_from
    from legdsl.export.player import write_player
    from legdsl.export.stances import recorded_every_step

    path = out / "animation.html"
    if len(result.trajectory) == 0:
        print(f"  animation: not written, the run recorded no samples ({path})")
        return path
    try:
        motion = motion_from(
            model,
            result.trajectory,
            dynamics,
            events=result.events,
            status=result.status,
            message=result.message or "",
            every_step=recorded_every_step(result.steps, len(result.trajectory)),
        )
    except UsageError as refused:  # one frame of a run that moves, as legdsl animate refuses it
        print(
            f"  animation: not written ({path}): {refused}: write it with legdsl animate "
            f"{out} and that --fps"
        )
        return path
    size = write_player(motion, path)
    _say_note(motion)  # as legdsl animate of the run says it
    print(f"  animation: {path} ({human_size(size)}); open it in a web browser", file=sys.stdout)
    return path
