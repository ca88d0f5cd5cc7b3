"""What a stopped ``legdsl tune`` had done, so that the same command run again goes on from there.

``OUT/.tune-journal.json`` holds the plan (all that decides the search: the ``.leg`` file's
digest, the controller, the bounds, the speeds, the objective, the population and the seed),
the start's runs, and each finished generation's candidates, their objectives and the runs of
its best. CMA-ES is deterministic given its seed, so telling a fresh search the recorded
objectives (``ask``, then ``tell``, without a run) brings it to the state of the stopped one,
bit for bit, and the tune goes on as if it had never stopped. A candidate that does not come
out as recorded (another version of cma) discards the generations, and the search starts
again from the start's runs. The journal is kept when a tune finishes: the same command
again comes to the same result without a candidate's run, and one with ``--generations``
raised goes on from its end (a finished tune's journal was removed, and both started afresh);
one with fewer generations than it holds is refused by the command (it replaced the finished
tune's files with the last asked generation's and cut the journal to it, unsaid). It records
the digest of the tuned ``.leg`` file each run writes (``wrote``), so that the command
replaces that file and no other (a user's own edited file in ``--out`` was replaced, unsaid).
A journal of another tune is not replaced either: the command refuses such an ``--out``, as
``legdsl sweep`` does one of another sweep (it said it set the journal aside, and replaced
that tune's files and journal).
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from legdsl.files import write_atomic

JOURNAL = ".tune-journal.json"
# the plan's parts as the command gives them, to say which differ from a journal's
PLAN_WORDS = {
    "creature": "creature (the .leg file changed)",
    "controller": "controller (or its file changed)",
    "bounds": "--param bounds",
    "objective": "--speeds, --time, --from or objective weights",
    "popsize": "--popsize",
    "seed": "--seed",
}
# the objective's fields as the command gives them
OBJECTIVE_WORDS = {
    "speeds": "--speeds", "duration": "--time", "start": "--from", "table2": "--table2",
    "table2_weight": "--table2-weight", "energy_weight": "--energy-weight",
    "spread_weight": "--spread-weight", "pitch_weight": "--pitch-weight",
}  # fmt: skip


@dataclass
class Journal:
    path: Path
    plan: dict[str, Any]
    start: list[Any] | None = None  # the runs of the file's own values, one per speed
    generations: list[dict[str, Any]] = field(default_factory=list)  # xs, scores, best_runs
    # why a journal found in OUT is not gone on from (a damaged one), or None
    set_aside: str | None = None
    # how the tune whose journal is in OUT differs from this one ("other --popsize"), or None
    another: str | None = None
    # the digest of each tuned file a run of this tune wrote, by its name; None for a journal
    # of an earlier legdsl, which recorded none (its files are taken as the tune's)
    wrote: dict[str, str] | None = field(default_factory=dict)

    @classmethod
    def open(cls, out: Path, plan: dict[str, Any]) -> Journal:
        """The journal in ``out`` if it is of this plan, else an empty one: one of another
        tune says how it differs (``another``: the command refuses), a damaged one is set
        aside (no reason to refuse: the tune starts afresh and replaces it)."""
        plan = json.loads(json.dumps(plan))  # as it reads back: lists, not tuples
        journal = cls(out / JOURNAL, plan)
        if not journal.path.exists():
            return journal
        try:
            data = json.loads(journal.path.read_text(encoding="utf-8"))
        except (OSError, UnicodeDecodeError, ValueError):
            data = None
        if isinstance(data, dict) and isinstance(data.get("plan"), dict) and data["plan"] != plan:
            other = _differing(data["plan"], plan)
            journal.another = f"of a tune with other {', '.join(other) or 'settings'}"
            return journal
        start, generations = (data or {}).get("start"), (data or {}).get("generations")
        if _runs(start) and isinstance(generations, list) and all(map(_generation, generations)):
            journal.start, journal.generations = start, generations
            wrote = data.get("wrote") if isinstance(data, dict) else None
            journal.wrote = dict(wrote) if isinstance(wrote, dict) else None
        else:
            journal.set_aside = "it is damaged"
        return journal

    def add(self, xs: list[list[float]], scores: list[float], best_runs: list[Any]) -> None:
        self.generations.append({"xs": xs, "scores": scores, "best_runs": best_runs})
        self.save()

    def save(self) -> None:
        data: dict[str, Any] = {"plan": self.plan, "start": self.start,
                                "generations": self.generations}  # fmt: skip
        if self.wrote is not None:  # an earlier legdsl's journal records none until written
            data["wrote"] = self.wrote
        write_atomic(self.path, json.dumps(data, default=float) + "\n")

    def written(self, path: Path) -> None:
        """Records the tuned file this run wrote at ``path``."""
        self.wrote = {**(self.wrote or {}), path.name: digest(path)}
        self.save()

    def replaces(self, path: Path) -> str | None:
        """Why the tuned file may not replace ``path``, or None where it may: there is none,
        or it is the one a run of this tune wrote, as it wrote it."""
        if not path.exists() and not path.is_symlink():
            return None
        if self.wrote is None:  # an earlier legdsl's journal of this tune: it recorded none
            return None
        if path.is_file() and path.name in (self.wrote or {}):
            if self.wrote and self.wrote[path.name] == digest(path):
                return None
            return "has changed since this tune wrote it"
        return "is not a file this tune wrote"


def digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _differing(before: dict[str, Any], plan: dict[str, Any]) -> list[str]:
    """The options (or the file) that differ between a journal's plan and this tune's, each
    named alone: it named '--param bounds' where only the file's value of a parameter (a
    bound's start) had changed, and four options where --time alone had."""
    other: list[str] = []
    for key, value in plan.items():
        was = before.get(key)
        if was == value:
            continue
        if key == "objective" and isinstance(was, dict) and isinstance(value, dict):
            other += [OBJECTIVE_WORDS.get(str(k), str(k)) for k in value if was.get(k) != value[k]]
        elif key != "bounds" or _without_starts(was) != _without_starts(value):
            other.append(PLAN_WORDS.get(key, key))
    return other


def _without_starts(bounds: object) -> object:
    """Bounds as the command gives them: their starts are the file's values (its digest)."""
    if not isinstance(bounds, list) or not all(isinstance(b, dict) for b in bounds):
        return bounds
    return [{k: v for k, v in b.items() if k != "start"} for b in bounds]


def _runs(rows: object) -> bool:
    return isinstance(rows, list) and all(isinstance(r, dict) and "outcome" in r for r in rows)


def _generation(entry: object) -> bool:
    """Whether a journal's entry is a generation as ``add`` writes it (else the journal was
    edited or damaged, and the tune starts afresh)."""
    return (
        isinstance(entry, dict)
        and isinstance(entry.get("xs"), list)
        and isinstance(entry.get("scores"), list)
        and len(entry["xs"]) == len(entry["scores"]) > 0
        and all(isinstance(v, int | float) for v in entry["scores"])
        and _runs(entry.get("best_runs"))
    )
