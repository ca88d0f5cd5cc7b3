"""What the API gives as read-only: a run's arrays (``run.samples``, ``run[NAME]``,
``run.trajectory``) and a batch's (``copies.status``, ``copies.sim_time``).

Each is a read-only view of the array the run or batch holds (which stays writeable for
the pipeline that made it): changed in place, a series changed the run's own times and
coordinates (its plots, metrics and saved files), and ``copies.status[0] = 'fell'`` stored
``'fe'`` (the array's text width was its longest word's) and ``repr(copies)`` counted it.
"""

from __future__ import annotations

from dataclasses import fields, replace
from typing import Any

import numpy as np

from legdsl.sim.trajectory import ARRAYS, Trajectory


def read_only(array: Any) -> Any:
    """A read-only view of ``array`` (``array`` itself if it is no numpy array)."""
    if not isinstance(array, np.ndarray):
        return array
    view = array.view()
    view.flags.writeable = False
    return view


def read_only_trajectory(trajectory: Trajectory) -> Trajectory:
    """``trajectory`` with each of its arrays a read-only view (its names and meta shared)."""
    arrays = {f.name: read_only(getattr(trajectory, f.name)) for f in fields(trajectory)
              if f.name in ARRAYS}  # fmt: skip
    return replace(trajectory, **arrays)
