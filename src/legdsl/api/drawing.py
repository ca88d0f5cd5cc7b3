"""``Run.plot()`` drawn from what the run holds, and where a run's pictures go by default.

Figure 6 is drawn from the run's own samples, model and run.json contents, as ``metrics()``
and ``animate()`` measure and draw: ``plot()`` used to save the run to a directory first and
draw that, reading the creature back from its ``.leg`` file, so a run held in memory whose
file was edited since was refused in the command line's words ('run it again (legdsl run
h.leg ... --out runs/e1)'), and a run never saved left a whole copy of itself (run.json,
trajectory.csv and .npz: 146 MB for a 1500 s run) in a temporary directory, never removed.
Now nothing of the run is written but the picture: into ``path``, else the run's directory
(``save``'s or ``open_run``'s), else a temporary directory of the run's own that holds its
pictures only.
"""

from __future__ import annotations

import re
import tempfile
from pathlib import Path
from typing import Any

from legdsl.files import atomic_same_name
from legdsl.lang.errors import UsageError


def draw_figure6(run: Any, out: Path, t_from: float) -> None:
    """Figure 6 of ``run`` (a ``legdsl.api.Run``) from ``t_from`` into ``out``."""
    from legdsl.analysis.plot import (
        Drawn,
        draw_run,
        ground_height,
        leg_angles,
        pyplot,
        segment_switches,
    )
    from legdsl.analysis.plot_ending import run_ending

    plt = pyplot()
    tr, info = run.trajectory, run.info
    title = run.directory.name if run.directory is not None else run.model.name
    ground = ground_height(run.model, tr, float(info.get("scale") or 1.0))
    welded = run.model.welded_root  # its pitch panel says so
    drawn = Drawn(title, "this run", ground, segment_switches(info), run_ending(info), welded)
    try:
        with atomic_same_name(out) as picture:  # no half PNG under its name
            draw_run(plt, tr, drawn, picture, leg_angles(run.model), t_from, None)
    except UsageError as e:  # the window, in the call's words rather than legdsl plot's
        said = re.sub(r"--from (\S+?)s\b", r"start=\1 s", str(e))
        said = said.replace("give --from and --to within", "give a start within")
        raise UsageError(f"plot(): {said}") from None


def pictures_directory(run: Any) -> Path:
    """Where ``run``'s pictures go when no ``path`` is given: its directory while it holds
    the run (``save`` wrote it, or ``open_run`` read it), else a temporary directory of the
    run's own, made on first use, holding its pictures only."""
    saved = run.directory
    if saved is not None and all((saved / n).is_file() for n in ("run.json", "trajectory.npz")):
        return Path(saved)
    own = run.__dict__.get("_pictures")
    if own is None or not Path(own).is_dir():
        own = run._pictures = Path(tempfile.mkdtemp(prefix=f"legdsl-{run.model.name}-"))
    return Path(own)
