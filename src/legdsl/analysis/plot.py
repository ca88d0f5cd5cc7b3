"""``legdsl plot DIR``: a run drawn like Figure 6 of the paper.

Four panels against time: the centre of mass's height, the root body's pitch (and roll, in
3D; a sentence instead for a root welded to the world), the centre of mass's forward speed
with its command (and sideways speed, in 3D), and the joint angles of the first leg (over
more panels for a leg of many joints, ``plot_panels``); every stance phase of that leg is
bracketed by vertical dashed lines, as in the paper.
"""

from __future__ import annotations

import textwrap
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from legdsl.analysis.path_report import Followed, followed_in
from legdsl.analysis.plot_ending import (
    Ending,
    lay_out,
    mark_ending,
    run_ending,
    shown_span,
    title_room,
)
from legdsl.analysis.plot_marks import LABEL_STEP, seconds_per_pixel, stack_labels, visible_bars
from legdsl.analysis.plot_panels import draw_joints, joint_groups, welded_note
from legdsl.analysis.plot_panels import legend as _legend
from legdsl.analysis.plot_units import scale_axes, scale_axis
from legdsl.figures import figure
from legdsl.lang.errors import UsageError
from legdsl.signals import import_held
from legdsl.sim.trajectory import Trajectory, load_run_info

if TYPE_CHECKING:
    from legdsl.ir.model import Model
    from legdsl.ir.paths import PathSpec

OFF_AXIS = 1e6  # a speed command this many times the speeds drawn (and 1 m/s) is off the axis


def pyplot() -> Any:
    """matplotlib's pyplot, drawing off screen (Agg); imported when first drawn (some 0.5 s),
    whole even if a Ctrl-C comes meanwhile (``import_held``)."""
    import_held("matplotlib").use("Agg")
    return import_held("matplotlib.pyplot")


def stance_phases(tr: Trajectory, leg: int) -> list[tuple[float, float]]:
    """(touchdown, liftoff) times of a leg (any of its soles down); an open stance ends at
    the last sample."""
    touching = tr.leg_touching(leg)
    phases = []
    start = None
    for i, now in enumerate(touching):
        if now and start is None:
            start = tr.t[i]
        elif not now and start is not None:
            phases.append((start, tr.t[i]))
            start = None
    if start is not None:
        phases.append((start, tr.t[-1]))
    return phases


def samples_in_window(
    tr: Trajectory,
    run: Path | str,
    t_from: float,
    t_to: float | None,
    verb: str,
    curve: bool = False,
) -> np.ndarray:
    """Which samples lie in the window (a mask); ``UsageError`` when none does, as a window
    past the end of the run: drawn, its panels were empty on axes matplotlib made up, and
    measured, every row n/a. A ``curve`` (a picture) needs two: one sample of a longer run
    drew no line, on an axis of the stance around it (100 s past a long run's end)."""
    end = tr.t[-1] if t_to is None else t_to
    window = (tr.t >= t_from) & (tr.t <= end)
    last = float(tr.t[-1])
    every = f"the run was recorded every {last / (len(tr) - 1):.3g} s" if len(tr) > 1 else ""
    if not window.any():
        if t_from > last:
            where = f"--from {t_from:g}s is after its last sample, at {last:g} s"
        else:
            where = f"none lies from {t_from:g} to {end:g} s"
        fix = f"give --from and --to within 0 to {last:g} s"
        if len(tr) > 1 and tr.t[0] <= t_from <= end <= last:  # between two samples
            fix = f"widen the window: {every}"
        raise UsageError(f"nothing of {run} to {verb}: {where}; {fix}")
    if curve and window.sum() == 1 and len(tr) > 1:  # a run of one sample is drawn as it is
        raise UsageError(
            f"too little of {run} to {verb}: only the sample at {tr.t[window][0]:g} s lies from "
            f"{t_from:g} to {end:g} s; widen the window: {every}"
        )
    return window


def picture_format(out: Path) -> str:
    """The format ``out``'s name says, else PNG: given to matplotlib, which would otherwise
    write ``fig.png`` when asked for ``fig`` (or ``/dev/stdout.png`` for ``/dev/stdout``)."""
    return Path(out).suffix[1:].lower() or "png"


# Stances past this many are not marked (a 30 min run's 2,390 dashed pairs were a grey wall
# over the curves); ``crowded`` says so, with the window to give instead.
MOST_STANCES = 200


def _command(speed: Any, t: np.ndarray, command: np.ndarray, forward: np.ndarray) -> None:
    """The speed command, dashed; one past ``OFF_AXIS`` times the speeds drawn (1e308 m/s,
    finite, overflowed matplotlib's ticks, which warned) is named in the legend alone."""
    most = float(np.nanmax(np.abs(command)))
    if most <= OFF_AXIS * (1.0 + float(np.max(np.abs(forward), initial=0.0))):
        speed.plot(t, command, color="0.5", linestyle="--", label="command")
    else:
        speed.plot([], [], color="0.5", linestyle="--", label=f"command (up to {most:.3g} m/s, "
                   "off the axis)")  # fmt: skip


def _stances_in(tr: Trajectory, t_from: float, end: float) -> list[tuple[float, float]]:
    """The first leg's stances that reach into the window (none without legs)."""
    if not tr.leg_names:
        return []
    return [(a, b) for a, b in stance_phases(tr, 0) if not (b < t_from or a > end)]


def crowded(tr: Trajectory, t_from: float = 0.0, t_to: float | None = None) -> str | None:
    """A note for a window with more stances than a figure can show, else None."""
    if not len(tr):
        return None
    end = tr.t[-1] if t_to is None else t_to
    n = len(_stances_in(tr, t_from, end))
    if n <= MOST_STANCES:
        return None
    seconds = (end - t_from) * MOST_STANCES / n / 8  # 25 stances
    return (
        f"{n} stances of leg '{tr.leg_names[0]}' in {end - t_from:.0f} s: too many to tell "
        f"apart in the figures (their lines are left out, the footfall bars run together); "
        f"draw a few seconds of it, e.g. --from {t_from:g} --to {t_from + seconds:.3g}"
    )


def plot_run(
    run: Path,
    out: Path,
    angles: tuple[str, ...] = (),
    t_from: float = 0.0,
    t_to: float | None = None,
) -> Path:
    """Draw the Figure-6 panels of the run in directory ``run`` into ``out`` (PNG)."""
    from legdsl.analysis.recorded import model_if_readable

    plt = pyplot()
    tr = Trajectory.load(run)
    ending = run_ending(load_run_info(run)) if (run / "run.json").is_file() else None
    model = model_if_readable(run)  # None: no ground drawn, no welded root told
    ground = ground_under_com(run, tr, model)
    welded = model.welded_root if model is not None else None
    drawn = Drawn(run.name, run, ground, switch_times(run), ending, welded)
    return draw_run(plt, tr, drawn, out, angles, t_from, t_to)


@dataclass(frozen=True)
class Drawn:
    """What Figure 6 takes of a run besides its samples: its title, how its messages name it
    (its directory), the ground under its centre of mass (None: a flat floor) and its
    controller changes (``switch_times``), how it ended where not ok (``run_ending``), and
    its root body's name where it is welded to the world (``Model.welded_root``). The API's
    ``Run.plot`` gives them from memory."""

    title: str
    named: Path | str
    ground: np.ndarray | None
    switches: list[tuple[float, str]]
    ending: Ending | None = None
    welded: str | None = None


def draw_run(
    plt: Any,
    tr: Trajectory,
    drawn: Drawn,
    out: Path,
    angles: tuple[str, ...] = (),
    t_from: float = 0.0,
    t_to: float | None = None,
) -> Path:
    """Draw the Figure-6 panels of ``tr`` into ``out`` (PNG, SVG or PDF as its name says)."""
    window = samples_in_window(tr, drawn.named, t_from, t_to, "draw", curve=True)
    end = tr.t[-1] if t_to is None else t_to
    t = tr.t[window]
    groups = joint_groups([n for n in angles if n in tr.q_names])  # a panel of 8 at most each
    fig, axes = plt.subplots(3 + len(groups), 1, figsize=(9.5, 9 + 2.1 * (len(groups) - 1)),
                             sharex=True)  # fmt: skip  # legends on the right
    height, pitch, speed, *panels = axes
    joints = panels[-1]  # the time axis's

    # the centre of mass's: the body's (its root's) height is not what is drawn
    height.plot(t, tr.com[window, 2], color="k", label="centre of mass")
    height.set_ylabel("centre-of-mass\nheight (m)")
    ground = drawn.ground
    if ground is not None:  # heights are world z: on terrain, the ground they stand over too
        height.plot(t, ground[window], color="0.5", linewidth=1.0, label="ground under com")
        _legend(height)
        height.set_ylabel("centre-of-mass height,\nworld z (m)")
    if drawn.welded is not None:  # its flat zeros said nothing: a sentence says why
        welded_note(pitch, drawn.welded)
    else:  # unwrapped: a planar flip's pitch, read in (-180, 180], is drawn as the turn it makes
        pitch.plot(t, np.degrees(np.unwrap(tr.root_rpy[window, 1])), color="k", label="pitch")
        pitch.set_ylabel("body pitch (deg),\n+ nose down")

    heading = tr.root_rpy[window, 2]
    vx, vy = tr.com_vel[window, 0], tr.com_vel[window, 1]
    forward = vx * np.cos(heading) + vy * np.sin(heading)
    speed.plot(t, forward, color="k", label="forward speed")
    if not tr.planar:  # a 3D run also tips and slides sideways: roll and sideways speed too
        if drawn.welded is None:
            pitch.plot(t, np.degrees(tr.root_rpy[window, 0]), color="k", linestyle=":",
                       label="roll")  # fmt: skip
            _legend(pitch)
            pitch.set_ylabel("body pitch (+ nose down),\nroll (deg)")
        sideways = -vx * np.sin(heading) + vy * np.cos(heading)
        speed.plot(t, sideways, color="k", linestyle=":", label="sideways speed")
    if np.isfinite(tr.speed_command[window]).any():
        _command(speed, t, tr.speed_command[window], forward)
    if not tr.planar or np.isfinite(tr.speed_command[window]).any():
        _legend(speed)
    speed.set_ylabel("centre-of-mass\n" + ("forward speed (m/s)" if tr.planar else "speed (m/s)"))

    draw_joints(panels, groups, tr, window, tr.leg_names[0] if tr.leg_names else "")
    joints.set_xlabel("time (s)")

    stances = _stances_in(tr, t_from, end)
    for start, stop in stances if len(stances) <= MOST_STANCES else ():
        for ax in axes:
            ax.axvline(start, color="0.6", linestyle="--", linewidth=0.8)
            ax.axvline(stop, color="0.6", linestyle="--", linewidth=0.8)
    labels = []
    for t_switch, controller in drawn.switches:  # controller changes (legdsl run --switch)
        if t_from <= t_switch <= end:
            for ax in axes:
                ax.axvline(t_switch, color="tab:red", linewidth=1.2)
            labels.append(height.text(t_switch, 1.0, f" {controller}", color="tab:red",
                                      fontsize=8, va="bottom",
                                      transform=height.get_xaxis_transform()))  # fmt: skip
    # the window's samples (on to the run's end, where it ended early), not a stance begun
    # before it or a --to past the end; the footfall diagram's axis is the same
    first, last = shown_span(t, drawn.ending, t_to)
    labels += mark_ending(axes, drawn.ending, first, last)
    if last > first:
        height.set_xlim(first, last)
    scale_axes(axes, joints)  # mm, ms for a tiny creature (the x axis is shared)
    creature = drawn.title
    fig.suptitle(
        (drawn.ending.title(95) + "\n" if drawn.ending is not None else "")
        + (
            creature
            if not tr.leg_names
            else f"{creature}: stance phases of leg '{tr.leg_names[0]}' between dashed lines"
            if len(stances) <= MOST_STANCES
            else f"{creature}: {len(stances)} stances of leg '{tr.leg_names[0]}', too many to mark"
        ),
        fontsize=10 if drawn.ending is not None else None,
    )
    lay_out(fig)
    if stack_labels(labels) > 1:  # rows of labels over the top panel: laid out again
        lay_out(fig)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=100, format=picture_format(out))
    plt.close(fig)
    return out


def switch_times(run: Path) -> list[tuple[float, str]]:
    """(time, controller) of each controller change of a run (``legdsl run --switch``)."""
    return segment_switches(load_run_info(run)) if (run / "run.json").is_file() else []


def segment_switches(info: dict[str, Any]) -> list[tuple[float, str]]:
    """``switch_times`` read from a run.json's contents (``info``)."""
    segments = info.get("segments") or []
    out = []
    for seg in segments[1:]:
        if isinstance(seg, dict) and isinstance(seg.get("from"), int | float):
            out.append((float(seg["from"]), str(seg.get("controller", ""))))
    return out


def plot_footfall(run: Path, out: Path, t_from: float = 0.0, t_to: float | None = None) -> Path:
    """The footfall diagram of a run (PNG): each foot's stance as a bar over time, one row
    per leg (per contact for a creature without legs), the first leg at the top, then a row
    for each other contact that touched, a sole of a leg with several too (``footfall_bars``); each
    controller change is a vertical line labelled with the controller it starts."""
    plt = pyplot()

    tr = Trajectory.load(run)
    ending = run_ending(load_run_info(run)) if (run / "run.json").is_file() else None
    inside = tr.t[(tr.t >= t_from) & (tr.t <= (tr.t[-1] if t_to is None else t_to))]
    if len(inside):  # Figure 6's axis: the window's samples, on to an early end
        t_from, end = shown_span(inside, ending, t_to)
    else:
        end = float(tr.t[-1]) if t_to is None else min(t_to, float(tr.t[-1]))
    rows = footfall_bars(tr)
    title = (ending.title(110) + "\n" if ending is not None else "") + (
        f"{run.name}: footfalls (each foot's stance as a bar)"
    )  # its lines above the rows: the picture taller by them
    tall = 0.9 + 0.45 * max(len(rows), 1) + title_room(title, 10)
    fig, ax = plt.subplots(figsize=(9, tall))
    ax.set_yticks(range(len(rows)), [name for name, _ in reversed(rows)])
    labels = []
    for t, controller in switch_times(run):
        if t_from <= t <= end:
            ax.axvline(t, color="tab:red", linewidth=1.2)
            labels.append(ax.text(t, len(rows) - 0.45, f" {controller}", color="tab:red",
                                  fontsize=8, va="bottom"))  # fmt: skip
    if end > t_from:  # a run of one sample has no time axis to fix
        ax.set_xlim(t_from, end)
    ax.set_ylim(-0.6, len(rows) - 0.4 + (0.5 if switch_times(run) else 0))
    ax.set_xlabel("time (s)")
    scale_axis(ax.xaxis, ax.xaxis.label, (t_from, end))  # ms for a tiny creature's run
    mark_ending([ax], ending, t_from, end, word=False)
    ax.set_title(title, fontsize=10)
    ax.set_axisbelow(True)  # the grid behind the bars
    ax.grid(True, axis="x", color="0.9")
    lay_out(fig)
    if (levels := stack_labels(labels)) > 1:  # taller by the rows of labels, the legs' as they were
        room = (levels - 1) * LABEL_STEP * fig.dpi / 72  # px
        bottom, top = ax.get_ylim()
        ax.set_ylim(bottom, top + room * (top - bottom) / ax.get_window_extent().height)
        fig.set_figheight(fig.get_figheight() + room / fig.dpi)
        lay_out(fig)
    pixel = seconds_per_pixel(ax, t_from, end)  # the axes laid out: a pixel's time
    for k, (_name, stances) in enumerate(rows):
        y = len(rows) - 1 - k
        ax.broken_barh(visible_bars(stances, t_from, end, pixel), (y - 0.35, 0.7), facecolors="k")
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=100, format=picture_format(out))
    plt.close(fig)
    return out


def footfall_bars(tr: Trajectory) -> list[tuple[str, list[tuple[float, float]]]]:
    """Each leg's (each contact's, for a creature without legs) stances as (start, end) times,
    then those of each other contact that touched in the run, under its own name: a tail, a
    heel beside a leg's toe, and each sole of a leg that has several. A leg's stance is while
    any of its soles touches, as the metrics count it, so its soles' own rows are what shows
    a heel strike apart from the toe's landing."""
    width = tr.contact.shape[1]
    if tr.leg_names:
        rows = [(name, tr.soles_of(i)) for i, name in enumerate(tr.leg_names)]
        alone = {soles[0] for _, soles in rows if len(soles) == 1}  # a leg's row is its foot's
        # soles in their legs' order (foot, heel, toe), then the other contacts
        order = dict.fromkeys([c for _, soles in rows for c in soles if c not in alone])
        order |= dict.fromkeys(range(width))
        rows += [(tr.contact_names[c], (c,)) for c in order
                 if c not in alone and bool(np.any(tr.contact[:, c] != 0))]  # fmt: skip
    else:
        rows = [(name, (c,)) for c, name in enumerate(tr.contact_names)]
    return [
        (name, _runs_of(tr.t, np.any(tr.contact[:, list(cs)] != 0, axis=1))
         if all(0 <= c < width for c in cs) else [])
        for name, cs in rows
    ]  # fmt: skip


def _runs_of(t: np.ndarray, on: np.ndarray) -> list[tuple[float, float]]:
    """(start, end) times of each run of ``on``; a run still on at the end ends there."""
    d = np.diff(np.concatenate(([0], on.astype(np.int8), [0])))
    starts, stops = np.flatnonzero(d == 1), np.flatnonzero(d == -1)
    last = len(t) - 1
    pairs = zip(starts.tolist(), stops.tolist(), strict=True)
    return [(float(t[a]), float(t[min(int(b), last)])) for a, b in pairs]


def first_leg_angles(run: Path) -> tuple[str, ...]:
    """The hinge coordinates of the run's first leg, read back from its creature's .leg file."""
    from legdsl.analysis.recorded import recorded_model, run_source

    info = load_run_info(run)
    if run_source(run, info) is None:
        return ()
    return leg_angles(recorded_model(run, info)[1])


def leg_angles(model: Model) -> tuple[str, ...]:
    """The hinge coordinates of ``model``'s first leg (none without legs)."""
    if not model.legs:
        return ()
    joints = model.legs[0].joints
    return tuple(d.name for d in model.dofs if d.joint in joints and d.motion == "hinge")


def ground_under_com(run: Path, tr: Trajectory, model: Model | None) -> np.ndarray | None:
    """The terrain's height under the centre of mass at every sample, or None for a flat
    floor (or when the run's creature, ``model``, could not be read back: the panel is then
    the body alone). A ``--scale L`` run's ground is the file's scaled by L, as its motion
    and metrics are."""
    if model is None or model.ground is None or not model.ground.terrain:
        return None
    return ground_height(model, tr, float(load_run_info(run).get("scale") or 1.0))


def ground_height(model: Model, tr: Trajectory, scale: float = 1.0) -> np.ndarray | None:
    """``ground_under_com`` of ``model``'s ground, scaled by ``scale`` (a ``--scale L`` run)."""
    from legdsl.sim.contact import GroundContact

    if model.ground is None or not model.ground.terrain:
        return None
    surface = GroundContact(model.ground, (), model.planar)
    return np.array([scale * surface.height(float(x) / scale, float(y) / scale)
                     for x, y in tr.com[:, :2]])  # fmt: skip


def run_paths(run: Path) -> list[PathSpec]:
    """The paths a run followed (``PathSpec``s from its run.json; none for older runs)."""
    return [spec for spec, _ in run_followed(run)]


def run_followed(run: Path) -> list[Followed]:
    """The paths a run followed with the spans of the run it followed each in (run.json's
    ``followed``: a run that changed to a controller with another path), None for the whole."""
    if not (run / "run.json").is_file():
        return []
    return followed_in(load_run_info(run), f"{run}/run.json")


def path_title(name: str, report: dict[str, Any]) -> str:
    """The top view's title for a path (``path_report``): an open path's share, a closed
    one's laps, each figure with the window it was measured in."""
    from legdsl.analysis.path_rows import progress_label, window_label

    closed = report.get("closed", True)
    covered = "laps" if closed else f"of its {figure(report['length'])} m"
    window, since = window_label(report), progress_label(report)
    deviation = f"lateral deviation {figure(report['lateral_rms'])} m RMS, " + (
        f"{figure(report['lateral_max'])} m max"
    )
    made = f"{report['laps']:.2f} {covered}"
    if since == window:  # one window for every figure: said once
        return f"{name}: {deviation}, {made} ({window})"
    return f"{name}: {deviation} ({window}), {made} ({since})"


def plot_top(run: Path, out: Path, t_from: float = 0.0, t_to: float | None = None) -> Path:
    """A top view: the path(s) the run followed and the track of the centre of mass."""
    plt = pyplot()

    from legdsl.analysis.path_report import followed_reports, time_unit
    from legdsl.analysis.top_marks import mark_way, unbroken
    from legdsl.sim.path_tracking import PathGeometry

    tr = Trajectory.load(run)
    end = tr.t[-1] if t_to is None else t_to
    window = (tr.t >= t_from) & (tr.t <= end)
    followed = run_followed(run)
    drawn = []  # each path's points, then the track: the figure takes their shape
    for spec, _ in followed:
        geo = PathGeometry(spec)
        s = np.linspace(0.0, geo.length, 400 if spec.shape == "circle" else 2000)
        pts = np.array([geo.at(float(v))[:2] for v in s])
        drawn.append(np.vstack([pts, pts[:1]]) if spec.shape != "circle" and geo.closed else pts)
    track = tr.com[window, :2]
    span = np.ptp(np.vstack([*drawn, track]), axis=0) + 1.0  # a metre's margin, never 0 wide
    titles = [
        textwrap.fill(unbroken(path_title(spec.name, report)), 90)
        for spec, report in followed_reports(
            tr, followed, t_from if t_from > 0 else None, t_to, time_unit(load_run_info(run))
        )
        if report["lateral_rms"] is not None
    ]
    # 6 inches of plot across; as tall as the ground covered is deep (within 3 to 7), plus
    # the title's lines above and the legend's below, so a long straight path is no strip
    ending = run_ending(load_run_info(run)) if (run / "run.json").is_file() else None
    lines = sum(t.count("\n") + 1 for t in titles) + (
        ending.title(90).count("\n") + 1 if ending else 0
    )
    tall = float(np.clip(6 * span[1] / span[0], 3, 7)) + 0.2 * lines + 1.8
    # laid out as drawn: the equal aspect moves the limits then, and their wider tick labels
    # pushed "y (m)" off the picture's edge after tight_layout had measured the old ones
    fig, ax = plt.subplots(figsize=(7, tall), layout="constrained")
    for k, ((spec, spans), pts) in enumerate(zip(followed, drawn, strict=True)):
        when = ", ".join(f"{a:g} to {b:g} s" for a, b in spans or [])  # a switched run's
        ax.plot(pts[:, 0], pts[:, 1], color="0.6", linewidth=3, linestyle=("-", "--", ":")[k % 3],
                label=f"path {spec.name}" + (f" ({when})" if when else ""))  # fmt: skip
    ax.plot(track[:, 0], track[:, 1], color="k", linewidth=1, label="centre of mass")
    mark_way(ax, track, tr.t[window], drawn)  # the start, the end, the ways round
    ax.set_aspect("equal", adjustable="datalim")  # true distances, filling the plot
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.grid(True, color="0.9")
    # under the x label, whatever the plot's height (anchored at a share of the axes' height,
    # it left a gap under a tall plot and came close to the label under a short one)
    fig.legend(loc="outside lower center", ncol=2, fontsize=8, frameon=False)
    ax.set_title(
        (ending.title(90) + "\n" if ending is not None else "")
        + f"{run.name}: top view, {tr.t[window][0]:.1f} to {tr.t[window][-1]:.1f} s"
        + ("\n" + "\n".join(titles) if titles else ""),
        fontsize=9,
    )
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=100, format=picture_format(out))
    plt.close(fig)
    return out
