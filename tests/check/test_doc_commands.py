"""The ``legdsl`` command lines of README.md and docs/*.md stay true: each is read by the
command line's own parser and by the same functions the commands read their values with
(units, ``--set``, ``--switch``, ``--path``, ``--grid``...), against the creature it names,
without running anything; every repository file a command (or a ``python docs/scripts/...``
line) names exists; and the ``legdsl ...`` spans of the prose name real options.

Command lines are taken from indented and shell-fenced code blocks (``\\`` continuations
joined, ``#`` comments dropped, ``&&`` chains split; each block starts at the repository
root, a ``cd`` in it moves on) and from the first column of the tables of commands. A
synopsis's placeholders are made concrete by ``SYNOPSIS``; a file that an earlier step of the
page writes is checked as the file it is made from (``WRITTEN_BY_THE_DOC``); a line that
cannot be made concrete goes in ``NOT_CHECKED`` with the reason.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import os
import re
import shlex
from pathlib import Path
from typing import Any

import pytest

from legdsl.analysis.table2 import TABLE2
from legdsl.api.sweep import actuator_settings, parse_axis, seconds
from legdsl.api.tune_cli import _check_search, _speed_input, _speeds
from legdsl.check.source import check_model
from legdsl.cli import _parser
from legdsl.cli.common import file_read_as_option, negative_values_joined, numeric, read_window
from legdsl.export.animate import frame_rate, motion_format, parse_overlays, parse_size, video_fps
from legdsl.ir.model import Model
from legdsl.lang.errors import LegError, UsageError
from legdsl.pipeline.options import RUN_NUMERIC, read_seconds
from legdsl.pipeline.path_option import parse_path_option
from legdsl.pipeline.scaled import check_scale
from legdsl.pipeline.scenes import find_scene, parse_switch
from legdsl.pipeline.settings import require_controller, sort_settings

ROOT = Path(__file__).resolve().parents[2]
DOCS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]

# A synopsis's placeholders, replaced (in this order, as text) by values that exist:
# FILE is a shipped creature with several controllers and scenes, DIR a run directory.
SYNOPSIS: list[tuple[str, str]] = [
    ("[--path [NAME=]SHAPE]", "[--path 'circle(center = (0, 5) m, radius = 5 m)']"),
    ("--controller NAME", "--controller run"),
    ("--set NAME=VALUE ...", "--set speed=1.5m/s"),
    ("--switch T=NAME ...", "--switch 6s=gallop"),
    ("--scene NAME", "--scene run_gallop_run"),
    ("--grid NAME=LO:HI:N ...", "--grid speed=1:2:3"),
    ("--param NAME=LO:HI ...", "--param k_speed=0.02:0.2"),
    ("--speeds V,V", "--speeds 1,1.5"),
    ("--leg NAME", "--leg left"),
    ("--group NAME=LEG,LEG]...", "--group either=left,right]"),
    ("[--overlays ...]", "[--overlays state,speed]"),
    ("--format glb|gltf|usd|usda|bvh", "--format glb"),
    ("--format mjcf|urdf", "--format mjcf"),
    ("FILE...", "FILE"),
    ("FILE.leg", "FILE"),
    ("-o FILE.glb", "-o runs/biped/motion.glb"),
    ("--jobs J", "--jobs 2"),
    ("-o FILE.html", "-o runs/biped/player.html"),
    ("-o FILE.mp4", "-o runs/biped/mujoco.mp4"),
    ("--video FILE.mp4", "--video runs/biped/run.mp4"),
    ("--time T", "--time 10"),
    ("--from T", "--from 3"),
    ("--to T", "--to 5"),
    ("--out DIR", "--out runs/biped"),
    ("FILE", "creatures/biped.leg"),
    ("DIR", "runs/biped"),
]

# .leg files a page writes before it runs them (by a script, legdsl scale or by hand),
# checked as the file they are made from.
WRITTEN_BY_THE_DOC: dict[str, str] = {
    "kangaroo_x2.leg": "creatures/kangaroo.leg",  # legdsl scale ... -o kangaroo_x2.leg
    "my.leg": "creatures/hopper.leg",  # the reader's own file
    "detuned/kangaroo.leg": "creatures/kangaroo.leg",  # the kangaroo with its gains detuned
    "heavy/hopper.leg": "creatures/hopper.leg",  # the hopper made heavier
    "kvariants/v03/kangaroo.leg": "creatures/kangaroo.leg",  # docs/scripts/tune_variants.py's
    "stocky/stocky.leg": "creatures/quadruped.leg",  # docs/scripts/stocky_quadruped.py's
    "wallaby_box.leg": "tests/good/outside/wallaby.leg",  # the wallaby with a box to jump
    "runs/jump4/h0.30/kangaroo_box.leg": "creatures/kangaroo.leg",  # the jump script's file
}

# Command lines that cannot be made concrete: (page, start of the line) -> why.
NOT_CHECKED: dict[tuple[str, str], str] = {}

# A path written from these folders (or from ../) names the repository's files: it must
# exist where the command stands (a code block starts at the repository root; a 'cd' in it
# moves on), and an output's folder must exist.
REPOSITORY = ("creatures/", "tests/", "docs/", "benchmarks/", "grammar/", "../")
OUTPUTS = ("-o", "--output", "--out", "--video", "--generated")
SHELL = ("", "sh", "bash", "shell", "console")


def _code_lines(path: Path) -> list[tuple[int, int, str]]:
    """(block, line number, line) of the code blocks (indented, or fenced as shell), with
    continuations joined; and of the first column of a table of commands."""
    out: list[tuple[int, int, str]] = []
    fence: str | None = None
    block, pending, start, was_code = 0, "", 0, False
    for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        if line.lstrip().startswith("```"):
            fence = None if fence is not None else line.strip()[3:].strip()
            block += 1
            continue
        table = re.match(r"\|\s*(`legdsl [^|]*?)\s*\|", line.replace("\\|", "\x00"))
        if table:
            for span in re.findall(r"`(legdsl [^`]*)`", table.group(1)):
                block += 1
                out.append((block, number, span.replace("\x00", "|")))
            continue
        code = fence in SHELL if fence is not None else line.startswith(("    ", "\t"))
        if not (code or pending):
            was_code = False
            continue
        if not was_code and fence is None:
            block += 1
        was_code = True
        start = start if pending else number
        if line.rstrip().endswith("\\"):
            pending += line.rstrip()[:-1] + " "
            continue
        out.append((block, start, pending + line.strip()))
        pending = ""
    return out


def _commands(line: str) -> list[list[str]]:
    """The commands of a shell line (``a && b``, ``a; b``, ``a | b``), each without the
    variables and ``nice`` before it."""
    lexer = shlex.shlex(line.strip().removeprefix("$ "), posix=True, punctuation_chars=True)
    lexer.whitespace_split = True
    try:
        tokens = list(lexer)
    except ValueError:  # an unbalanced quote: no shell line, unless it names legdsl
        return (
            [["legdsl", "<unbalanced quote>", line]]
            if re.search(r"(^|&&|;|\|)\s*legdsl ", line)
            else []
        )
    found: list[list[str]] = []
    command: list[str] = []
    for token in [*tokens, ";"]:
        if token not in ("&&", "||", ";", "|", "&"):
            command.append(token)
            continue
        while command and (command[0] == "nice" or re.fullmatch(r"[A-Z_]+=\S*", command[0])):
            command.pop(0)
        if command:
            found.append(command)
        command = []
    return found


def _concrete(text: str) -> str:
    """A synopsis made a command line: placeholders replaced, optional brackets dropped."""
    for placeholder, value in SYNOPSIS:
        text = re.sub(rf"(?<![\w/-]){re.escape(placeholder)}(?![\w/.])", value, text)
    text = re.sub(r"\s\.\.\.(?=\s|$)", "", text)  # and more options
    return re.sub(r"(^|\s)\[|\](?=\s|$)", r"\1", text)


def doc_commands(program: tuple[str, ...]) -> list[Any]:
    """The commands of the pages run by ``program``: (page, line number, folder, argv)."""
    found = []
    for path in DOCS:
        page = path.relative_to(ROOT).as_posix()
        here, block = ".", -1
        for in_block, number, line in _code_lines(path):
            here = "." if in_block != block else here
            block = in_block
            for argv in _commands(_concrete(line)):
                if argv[0] == "cd" and len(argv) == 2:
                    here = os.path.normpath(os.path.join(here, argv[1]))
                elif argv[0] in program:
                    param = pytest.param(page, number, here, argv[1:], id=f"{page}:{number}")
                    found.append(param)
    return found


COMMANDS = doc_commands(("legdsl",))
SCRIPTS = doc_commands(("python", "python3"))


def _parse(argv: list[str]) -> argparse.Namespace:
    parser = _parser()
    given = negative_values_joined(argv, parser)
    if mistake := file_read_as_option(given):
        raise UsageError(mistake)
    said = io.StringIO()
    try:
        with contextlib.redirect_stderr(said):
            return parser.parse_args(given)
    except SystemExit:
        raise UsageError(said.getvalue().strip().splitlines()[-1]) from None


_MODELS: dict[tuple[str, str | None], Model] = {}


def _model(file: str, creature: str | None) -> Model:
    source = WRITTEN_BY_THE_DOC.get(file, file)  # file: from the repository root
    if (source, creature) not in _MODELS:
        _MODELS[source, creature] = check_model(ROOT / source, creature)
    return _MODELS[source, creature]


def _check_run(args: argparse.Namespace) -> None:
    for flag, spec in RUN_NUMERIC.values():
        numeric(args, flag[2:].replace("-", "_"), flag, spec)
    check_scale(args.scale)
    model = _model(args.file, args.creature)
    controller = args.controller
    if args.scene is not None:
        controller = controller or find_scene(model, args.scene).controller
    if controller is not None:
        require_controller(model, controller)
    later = [parse_switch(text, model).controller for text in args.switch]
    sort_settings(list(args.set), model, controller, later)
    for text in args.path:
        parse_path_option(text)


def _check_sweep(args: argparse.Namespace) -> None:
    model = _model(args.file, args.creature)
    require_controller(model, args.controller)
    controller = model.controller(args.controller)
    dims = {c.name: c.dim for c in (*controller.inputs, *controller.params)}
    for kind in ("grid", "random", "lhs"):
        for text in getattr(args, kind):
            parse_axis(kind, text, dims | actuator_settings(model))
    seconds("--time", args.time)
    if args.t_from is not None:
        seconds("--from", args.t_from, "nonnegative")
    sort_settings(list(args.set), model, args.controller)


def _check_tune(args: argparse.Namespace) -> None:
    model = _model(args.file, args.creature)
    require_controller(model, args.controller)
    controller = model.controller(args.controller)
    for text in args.param:
        parse_axis("param", text, {c.name: c.dim for c in controller.params})
    _speeds(args.speeds, _speed_input(args.controller, controller).dim)
    _check_search(args)


def _check_metrics(args: argparse.Namespace) -> None:
    read_window(args)
    if args.min_stance is not None:
        read_seconds("--min-stance", args.min_stance)
    if args.table2 is not None and args.table2 not in TABLE2:
        raise UsageError(f"--table2 {args.table2!r}: Table 2 has {', '.join(TABLE2)}")


def _check_animate(args: argparse.Namespace) -> None:
    parse_overlays(args.overlays)
    if args.video:
        parse_size(args.size or "960x540")
        video_fps(frame_rate(args.fps), 30.0, args.video.endswith(".gif"))


def _check_replay(args: argparse.Namespace) -> None:
    if not args.mujoco:
        raise UsageError("replay: say where: --mujoco")
    parse_size(args.size or "960x540")
    video_fps(frame_rate(args.fps), 30.0)


def _check_models(args: argparse.Namespace) -> None:
    for given in (
        args.files if "files" in args else [args.file]
    ):  # a pattern as the shell expands it
        for file in sorted(ROOT.glob(given)) if "*" in given else [given]:
            _model(str(file), getattr(args, "creature", None))


def _check_compile(args: argparse.Namespace) -> None:
    if args.all == bool(args.files):
        raise UsageError("legdsl compile: give .leg files or --all (not both)")
    _check_models(args)


CHECKS = {
    "run": _check_run,
    "sweep": _check_sweep,
    "tune": _check_tune,
    "metrics": _check_metrics,
    "plot": read_window,
    "animate": _check_animate,
    "replay": _check_replay,
    "export-motion": lambda args: motion_format(args.format, args.output),
    "scale": lambda args: check_scale(args.by),
    "check": _check_models,
    "show": _check_models,
    "export": _check_models,
    "compile": _check_compile,
}


def _where(here: str, path: str) -> str:
    return os.path.normpath(os.path.join(here, path))


def _missing_paths(here: str, argv: list[str]) -> list[str]:
    """The repository paths of ``argv`` that are not there (an output's: its folder)."""
    missing = []
    for before, token in zip(["", *argv], argv, strict=False):
        value = token.partition("=")[2] if token.startswith("-") else token
        if not value.startswith(REPOSITORY):
            continue
        path = _where(here, value)
        if before in OUTPUTS:
            path = os.path.dirname(path) or "."
        if not list(ROOT.glob(path)) or path.startswith(".."):
            missing.append(value)
    return missing


@pytest.mark.parametrize(("page", "number", "here", "argv"), COMMANDS)
def test_doc_command_is_read_by_the_command_line(
    page: str, number: int, here: str, argv: list[str]
) -> None:
    line = " ".join(argv)
    if (why := NOT_CHECKED.get((page, line[:40]))) is not None:
        pytest.skip(why)  # listed above, with its reason
    try:
        args = _parse(argv)
        for name in ("file", "files"):  # as the shell passes them, from where the command is
            if isinstance(given := getattr(args, name, None), str):
                setattr(args, name, _where(here, given))
            elif isinstance(given, list):
                setattr(args, name, [_where(here, g) for g in given])
        CHECKS[args.command](args)
    except (UsageError, LegError) as e:
        pytest.fail(f"{page}:{number}: legdsl {line}\n  {e}")
    assert _missing_paths(here, argv) == [], f"{page}:{number}: legdsl {line} (in {here}/)"


@pytest.mark.parametrize(("page", "number", "here", "argv"), SCRIPTS)
def test_doc_script_is_there(page: str, number: int, here: str, argv: list[str]) -> None:
    assert _missing_paths(here, argv) == [], f"{page}:{number}: python {' '.join(argv)}"


def test_the_pages_show_commands_and_the_lists_are_used() -> None:
    assert len(COMMANDS) >= 140 and len(SCRIPTS) >= 20
    shown = {(p.values[0], " ".join(p.values[3])[:40]) for p in COMMANDS}
    assert [k for k in NOT_CHECKED if k not in shown] == []
    files = {_where(p.values[2], t) for p in COMMANDS for t in p.values[3] if t.endswith(".leg")}
    assert [f for f in WRITTEN_BY_THE_DOC if f not in files] == []
    commands = _parser()._subparsers._group_actions[0].choices  # type: ignore[union-attr]
    assert set(CHECKS) == set(commands)


def _prose_commands() -> list[tuple[str, str]]:
    """The ``legdsl SUBCOMMAND ...`` spans of the pages' prose (often only a part of a
    command: ``legdsl run --scale L``), with their page."""
    found = []
    for path in DOCS:
        text = re.sub(r"^```.*?^```", "", path.read_text(encoding="utf-8"), flags=re.S | re.M)
        page = path.relative_to(ROOT).as_posix()
        found += [(page, span) for span in re.findall(r"`(legdsl [a-z][^`]*)`", text)]
    return found


def test_prose_names_only_commands_and_options_that_exist() -> None:
    commands = _parser()._subparsers._group_actions[0].choices  # type: ignore[union-attr]
    spans = _prose_commands()
    assert len(spans) >= 100
    wrong = []
    for page, span in spans:
        name, *rest = span.split()[1:]
        if name not in commands:
            wrong.append(f"{page}: `{span}`: no command {name}")
            continue
        known = commands[name]._option_string_actions
        for token in rest:
            option = token.partition("=")[0]
            if re.fullmatch(r"--?[a-z][\w-]*", option) and option not in known:
                wrong.append(f"{page}: `{span}`: legdsl {name} has no option {option}")
    assert wrong == []
