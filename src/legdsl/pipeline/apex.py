"""The foot clearance at each hop's apex: a metric that needs the creature's kinematics.

The apex height of the centre of mass comes from the trajectory alone
(``legdsl.analysis.rows.apex_heights``); how high the feet are at that moment needs the contact
points' positions, which the trajectory does not keep. They are recomputed here with the
creature's generated dynamics module (``contact_positions``), found from ``run.json``'s source
and ``generated/NAME/dynamics.py`` when that module is there and fresh (it is never compiled
for this). The clearance of a flight is the height of its lowest foot (the legs' foot
contacts; every contact of a creature without legs) above the ground under it, at the sample
where the centre of mass is highest. A run made with ``--scale L`` is
measured as the scaled creature: its coordinates are scaled back, and the heights by L.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from legdsl.analysis.recorded import recorded_model, run_source
from legdsl.analysis.results import Flight, Summary
from legdsl.analysis.rows import stat
from legdsl.codegen.fingerprints import model_fingerprint
from legdsl.lang.errors import LegError, UsageError
from legdsl.pipeline.generated import import_module_file, recorded_candidates
from legdsl.pipeline.scaled import q_factors
from legdsl.sim.contact import GroundContact
from legdsl.sim.trajectory import Trajectory, load_run_info

KEY = "apex_foot_clearance"
LABEL = "foot clearance at the apex (m)"


class Kinematics(NamedTuple):
    """What a metric needs to recompute a run's contacts: its creature and generated dynamics,
    and the run's ``--scale`` (1 without) with the factors its coordinates were scaled by."""

    model: Any
    dynamics: Any
    q_factors: Any
    scale: float


ROWS = (
    "the rows measured on the creature's geometry (foot clearance at the apex, touchdown "
    "speed, margins to the terrain) are left out"
)
HERE = "run legdsl metrics from the folder the run was made in"


def kinematics_or_why(run: Path, tr: Trajectory, generated: Path | None) -> Kinematics | str:
    """The kinematics of a run's creature, or a note saying why they are not at hand and how
    to have them: each case left the rows out without a word, and copying the .leg file as
    advised did not bring them back (its generated modules, or the files it uses, were not
    found). "" for a trajectory without run.json, which names no creature. The modules are
    ``generated``'s (``--generated``), else those of the folder run.json records
    (``recorded_candidates``) that has them, else ``generated/`` here."""
    try:
        info = load_run_info(run)
    except UsageError:
        return ""
    named = str(info.get("source", ""))
    source = run_source(run, info)
    if source is None:
        if Path(named).is_absolute():
            return f"the file {named!r} that {run}/run.json names is gone, so {ROWS}; put it back"
        give = ("" if recorded_candidates(run, info) else " and give --generated the folder "
                "of its generated modules (generated/ where the run was made)")  # fmt: skip
        return (
            f"the file {named!r} that {run}/run.json names is not found from here, so {ROWS}; "
            f"{HERE}, or copy the file (and the files it uses) into {run}{give}"
        )
    try:
        _, model = recorded_model(run, info, source)  # a creature changed since: a UsageError
    except LegError as e:
        return (
            f"{source}, the file {run}/run.json names, does not load "
            f"({e.render().splitlines()[0]}), so {ROWS}; {HERE}, or copy the files it uses "
            "to where its use lines name them"
        )
    recorded = recorded_candidates(run, info) if generated is None else []
    found = [g for g in recorded if (g / model.name / "dynamics.py").is_file()]
    generated = generated or next(iter(found), Path("generated"))
    path = generated / model.name / "dynamics.py"
    if model.nq != tr.q.shape[1]:
        return (
            f"the creature of {source} has {model.nq} coordinates and the run's {tr.q.shape[1]}, "
            f"so {ROWS}; run it again"
        )
    if not path.is_file():
        return (
            f"{path}, the creature's generated kinematics, is not there (legdsl metrics never "
            f"compiles it){_recorded(recorded)}, so {ROWS}; give --generated the "
            f"folder of the run's generated modules (generated/ where the run was made), or "
            f"make them with legdsl compile {source} --out {generated}"
        )
    dyn = import_module_file(path, f"legdsl_apex_{model.name}")
    if getattr(dyn, "MODEL_FINGERPRINT", None) != model_fingerprint(model):
        return (
            f"{path} is not compiled from the creature of {source} as it is now, so {ROWS}; "
            f"give --generated the folder of the run's generated modules, or make them again "
            f"with legdsl compile {source} --out {generated}"
        )
    scale = float(info.get("scale") or 1.0)
    return Kinematics(model, dyn, q_factors(model, scale), scale)


def _recorded(folders: list[Path]) -> str:
    """Where else the modules were looked for: the folder run.json records."""
    named = dict.fromkeys(os.path.normpath(f) for f in folders)  # often one folder, twice
    return f", nor under {' or '.join(named)}, the folder run.json records" if named else ""


def clearance_row(found: Kinematics, tr: Trajectory, flights: Sequence[Flight]) -> Summary:
    """The mean clearance over the flights, measured with the run's creature ``found``."""
    model, dyn, q_f, scale = found
    names = tuple(c.name for c in model.contacts)
    ground = GroundContact(model.ground, names, model.planar) if model.ground else None
    # every sole of every leg: a leg's clearance is its lowest sole's
    feet_of = [i for leg in range(len(tr.leg_feet)) for i in tr.soles_of(leg)] or list(
        range(len(names))
    )
    values = []
    for f in flights:
        inside = np.flatnonzero((tr.t >= f.t_start) & (tr.t <= f.t_end))
        if not inside.size:
            continue
        k = int(inside[np.argmax(tr.com[inside, 2])])
        points = dyn.contact_positions([float(x) for x in tr.q[k] / q_f])
        feet = [points[i] for i in feet_of]
        under = [ground.height(p[0], p[1]) if ground else 0.0 for p in feet]
        values.append(scale * min(p[2] - h for p, h in zip(feet, under, strict=True)))
    return stat(KEY, LABEL, values)


def with_clearance(summaries: list[Summary], row: Summary | None) -> list[Summary]:
    """The rows with the clearance after the apex height (unchanged without one)."""
    if row is None:
        return summaries
    keys = [s.key for s in summaries]
    at = keys.index("apex_height") + 1 if "apex_height" in keys else len(summaries)
    return [*summaries[:at], row, *summaries[at:]]
