"""What a batch's copies take in memory, checked before anything is laid out, and how their
rows are laid out: each copy's from a cache line of its own (``legdsl.pipeline.batch``)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from legdsl.ir.model import Model
from legdsl.lang.errors import UsageError
from legdsl.sim.recorder import address_space_left, recording_budget, sample_bytes
from legdsl.sim.run_loop import RunOptions, run_samples, steps_per_sample

LINE = 64  # bytes: a cache line
PER_COPY_OBJECTS = 1024  # bytes: about what Copies keeps per copy in Python


def check_recordings(model: Model, opts: RunOptions, copies: int) -> None:
    """The copies' recordings are laid out at once, for every sample of their runs: more than
    ``recording_budget`` is refused before anything runs."""
    budget = recording_budget()
    samples = copies * run_samples(opts)
    need = samples * sample_bytes(model)
    if budget is None or need <= budget:
        return
    rate = 1.0 / (steps_per_sample(opts) * opts.dt)
    raise UsageError(
        f"a batch of {copies} copies of {opts.duration:g} s: their recordings would take "
        f"{need / 2**30:,.1f} GiB ({samples:,} samples at {rate:g} Hz), more than "
        f"{budget_words(budget)}; record less often (record_rate="
        f"{rate * budget / need:.3g} fits), run for less time, or run fewer copies at once"
    )


def check_copies_memory(model: Model, opts: RunOptions, copies: int,
                        laid: Mapping[str, tuple[int, Any]], struct: int) -> None:  # fmt: skip
    """The copies' structs, their arrays and their recordings are laid out at once (and a
    Python object per copy is made after): more than ``recording_budget`` in all is refused
    before anything is allocated (else a huge batch is a MemoryError, or the system kills it)."""
    budget = recording_budget()
    rows = sum(-(-size * np.dtype(dtype).itemsize // LINE) * LINE for size, dtype in laid.values())
    per_copy = rows + struct + PER_COPY_OBJECTS + run_samples(opts) * sample_bytes(model)
    if budget is None or copies * per_copy <= budget:
        return
    raise UsageError(
        f"a batch of {copies:,} copies: their states and recordings would take "
        f"{copies * per_copy / 2**30:,.1f} GiB ({per_copy:,} bytes a copy), more than "
        f"{budget_words(budget)}; run at most "
        f"{budget // per_copy:,} copies at once"
    )


def budget_words(budget: int) -> str:
    """``recording_budget``'s ``budget`` said as the limit it is: half of this machine's
    memory, or half of what the process's address-space limit (``ulimit -v``) leaves it (a
    4 GB ``ulimit -v`` on a 23 GB machine was told as "half of this machine's memory (1.8
    GiB)")."""
    left = address_space_left()
    if left is not None and budget >= left // 2:
        import resource

        limit = resource.getrlimit(resource.RLIMIT_AS)[0]
        return (
            f"{budget / 2**30:,.1f} GiB, half of what this process's address-space limit "
            f"(ulimit -v: {limit / 2**30:,.1f} GiB, {(limit - left) / 2**30:,.1f} GiB of it "
            "taken) leaves it"
        )
    return f"{budget / 2**30:,.1f} GiB, half of this machine's memory"


def lined_up(n: int, size: int, dtype: Any) -> np.ndarray:
    """An (n, size) block of zeros whose rows each start a cache line: the copies two threads
    run side by side then never write to one line (which would make the cores take turns)."""
    item = np.dtype(dtype).itemsize
    per = -(-size * item // LINE) * LINE // item  # a row's length, padded to whole lines
    raw = np.zeros(n * per * item + LINE, dtype=np.uint8)
    start = -raw.ctypes.data % LINE
    return raw[start : start + n * per * item].view(dtype).reshape(n, per)[:, :size]
