"""``legdsl metrics``: its options, and the table, JSON and notes it prints."""

from __future__ import annotations

import argparse
import json
import sys
from typing import Any

from legdsl.cli.common import Command, add_window, read_window
from legdsl.lang.errors import UsageError


def cmd_metrics(args: argparse.Namespace) -> int:
    from legdsl.analysis.segments import segment_table
    from legdsl.analysis.table2 import MEASURE, TABLE2, compare_table
    from legdsl.pipeline.measure import measure_run, run_segments
    from legdsl.pipeline.options import read_seconds

    read_window(args)  # a mistake is main's to tell, as every command's is
    min_stance = None if args.min_stance is None else read_seconds("--min-stance", args.min_stance)
    edge = read_seconds("--friction-edge", args.friction_edge, "nonnegative")
    if args.table2 is not None and args.table2 not in TABLE2:
        known = ", ".join(repr(k) for k in TABLE2)
        raise UsageError(f"--table2 {args.table2!r}: Table 2 has {known}")
    metrics, reports = measure_run(
        args.dir, args.t_from, args.t_to, args.leg, args.group, args.joint, args.against,
        args.generated, args.table2, min_stance, edge,
    )  # fmt: skip
    segments = run_segments(args.dir)
    given = {"--min-stance": args.min_stance, "--friction-edge": args.friction_edge}
    told = [_bare_seconds(note, flag, given[flag]) if flag in given else note
            for flag, note in metrics.option_notes.items()]  # fmt: skip
    sized = _size_note(args.dir, args.table2) if args.table2 is not None else None
    missed = [r.get("note") for r in reports]  # a path the centre of mass kept off
    ended = metrics.ending_note(f"the run in {args.dir}")  # as plot and animate say it
    notes = (ended, metrics.unmeasured, metrics.scuff_note, *told, metrics.unwritten, sized)
    for note in (*notes, *missed):
        if note:
            print(f"legdsl: note: {note}", file=sys.stderr)
    if args.json:
        data = metrics.to_dict()
        if reports:
            data["path_reports"] = reports
        if segments:
            data["segments"] = segments
        print(json.dumps(data, indent=2, allow_nan=False))
        return 0
    print(metrics.table(), end="")
    if segments:
        print(segment_table(segments), end="")
    if args.table2 is not None:
        print(f"\nbeside Table 2 of the paper, {args.table2}:")
        table = compare_table(metrics, TABLE2[args.table2], measured_as=MEASURE[args.table2])
        print(table, end="")
    print(metrics.path_table(), end="")
    return 0


def _size_note(run: Any, gait: str) -> str | None:
    """Table 2's note on a run of a creature of another size (``table2.size_note``)."""
    from legdsl.analysis.path_report import time_unit
    from legdsl.analysis.table2 import size_note
    from legdsl.sim.trajectory import load_run_info

    try:
        info = load_run_info(run)
    except (OSError, UsageError, ValueError):
        return None  # a trajectory without its run.json: its size is not known
    return size_note(gait, time_unit(info))


def _bare_seconds(note: str, flag: str, text: str) -> str:
    """``note`` on what ``flag``'s value did, saying that a number given without its unit
    is seconds (``--min-stance 20`` meant as 20 ms erased every stance)."""
    from legdsl.pipeline.settings import parse_given

    if parse_given(text.replace(" ", ""), flag).dim is not None:
        return note
    return f"{note}; a time without its unit is seconds: for {text} ms write {flag} {text}ms"


def add_metrics_parser(sub: Any) -> Command:
    """The ``metrics`` subcommand's options; its command."""
    m = sub.add_parser(
        "metrics",
        help="gait metrics of a recorded run, as in Table 2 of the paper",
        description="Measure a recorded run (DIR/trajectory.npz): stride duration and length, "
        "flight and stance durations, pitch and roll magnitude, change of leg length, speed "
        "and its error, peak vertical acceleration, the friction coefficient that would have "
        "prevented slipping and the elastic energy recirculated per step. Strides run from one "
        "touchdown of the reference foot to the next; only complete strides inside the window "
        "count. Prints a table (or JSON) and writes DIR/metrics.json. See docs/metrics.md.",
        epilog="Example: legdsl metrics runs/kangaroo --from 3 --joint tail_base --against hip",
    )
    m.add_argument("dir", metavar="DIR", help="a run directory holding trajectory.npz")
    m.add_argument(
        "--table2",
        metavar="ROWS",
        default=None,
        help="also print the run beside these rows of the paper's Table 2: 'kangaroo hop', "
        "'biped run', 'quadruped trot' or 'quadruped bound'",
    )
    add_window(m)
    m.add_argument(
        "--leg",
        metavar="NAME",
        help="reference leg (or virtual leg, or contact) whose touchdowns delimit strides "
        "(default: the first leg)",
    )
    m.add_argument(
        "--group",
        action="append",
        default=[],
        metavar="NAME=LEG,LEG",
        help="a virtual leg: the union of the contacts of these legs (of a run without legs: "
        "these contacts), e.g. front=fl,fr (repeat for each virtual leg)",
    )
    m.add_argument(
        "--joint",
        metavar="NAME",
        help="also the per-stride magnitude (peak to peak, deg) of this coordinate, e.g. tail_base",
    )
    m.add_argument(
        "--against",
        metavar="NAME",
        help="with --joint: its correlation with this coordinate (-1 is anti-phase), e.g. hip",
    )
    m.add_argument(
        "--min-stance",
        metavar="TIME",
        help="a contact shorter than this (e.g. 20ms; a number without its unit is seconds) is "
        "no touchdown: it starts no stride and is no stance (default: every contact counts; a "
        "note names those that look like scuffs)",
    )
    m.add_argument(
        "--friction-edge",
        default="10ms",
        metavar="TIME",
        help="left out at each end of a stance for the interior friction row (default 10ms, "
        "the paper's; a creature scaled by L: 10ms times the square root of L; a number "
        "without its unit is seconds)",
    )
    m.add_argument("--json", action="store_true", help="print JSON instead of the table")
    m.add_argument("--generated", default=None, metavar="DIR",
                   help="where the run's generated modules live, for the foot clearance at the apex, "
                   "the foot speed at touchdown and the margins to the terrain (default: the "
                   "folder the run was made with, which run.json records, found from the run "
                   "directory or where it was; else generated/; never compiled here)")  # fmt: skip
    return cmd_metrics
