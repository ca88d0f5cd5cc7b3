"""The numeric options of the command line and of ``RunOptions``, and output paths, checked
before any work starts.

Every numeric option takes a number with an optional unit, as ``--set`` does: ``--time 2s``,
``--dt 0.4ms``, ``--record-rate 100Hz``, ``--drop 5cm``, ``--fall-tilt 30deg``; a bare number
is in the option's own unit (s, Hz, m, deg). ``--fall-height off`` and ``--fall-tilt off`` turn
the fall rule's height or tilt off (``read_run_option``). Values that make no sense (not finite,
zero or negative where a duration or a step is meant) are a ``UsageError``: exit status 2.
"""

from __future__ import annotations

import contextlib
import math
import numbers
import os
import sys
import tempfile
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

from legdsl.files import closed_stream, free_bytes, written_as
from legdsl.ir.model import Model
from legdsl.lang.errors import UsageError
from legdsl.lang.scaling import COMPUTABLE_STEP, MOST_STEPS, SMALLEST_STEP
from legdsl.lang.units import KINDS, UNITS, a_kind
from legdsl.pipeline.outputs import not_standard_output
from legdsl.pipeline.settings import parse_given
from legdsl.pipeline.suggested_values import written
from legdsl.pipeline.text_numbers import one_text
from legdsl.sim.recorder import address_space_left, recording_budget, sample_bytes
from legdsl.sim.run_loop import FALL_OFF, INITIAL_ROWS, RunOptions, run_samples
from legdsl.sim.stability import where_step


@dataclass(frozen=True)
class Numeric:
    """How one option reads: its kind (a key of ``units.KINDS``), the unit of a bare number,
    and the smallest value it takes (``positive``: above zero; ``nonnegative``: zero or more);
    ``off``: what the word ``off`` turns off, where the option takes it (``read_run_option``)."""

    kind: str
    bare: str
    least: str = "positive"  # or "nonnegative", or "any"
    off: str = ""  # e.g. "the fall rule's height"


# legdsl run's numeric options: RunOptions field -> (flag, how it reads)
RUN_NUMERIC: dict[str, tuple[str, Numeric]] = {
    "duration": ("--time", Numeric("time", "s")),
    "dt": ("--dt", Numeric("time", "s")),
    "control_dt": ("--control-dt", Numeric("time", "s")),
    "record_rate": ("--record-rate", Numeric("frequency", "Hz", "nonnegative")),
    "drop": ("--drop", Numeric("length", "m", "nonnegative")),
    "fall_height": ("--fall-height", Numeric("length", "m", "nonnegative", off="height")),
    "fall_tilt": ("--fall-tilt", Numeric("angle", "deg", off="tilt")),
}
# what ``off`` reads as: no height is a fall; no tilt is past upside down (180 deg)
OFF_VALUES: dict[str, float | str] = {"fall_height": FALL_OFF, "fall_tilt": math.pi}
# the advice with a refused fall limit: the way to turn the rule off
FALL_OFF_ADVICE = (
    "to turn the fall rule's {what} off (a creature built to crawl or lie on the ground), "
    "write {off}"
)


def read_run_option(field: str, flag: str, text: str) -> float | str:
    """``legdsl run``'s option ``field`` (a key of ``RUN_NUMERIC``) written as ``text``, in SI;
    ``off`` (``--fall-height off``, ``fall_tilt='off'``) as ``OFF_VALUES`` has it."""
    spec = RUN_NUMERIC[field][1]
    if spec.off and is_off(text):
        return OFF_VALUES[field]
    return read_numeric(flag, text, spec)


def is_off(text: object) -> bool:
    """Whether an option's value is the word ``off`` (any case, spaces around it)."""
    return isinstance(text, str) and text.strip().lower() == "off"


def _off_written(flag: str) -> str:
    """``--fall-height off`` as the option is written: ``fall_height='off'`` in Python."""
    return f"{flag}'off'" if flag.endswith("=") else f"{flag} off"


WINDOW = Numeric("time", "s", "nonnegative")  # --from and --to


def read_numeric(flag: str, text: str, spec: Numeric) -> float:
    """``--dt 0.4ms`` -> 0.0004 (SI); a mistake raises ``UsageError`` naming the flag."""
    sep = "" if flag.endswith("=") else " "  # the API's start=, --from's space
    where = f"{flag}{sep}{text}"
    given = parse_given(text, where)
    want = KINDS[spec.kind][0]
    if given.dim is None:
        value = given.value * UNITS[spec.bare][0]
    elif given.dim == want:
        value = given.value
    else:
        raise UsageError(
            f"{where}: {flag} is {a_kind(want)}, but {given.text} is {a_kind(given.dim)}; "
            f"write e.g. {flag}{sep}{written(given, want, spec.bare)}"
        )
    off = FALL_OFF_ADVICE.format(what=spec.off, off=_off_written(flag)) if spec.off else ""
    if spec.least == "positive" and not value > 0:
        raise UsageError(f"{where}: {flag} must be more than zero" + f"; {off}" * bool(off))
    if spec.least == "nonnegative" and value < 0:
        raise UsageError(f"{where}: {flag} must not be negative" + f"; {off}" * bool(off))
    return value


def read_seconds(flag: str, text: str, least: str = "positive") -> float:
    """A time written as text, as ``legdsl run``'s options take it (``2s``, ``500 ms``; a
    bare number is seconds), in seconds; a mistake raises ``UsageError`` naming ``flag``. Blanks
    inside the number are refused: they were dropped, and ``--min-stance '1 0 ms'`` read 10 ms."""
    compact = one_text(f"{flag} {text!r}", text, f"{flag} '{{}}'")
    return read_numeric(flag, compact.replace(" ", ""), Numeric("time", "s", least))


def _real(value: object) -> bool:
    """A number (the API's options arrive as any Python value; True is no number here)."""
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


def named(field: str, flags: bool = True) -> str:
    """A ``RunOptions`` field as the caller wrote it: ``legdsl run``'s flag (``--time``,
    ``--integrator``) if ``flags``, else the API's argument (``time=``, ``integrator=``)."""
    if not flags:
        return f"{'time' if field == 'duration' else field}="
    return RUN_NUMERIC[field][0] if field in RUN_NUMERIC else f"--{field.replace('_', '-')}"


def given_as(field: str, value: str, flags: bool = True, unit: str = "") -> str:
    """An option with its value as the caller wrote it: ``--dt 0.4s``, or ``dt=0.4`` (SI)."""
    return f"{named(field)} {value}{unit}" if flags else f"{named(field, False)}{value}"


def check_fall_tilt(tilt: object, flags: bool = True) -> None:
    """A fall tilt (radians) is more than zero and at most upside down; ``legdsl run`` asks
    before it compiles (``--fall-tilt 181`` was refused only after a compile); in the API's
    words (``fall_tilt=``, radians) unless ``flags``."""
    off = "--fall-tilt off (fall_tilt='off' in Python)" if flags else "fall_tilt='off'"
    if not _real(tilt):
        raise UsageError(
            f"{given_as('fall_tilt', repr(tilt), flags)}: must be a number of radians more than "
            "zero, or 'off'"
        )
    tilt = float(tilt)  # type: ignore[arg-type]  # a Real, as _real said
    if not (math.isfinite(tilt) and tilt > 0):
        shown = f"{math.degrees(tilt)!r}deg" if flags else repr(tilt)
        raise UsageError(
            f"{given_as('fall_tilt', shown, flags)}: must be more than zero; "
            + FALL_OFF_ADVICE.format(what="tilt", off=off)
        )
    if tilt > math.pi * (1 + 1e-12):  # fall_tilt=60 in Python is 60 rad, not 60 degrees
        if flags:
            raise UsageError(
                f"--fall-tilt {math.degrees(tilt):.4g}deg ({tilt:.4g} rad) is past upside down "
                "(180 deg), so no tilt would stop the run; give at most 180deg, or off (in "
                "Python a number is radians: write fall_tilt='60 deg')"
            )
        raise UsageError(
            f"fall_tilt={tilt:.4g} (radians: {math.degrees(tilt):.4g} deg) is past upside down "
            "(pi, 180 deg), so no tilt would stop the run; give at most math.pi, a text with "
            "its unit such as fall_tilt='60 deg', or fall_tilt='off'"
        )


def check_run_options(options: RunOptions, flags: bool = True, api: bool = False) -> None:
    """Raise ``UsageError`` for options no run can use (the API's path to the same rules); a
    step is advised as --dt if ``flags``, else (a sweep's or a tune's runs) as the file's;
    the options are named as the API's arguments (``time=``, SI numbers) if ``api``, else
    as ``legdsl run``'s flags."""
    cli = not api

    def say(field: str, value: float, unit: str) -> str:  # --dt 0.4s, or dt=0.4
        return given_as(field, f"{value:g}", cli, unit)

    for field in ("duration", "dt", "control_dt"):
        value = getattr(options, field)
        if not (_real(value) and math.isfinite(value) and value > 0):
            raise UsageError(
                f"{given_as(field, repr(value), cli)}: must be a finite number more than zero"
            )
    for field in ("record_rate", "drop", "fall_height"):
        value = getattr(options, field)
        if value is None or (field == "fall_height" and value == FALL_OFF):
            continue
        if not (_real(value) and math.isfinite(value) and value >= 0):
            off = "--fall-height off (fall_height='off' in Python)" if cli else "fall_height='off'"
            raise UsageError(
                f"{given_as(field, repr(value), cli)}: must be a finite number, zero or more"
                + f"; {FALL_OFF_ADVICE.format(what='height', off=off)}" * (field == "fall_height")
            )
    dt, of = named("dt", cli), " of " if cli else ""  # a --dt of 0.3s, a dt=0.3
    if options.dt > options.duration:  # first: the advice below would lead to it
        shorter = (
            f", or a {dt}{of}{options.duration:g}{'s' * cli} or less"
            if options.duration**2 > 0
            else ""
        )
        raise UsageError(
            f"{say('dt', options.dt, 's')} is longer than the run "
            f"({say('duration', options.duration, 's')}); give "
            f"{say('duration', options.dt, 's')} or more{shorter}" + " (seconds)" * api
        )
    _check_step_counts(options, flags, cli)
    rate = options.record_rate
    if rate is not None and rate > 0 and rate * options.duration < 1.0 - 1e-9:
        # one sample, the start: its summary's end would be its start, its exports one frame
        least = f"{1.0 / options.duration:.3g}"
        raise UsageError(
            f"{say('record_rate', rate, 'Hz')} records only the start of a "
            f"{options.duration:g}{'s' if cli else ' s'} run; give {given_as('record_rate', least, cli, 'Hz')} or "
            f"more{' (Hz)' * api}, or 0 to record every step"
        )
    check_fall_tilt(options.fall_tilt, cli)
    if options.integrator not in ("euler", "rk4"):
        use = "euler or rk4" if cli else "integrator='euler' or integrator='rk4'"
        raise UsageError(f"{given_as('integrator', repr(options.integrator), cli)}: use {use}")
    # the controller runs on steps: once a step at most (a shorter interval ran every step)
    if options.control_dt < options.dt * (1.0 - 1e-9):
        raise UsageError(
            f"{say('control_dt', options.control_dt, 's')} is shorter than the integration "
            f"step ({say('dt', options.dt, 's')}), and the controller runs at most once a step; "
            f"give {say('control_dt', options.dt, 's')} or more, or a {dt}{of}"
            f"{options.control_dt:g}{'s' * cli} or less"
        )


def _check_step_counts(options: RunOptions, flags: bool, cli: bool = True) -> None:
    """A step so small that its square is 0 (the stiffness check divides by it), or a run or
    control interval of more steps than ``MOST_STEPS``: refused (named as flags if ``cli``)."""
    dt = options.dt
    step = "--dt" if flags and cli else "dt"
    if not dt * dt > 0:
        raise UsageError(
            f"{given_as('dt', f'{dt:g}', cli, 's')} is too small to compute with (its square is "
            f"0 in doubles); give {given_as('dt', f'{COMPUTABLE_STEP:g}', cli, 's')} or more "
            f"(below {SMALLEST_STEP:g}s, a second of motion is more than a billion steps)"
        )
    for field, seconds in (("duration", options.duration), ("control_dt", options.control_dt)):
        if seconds / dt > MOST_STEPS:
            where = where_step(flags=flags, step="--dt" if cli else "dt=")
            raise UsageError(
                f"{given_as(field, f'{seconds:g}', cli, 's')} is {seconds / dt:.3g} steps of "
                f"{step} {dt:g}s, more than a run can count ({MOST_STEPS:.3g}); give "
                f"{given_as(field, f'{MOST_STEPS * dt:.3g}', cli, 's')} or less, "
                f"or a longer step {where}"
            )


# A drop is refused where doubles at its height are further apart than this fraction of
# the creature's shortest link: its geometry, added to the height, would be lost in rounding.
DROP_RESOLUTION = 1e-6


def check_drop(drop: float, model: Model, scale: float | None = None) -> None:
    """``--drop H`` for a creature it cannot lift (welded to the world, or without a contact to
    lift), or with H * eps (the spacing of doubles near H, at most) more than
    ``DROP_RESOLUTION`` of the shortest link (of the creature scaled by ``scale``): refused.
    It needs the checked creature alone: ``legdsl run`` asks before compiling it."""
    welded = model.welded_root
    if welded is not None:
        raise UsageError(
            f"--drop lifts a free root, but creature '{model.name}' is welded to the world (its "
            f"root body '{welded}' is 'fixed'): to start it higher, move the point after "
            "'fixed at' in the .leg file"
        )
    if not model.contacts:  # it lifts the lowest contact: without one it would do nothing
        raise UsageError(
            f"--drop lifts the creature until its lowest contact is H above the ground, but "
            f"creature '{model.name}' has no contacts: to start it higher, give its root a "
            "larger 'initial z = ...' in the .leg file"
        )
    links = [(b.length, b.name) for b in model.bodies if b.length]
    if not links:
        return
    length, name = min(links)
    length *= scale or 1.0
    highest = DROP_RESOLUTION * length / sys.float_info.epsilon
    if drop > highest:
        spacing = drop * sys.float_info.epsilon
        raise UsageError(
            f"--drop {drop:g}m: doubles near that height are up to {spacing:.3g} m "
            f"apart, more than {DROP_RESOLUTION:g} of the creature's shortest link ({name}, "
            f"{length:g} m), so its geometry would be lost in rounding; give --drop "
            f"{highest:.3g}m or less"
        )


def _why(e: OSError) -> str:
    return e.strerror or str(e)


def notes_before_run(
    settings: list[str],
    options: RunOptions,
    model: Model,
    sources: Mapping[str, str] | None = None,
    flags: bool = True,
) -> list[str]:
    """What ``legdsl run`` (and the API, as warnings) notes before a run, once its options
    are checked (a mistake in them is told first): changes set for after the run's end (a
    scene's named by its line, ``sources``), and a drop whose fall outlasts the run; its
    options named as ``legdsl run``'s flags if ``flags``, else as the API's arguments."""
    from legdsl.pipeline.scenes import too_late

    check_run_options(options, api=not flags)
    said = [fall_note(options, model, flags), recording_note(options, model, flags)]
    return [*too_late(settings, options, sources, flags), *(note for note in said if note)]


def recording_note(options: RunOptions, model: Model, flags: bool = True) -> str | None:
    """The note of a run whose recording cannot grow to all its samples within
    ``recording_budget`` (the old arrays and the new while it doubles): it will stop early,
    as interrupted (None: it fits, or the system does not say how much memory it has); its
    advice in ``legdsl run``'s flags if ``flags``, else in the API's arguments (a Python
    caller was told "(exit 130)" and "--record-rate"). The budget is the run's as it grows:
    under ``ulimit -v``, half of what the limit leaves once the recording held so far is
    taken, so the figure told is the one the run tells as it stops, in GiB as it does (it was
    the budget now, as if the recording took no room: 937 MB here, then 0.705 GiB there)."""
    per, samples = sample_bytes(model), run_samples(options)
    budget, left = recording_budget(), address_space_left()
    if budget is None:
        return None

    def cap(rows: int) -> int:  # the run's budget once it holds ``rows`` samples
        return budget if left is None else min(budget, (left - rows * per) // 2)

    rows = INITIAL_ROWS
    while rows < samples and (rows + min(samples, 2 * rows)) * per <= cap(rows):
        rows = min(samples, 2 * rows)
    if rows >= samples:
        return None
    ends = options.duration * rows / samples
    return (
        f"this run would record {samples:.3g} samples ({samples * per / 2**30:.3g} GiB); it "
        f"will stop as interrupted{' (exit 130)' * flags} near t = {ends:.3g} s with {rows} "
        "samples, its recording filling half of the memory the run may take (about "
        f"{max(0, cap(rows)) / 2**30:.3g} GiB; the rest is for writing it); to run it all, "
        "record fewer samples "
        + (
            "(a lower --record-rate, or a shorter --time)"
            if flags
            else "(a lower record_rate=, or a shorter time=)"
        )  # fmt: skip
    )


def fall_note(options: RunOptions, model: Model, flags: bool = True) -> str | None:
    """The note of a ``--drop`` whose fall from rest alone outlasts the run (None: it does not,
    or there is no ground or no gravity to fall by); in the API's words unless ``flags``."""
    g = -model.gravity[2]
    if options.drop is None or not options.drop > 0 or model.ground is None or not g > 0:
        return None
    fall = float((2.0 * options.drop / g) ** 0.5)
    if not fall > options.duration:
        return None
    if flags:
        drop, time, lower = f"--drop {options.drop:g}m", f"--time {fall:.3g}s", "--drop"
    else:
        drop, time, lower = f"drop={options.drop:g}", f"time={fall:.3g}", "drop="
    return (f"{drop}: the fall alone takes {fall:.3g} s, longer than the run "
            f"({options.duration:g} s), which ends with the creature in the air; give "
            f"{time} or more, or a lower {lower}")  # fmt: skip


def check_output_dir(path: str | Path, flag: str, shown: str | Path | None = None) -> Path:
    """A directory we may write (made later if missing): not a file, not under a file, and
    writable where it would be made. Raise ``UsageError`` otherwise."""
    if shown is None or str(shown) == str(path):  # the directory itself, not a file's folder
        not_standard_output(path, flag)
    path = Path(path)
    given = f"{flag} {shown if shown is not None else path}"
    if path.exists() and not path.is_dir():
        raise UsageError(f"{given}: this is a file, not a directory; give a directory")
    probe = path
    while not probe.exists():
        if probe.is_symlink():  # dangling, or a loop: nothing can be made there (said after a run)
            raise UsageError(
                f"{given}: {probe} is a symbolic link to {os.readlink(probe)}, which does not "
                "exist (or leads back to itself); make what it points to, or give another directory"
            )
        if probe.parent == probe:
            break
        probe = probe.parent
    if probe.exists() and not probe.is_dir():
        raise UsageError(
            f"{given}: {probe} is a file, so nothing can be made under it; give a directory"
        )
    try:  # a real probe: os.access says yes to root, also on a read-only or special file system
        with tempfile.TemporaryFile(dir=probe, prefix=".legdsl-probe-"):
            pass
    except OSError as e:
        raise UsageError(
            f"{given}: cannot write in {probe} ({_why(e)}); give a directory you can write"
        ) from None
    return path


# A run's files (trajectory.npz and .csv, run.json) over its recording in memory: 1.7 to 2.0
# measured, from a 6 s kangaroo run to a 30 min quadruped's (it was taken as 1, and a note
# given only at under half of that free: a 10 min run needing 61 MB on 21 MB had none)
ON_DISK = 2.0


def space_note(path: Path, flag: str, options: RunOptions, model: Model) -> str | None:
    """A note before the run when the disk under ``path`` may not hold its recording (its
    samples in memory, at most the half of the machine's memory a recording may fill, and
    trajectory.npz and .csv ``ON_DISK`` times that): a full disk refuses it only after the
    run. A note, not a refusal: a long run may be meant to be stopped early, and what it
    recorded by then may fit."""
    recording = run_samples(options) * sample_bytes(model)
    budget = recording_budget()
    need = ON_DISK * (min(recording, budget) if budget is not None else recording)
    free = free_bytes(path)
    if free is None or free >= need:  # None: the system does not say; the write will tell
        return None
    return (
        f"{flag} {path}: the disk there has {free / 1e6:.3g} MB free, and this run's "
        f"recording may take about {need / 1e6:.3g} MB, which a full disk refuses only after "
        f"the run; free some space there, give another {flag}, or record less (a shorter "
        "--time or a lower --record-rate)"
    )


def check_output_file(path: str | Path, flag: str) -> Path:
    """A file we may write: not a directory, its folder a writable directory (or makeable)."""
    path = Path(path)
    if stream := closed_stream(path):
        raise UsageError(f"{flag} {path}: this command was started with {stream} closed (>&-), "
                         "so nothing can be written there; give a file, or leave it open")  # fmt: skip
    if path.is_dir():
        raise UsageError(f"{flag} {path}: this is a directory; give a file name")
    parent = path.parent
    if parent.exists() and not parent.is_dir():
        raise UsageError(
            f"{flag} {path}: {parent} is a file, so nothing can be made under it; "
            "give a file in a directory"
        )
    check_output_dir(parent, flag, path)
    return path


def not_an_input(path: str | Path, flag: str, inputs: list[Path]) -> None:
    """An output that is one of the command's inputs is refused: written, it replaced the
    user's .leg file (export -o FILE.leg) or the run's own recording. So is a .leg name: no
    export is a .leg file, and the one named may be the creature a run.json names."""
    for given in inputs:
        with contextlib.suppress(OSError):
            if Path(path).exists() and Path(path).samefile(given):
                raise UsageError(
                    f"{flag} {path}: this is an input of the command ({given}), which "
                    "writing would destroy; give another file name"
                )
    if Path(path).suffix.lower() == ".leg":
        raise UsageError(
            f"{flag} {path}: a .leg name is for a creature's source, which this command does not "
            "write (and writing may destroy); give the output the name of its format"
        )


def os_error(what: str, path: Path, e: OSError) -> UsageError:
    """A ``UsageError`` for an ``OSError`` met while writing the user's output, naming the
    file of a directory it was writing (docs/runtime.md: a full disk names the file)."""
    file = Path(e.filename) if isinstance(e.filename, str) else None
    inside = f" ({written_as(file)})" if file is not None and file.parent == Path(path) else ""
    return UsageError(f"cannot write {what} {path}{inside}: {_why(e)}; give another place to write")
