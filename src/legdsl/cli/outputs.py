"""``legdsl plot`` and ``legdsl export``: the commands that write a file named by ``-o``.

Both keep the rule of ``legdsl.pipeline.outputs``: a name ends in the suffix of what is written
(else it is refused, saying the name to write), and with standard output as the file, the
messages go to standard error.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from legdsl.cli.common import read_window
from legdsl.files import atomic_same_name
from legdsl.lang.errors import UsageError
from legdsl.pipeline.outputs import (
    PICTURES,
    ROOM_TO_DRAW,
    is_stream,
    made_note,
    messages_for,
    named_as,
    new_directory,
    room_for,
)


def cmd_plot(args: argparse.Namespace) -> int:
    from legdsl.analysis.plot import (
        crowded,
        first_leg_angles,
        plot_footfall,
        plot_run,
        plot_top,
        run_paths,
    )
    from legdsl.analysis.plot_ending import run_ending
    from legdsl.analysis.recorded import one_run
    from legdsl.sim.trajectory import Trajectory, load_run_info

    read_window(args)
    run = Path(args.dir)
    if args.output:  # named as plot --help's usage line names it (it said --output)
        named_as(args.output, "-o", PICTURES, "a PNG picture (or .svg, .pdf)")
    tr = Trajectory.load(run)  # a missing or damaged run is a UsageError before anything is drawn
    one_run(run, tr)  # and so is a trajectory.npz of another run than run.json's
    out = _picture_file(args.output, run)
    say = messages_for(args.output)
    room_for("draw the run", ROOM_TO_DRAW)
    made = new_directory(out)
    with atomic_same_name(out) as tmp:  # matplotlib writes in place: a full disk left half a PNG
        plot_run(run, tmp, first_leg_angles(run), args.t_from, args.t_to)
    if made is not None:
        print(made_note(made, out), file=say)
    print(f"wrote {out}", file=say)

    # Beside --output the other pictures take its name (fig.png: fig-footfall.png), so that
    # plotting several runs into one folder overwrites none of them; beside a stream (a pipe,
    # /dev/stdout) they go to the run directory.
    def beside(kind: str) -> Path:
        if args.output and not is_stream(out):
            return out.with_name(f"{out.stem}-{kind}{out.suffix}")
        return run / f"{kind}.png"

    footfall = beside("footfall")
    with atomic_same_name(footfall) as tmp:
        plot_footfall(run, tmp, args.t_from, args.t_to)
    print(f"wrote {footfall} (footfall diagram)", file=say)
    if args.top or run_paths(run):
        top = beside("top")
        with atomic_same_name(top) as tmp:
            plot_top(run, tmp, args.t_from, args.t_to)
        print(f"wrote {top} (top view)", file=say)
    if (note := crowded(tr, args.t_from, args.t_to)) is not None:
        print(f"legdsl: note: {note}", file=sys.stderr)
    if (ending := run_ending(load_run_info(run))) is not None:  # as animate says it
        print(ending.note(run, f"{out} (and the pictures beside it)"), file=sys.stderr)
    return 0


def _picture_file(output: str | None, run: Path) -> Path:
    """Where Figure 6 goes: ``-o``'s file, else DIR/figure6.png; one that cannot be written
    is refused naming ``-o`` where it was given (a read-only run directory's figure6.png was
    refused as "--output ...", an option not given)."""
    from legdsl.pipeline.options import check_output_file

    if output:
        return check_output_file(output, "-o")
    try:
        return check_output_file(run / "figure6.png", "")
    except UsageError as e:
        raise UsageError(f"{str(e).lstrip()} (or draw it elsewhere: -o FILE.png)") from None


# what an export's name says it holds, where --format is not given
NAMED_FORMATS = {".xml": "mjcf", ".mjcf": "mjcf", ".urdf": "urdf"}


def format_named(output: str | None) -> str:
    """The ``legdsl export`` format ``-o``'s name says (as ``export-motion`` takes it): .xml
    or .mjcf is MJCF, .urdf is URDF; a name that says none, or no name, is refused."""
    suffix = Path(output).suffix.lower() if output not in (None, "-") else ""
    if suffix in NAMED_FORMATS:
        return NAMED_FORMATS[suffix]
    if output is None:
        said = "without -o, say the format: --format mjcf (NAME.xml) or --format urdf (NAME.urdf)"
    elif output == "-" or is_stream(output):
        said = f"-o {output}: say the format: --format mjcf or --format urdf"
    else:
        which = f"the suffix {suffix} says" if suffix else "a name without a suffix says"
        said = (f"-o {output}: {which} no format; name it .xml or .mjcf (MJCF) or .urdf "
                "(URDF), or give --format mjcf or --format urdf")  # fmt: skip
    raise UsageError(said)


def cmd_export(args: argparse.Namespace) -> int:
    from legdsl.check.source import check_model
    from legdsl.export.formats import (
        FORMATS,
        default_path,
        export_notes,
        export_text,
        write_atomic,
    )
    from legdsl.pipeline.options import (
        Numeric,
        check_output_file,
        not_an_input,
        os_error,
        read_numeric,
    )

    if args.output == "-" and sys.stdout is None:  # started with >&-: an AttributeError
        raise UsageError("-o -: this command was started with standard output closed (>&-), "
                         "so nothing can be written there; give a file, or leave it open")  # fmt: skip
    args.format = args.format or format_named(args.output)
    if args.output not in (None, "-"):
        check_output_file(args.output, "-o")
        not_an_input(args.output, "-o", [Path(args.file)])
        suffix = FORMATS[args.format][1]
        # both are XML; an MJCF file is also often named .mjcf, a URDF one .xml
        named = {"urdf": (suffix, ".xml"), "mjcf": (suffix, ".mjcf")}.get(args.format, (suffix,))
        named_as(args.output, "-o", named, f"{args.format.upper()} ({suffix})")
    model = check_model(args.file, args.creature)
    if args.format != "urdf" and (args.base != "world" or args.link_mass is not None):
        raise UsageError("--base and --link-mass are URDF options (--format urdf)")
    if args.format != "mjcf" and args.anchor_pads is not None:
        raise UsageError("--anchor-pads and --no-anchor-pads are MJCF options (--format mjcf)")
    link_mass = 0.0
    if args.link_mass is not None:  # a mass with its unit (1mg); a bare number is kg
        link_mass = read_numeric(
            "--link-mass", args.link_mass, Numeric("mass", "kg", "nonnegative")
        )
    text = export_text(model, args.format, args.base, link_mass, args.anchor_pads is not False)
    for note in export_notes(model, args.format, args.file, args.anchor_pads is not False):
        print(f"legdsl: note: {note}", file=sys.stderr)  # what the file leaves out
    what = f"({args.format.upper()}, creature '{model.name}', {model.nv} DOF)"
    if args.output == "-":
        sys.stdout.write(text)
        print(f"wrote standard output {what}", file=sys.stderr)  # as /dev/stdout's
        return 0
    out = check_output_file(args.output or default_path(model, args.format), "-o")
    made = new_directory(out)
    try:
        write_atomic(out, text)
    except OSError as e:
        raise os_error("the export", out, e) from None
    if made is not None:
        print(made_note(made, out), file=messages_for(out))
    print(f"wrote {out} {what}", file=messages_for(out))
    return 0
