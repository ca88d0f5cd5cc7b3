"""How many keyframes the run's stances get at a frame rate.

The exports resample a run at a fixed rate (60 per second unless ``--fps`` says otherwise),
whatever the creature's size. A small creature's stances are short (a 0.7 mm mite's last
5 ms, a 5 cm hopper's 49 ms) and would get no keyframe or a few: the motion is there, but
the foot's time on the ground is missed. The exports then print a note naming the rate
that gives the stances a few keyframes; the files themselves are as asked for.
"""

from __future__ import annotations

import math

import numpy as np

from legdsl.ir.model import Model
from legdsl.sim.trajectory import Trajectory

FRAMES_PER_STANCE = 4  # enough to see the foot land, load, unload and lift off


def stances(tr: Trajectory, on: np.ndarray) -> list[float]:
    """Durations (s) of the whole stances of ``on`` (a contact's or a leg's flags over the
    samples): touchdown to liftoff, both recorded."""
    on = np.asarray(on) > 0.5
    change = np.flatnonzero(np.diff(on.astype(int))) + 1
    downs = [int(i) for i in change if on[i]]
    ups = [int(i) for i in change if not on[i]]
    durations = []
    for down in downs:
        up = next((u for u in ups if u > down), None)
        if up is not None:
            durations.append(float(tr.t[up] - tr.t[down]))
    return durations


def typical_stance(model: Model, tr: Trajectory) -> tuple[str, float] | None:
    """The leg (``leg NAME``; each contact, for a creature without legs) with the shortest
    median stance and that median (s), or None without a whole stance. A leg stands while any of its soles
    touches (``foot sole, heel, toe``); the median, because a foot that brushes the ground for
    one sample (a tail, a trotting toe's first touch) is no stance to draw."""
    if len(tr) < 3 or not tr.contact.size:
        return None
    if tr.leg_names:
        flags = [(f"leg {name}", tr.leg_touching(i)) for i, name in enumerate(tr.leg_names)]
    else:
        flags = [(c.name, tr.contact[:, k]) for k, c in enumerate(model.contacts)
                 if k < tr.contact.shape[1]]  # fmt: skip
    medians = [(float(np.median(d)), name) for name, on in flags if (d := stances(tr, on))]
    if not medians:
        return None
    duration, name = min(medians)
    return name, duration


def _rounded_up(x: float) -> float:
    """``x`` rounded up to two significant digits (732.5 -> 740, 24.4 -> 25)."""
    step = 10.0 ** (math.floor(math.log10(x)) - 1)
    return float(f"{math.ceil(x / step - 1e-9) * step:.2g}")


def recorded_every_step(steps: object, samples: object) -> bool:
    """Whether a run of ``steps`` integration steps that kept ``samples`` samples recorded
    every step (``record_rate 0 Hz``, or a rate at or above the step's): then only a smaller
    step records faster. False where either count is unknown."""
    return isinstance(steps, int) and isinstance(samples, int) and 0 < steps < samples


def stance_note(
    model: Model, tr: Trajectory, fps: float, slow: float | None = None, every_step: bool = False
) -> str:
    """A note when ``fps`` gives a typical stance fewer than FRAMES_PER_STANCE keyframes (naming
    the rate that gives it that many), or ''. For a video (``slow``: its --slow-motion), the
    frames per simulated second are ``fps * slow``, and the note names the slow motion. Where
    the samples are too few, it says to record faster, or (``every_step``: the run recorded
    every step) that only a smaller step does."""
    stance = typical_stance(model, tr)
    span = float(tr.t[-1] - tr.t[0]) if len(tr) > 1 else 0.0
    if stance is None or stance[1] <= 0 or span <= 0:
        return ""
    foot, duration = stance
    recorded = (len(tr) - 1) / span
    used = min(fps, recorded) if slow is None else fps * slow  # frames per simulated second
    if duration * used >= FRAMES_PER_STANCE:
        return ""
    needed = FRAMES_PER_STANCE / duration
    said = f"legdsl: note: {foot}'s stances ({duration * 1e3:.3g} ms, the median) span "
    if slow is not None:  # a video interpolates between samples: slower is always possible
        advice = f"--slow-motion {_rounded_up(needed / fps):g} gives it {FRAMES_PER_STANCE}"
        return f"{said}{duration * used:.2g} frames of the video at {fps:g} fps; {advice}"
    rate = _rounded_up(needed)
    if rate >= recorded:
        advice = (
            f"the run's {recorded:.4g} samples per second give it the most (--fps {recorded:.4g}); "
            + (
                "they are every step it took, so only a smaller step gives more (legdsl run --dt)"
                if every_step
                else "record it faster for more (legdsl run --record-rate)"
            )
        )
    else:
        advice = f"--fps {rate:g} gives it {FRAMES_PER_STANCE}"
    return f"{said}{duration * used:.2g} keyframes at {used:.4g} per second; {advice}"
