"""``legdsl tune``: CMA-ES over chosen controller parameters, minimising an objective of metrics.

    legdsl tune creatures/kangaroo.leg --controller hop --param k_speed=0.01:0.1 \\
        --param kp=50:300 --speeds 3m/s,4m/s,5m/s --time 20 --out tuned/k

The objective of a candidate is the mean, over the commanded ``--speeds``, of

* the relative speed error ``|running speed - command| / command`` (from ``--from`` on),
* plus ``--table2-weight`` times the mean relative distance of the run's metrics to the
  rows of ``--table2 ROW`` (the paper's animation column, where the run measured them); for
  a gait of pairs (Table 2's trot and bound) the runs are measured on its pairs, found from
  the hips as ``legdsl metrics --table2`` finds them, and the share of the pairs' stances
  whose members land more than 10 ms apart is added too, a pair that never touches down
  together landing apart every time (a trot that holds its speed with the diagonal feet
  landing apart is no trot),
* plus ``--spread-weight`` times the stride-to-stride standard deviation of the running speed,
  relative to the command as the error is (a mean on the command can hide a gait swinging
  about it by a sixth over seconds),
* plus ``--pitch-weight`` times the trunk's pitch magnitude in radians: the mean over the
  strides (from ``--from``) of each stride's peak-to-peak pitch, ``pitch_magnitude`` of
  ``legdsl metrics`` (a tune for speed alone left the fast knee biped pitching 12 to 14
  degrees each stride),
* plus ``--energy-weight`` times the run's cost of transport: its positive actuator work per
  metre divided by its weight ``m g`` (``legdsl.analysis.energy``), the energy per metre
  made dimensionless like the other terms,

and a run that falls or diverges at ``t`` of ``T`` scores ``2 + (T - t) / T`` instead: more
the earlier it ends, always worse than any run that lasts (one that lasts without a whole
stride in its window scores 2: said so in the report, and warned of at the start). CMA-ES (the ``cma`` package)
searches the parameters scaled to [0, 1] within their bounds, from the file's values, with
``--seed``; each generation's runs go to parallel processes. It writes ``OUT/NAME.leg``,
the input with only the tuned values changed, ``OUT/tune.json`` (the best values, the
objective of every generation, the start's and the tuned runs' metrics at each speed) and
``OUT/tune.png`` (the objective per generation). Stopped by Ctrl-C or SIGTERM, it writes the
same with the best so far, and the same command goes on from there (``tune_journal``).
"""

from __future__ import annotations

import json
import math
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from legdsl.analysis.plot import pyplot
from legdsl.analysis.table2 import MEASURE, TABLE2
from legdsl.api.sweep import Job, run_jobs
from legdsl.api.tune_journal import Journal
from legdsl.api.tune_pace import time_left, wall
from legdsl.api.tune_report import NO_STRIDE as NO_STRIDE  # (read from here before)
from legdsl.api.tune_report import report as report
from legdsl.api.tune_report import tune_pitch as tune_pitch
from legdsl.api.tune_report import tune_speed as tune_speed
from legdsl.api.workers import Workers
from legdsl.files import atomic_same_name, write_atomic
from legdsl.pipeline.optional import import_whole
from legdsl.sim.run_loop import Interrupted

# how a tune ended early, by what stopped it (``tune.json``'s "ended"; else "finished")
STOPPED_BY: dict[type[BaseException], str] = {
    KeyboardInterrupt: "interrupted",
    Interrupted: "terminated",
}


@dataclass(frozen=True)
class Bound:
    name: str
    low: float  # SI
    high: float
    start: float  # the file's value


@dataclass(frozen=True)
class Objective:
    speeds: tuple[float, ...]  # m/s
    duration: float
    start: float  # measure from
    table2: str | None = None
    table2_weight: float = 1.0
    energy_weight: float = 0.0  # on the cost of transport (-)
    spread_weight: float = 0.0  # on the speed's stride-to-stride spread, relative to the command
    pitch_weight: float = 0.0  # on the trunk's stride pitch magnitude (rad)


def score(rows: Sequence[dict[str, Any]], objective: Objective) -> float:
    """The objective of one candidate from its runs (one per commanded speed)."""
    total = 0.0
    # a command of 0 (in place) has no size of its own: its drift is taken relative to the
    # slowest other command, so drifting at that speed costs as much as standing at it
    moving = [abs(s) for s in objective.speeds if s]
    in_place = min(moving) if moving else 1.0
    for row, speed in zip(rows, objective.speeds, strict=True):
        if row["outcome"] != "ok":
            total += 2.0 + (objective.duration - float(row["simulated"])) / objective.duration
            continue
        measured = float(row["running_speed"])
        # relative to the command's size: a backward command (< 0) is no negative error
        term = abs(measured - speed) / (abs(speed) or in_place) if math.isfinite(measured) else 2.0
        spread = float(row.get("running_speed_std", math.nan))
        if objective.spread_weight and math.isfinite(spread):  # a mean on the command may swing
            term += objective.spread_weight * spread / (abs(speed) or in_place)
        pitch = float(row.get("pitch_magnitude", math.nan))  # degrees, as legdsl metrics says
        if objective.pitch_weight and math.isfinite(pitch):  # held speed, trunk rocking
            term += objective.pitch_weight * math.radians(pitch)
        if objective.table2 is not None:
            apart = pairs_apart(row["by_label"], objective.table2)
            term += objective.table2_weight * (
                table2_distance(row["by_label"], objective.table2) + apart
            )
        cot = float(row.get("cost_of_transport", math.nan))
        if objective.energy_weight and math.isfinite(cot):  # no distance: the speed term says
            term += objective.energy_weight * cot
        total += term
    return total / len(objective.speeds)


def pairs_apart(by_key: dict[str, float], row: str) -> float:
    """The mean share of the pairs' stances whose members land more than 10 ms apart (the
    ``unison_PAIR`` rows; 0 for a gait measured without pairs). A pair whose members never
    touch together has no such stance (its row n/a): it lands apart every time, where it was
    left out and scored as in unison. A gait measured a step a stride (the biped's run: one
    virtual leg of both feet, which take turns) has no pair to land together."""
    if MEASURE.get(row, {}).get("pairs", "steps") == "steps":
        return 0.0
    shares = [v if math.isfinite(v) else 0.0 for k, v in by_key.items() if k.startswith("unison_")]
    return 1.0 - sum(shares) / len(shares) if shares else 0.0


def table2_distance(by_label: dict[str, float], row: str) -> float:
    """Mean relative distance to the paper's animation column over the rows measured."""
    parts = []
    alias = MEASURE.get(row, {})
    for label, (_, paper) in TABLE2[row].items():
        value = by_label.get(label, by_label.get(str(alias.get(label, ""))))
        if value is not None and math.isfinite(value) and paper:
            parts.append(abs(value - paper) / abs(paper))
    return sum(parts) / len(parts) if parts else 0.0


def tune(
    base: Job,
    bounds: Sequence[Bound],
    objective: Objective,
    generations: int,
    popsize: int | None,
    seed: int,
    workers: int,
    say: Callable[[str], None] = print,
    dask: str | None = None,
    journal: Journal | None = None,
    warn: Callable[[str], None] | None = None,
) -> dict[str, Any]:
    """Run CMA-ES; the history, the best values (SI) and the start's and best runs' rows. With
    a ``journal``, each generation is written down as it ends, and the generations it already
    holds are taken from it instead of being run again. ``warn`` (else standard error, after
    ``legdsl: warning:``) is told of a scoring window too short for a stride of the start."""
    warn = warn or (lambda text: print(f"legdsl: warning: {text}", file=sys.stderr))
    cma = import_whole("cma")  # a Ctrl-C there leaves it importable again

    def values_of(x: Sequence[float]) -> dict[str, float]:
        return {
            b.name: b.low + min(1.0, max(0.0, float(u))) * (b.high - b.low)
            for b, u in zip(bounds, x, strict=True)
        }

    def runs(
        pool: Workers,
        candidates: list[dict[str, float]],
        speeds: Sequence[float],
        duration: float | None = None,
    ) -> list[Any]:
        """Each candidate's rows, one per speed, in order (each run ``duration`` s, or the
        objective's)."""
        jobs = [
            replace(base, index=i, values={**c, "speed": s}, units={**base.units, "speed": "m/s"},
                    duration=duration or base.duration)
            for i, (c, s) in enumerate((c, s) for c in candidates for s in speeds)
        ]  # fmt: skip
        done = {row["run"]: row for row in run_jobs(jobs, pool)}
        rows = [done[i] for i in range(len(jobs))]
        n = len(speeds)
        return [rows[k * n : (k + 1) * n] for k in range(len(candidates))]

    def search() -> Any:
        x0 = [(b.start - b.low) / (b.high - b.low) for b in bounds]
        options: dict[str, Any] = {"bounds": [0.0, 1.0], "seed": seed, "maxiter": generations,
                                   "verbose": -9}  # fmt: skip
        if popsize is not None:
            options["popsize"] = popsize
        if len(bounds) == 1:  # cma 4 fails in one dimension once its step passes maxstd (a
            options["maxstd"] = math.inf  # third of the bounds): "not yet initialized"
        return cma.CMAEvolutionStrategy(x0, 0.3, options)

    history: list[dict[str, Any]] = []
    best: tuple[float, dict[str, float], list[Any]] | None = None

    def record(xs: list[list[float]], scores: list[float], best_runs: list[Any]) -> None:
        nonlocal best
        k = min(range(len(scores)), key=scores.__getitem__)
        if best is None or scores[k] < best[0]:
            best = (scores[k], values_of(xs[k]), best_runs)
        history.append({"generation": len(history) + 1, "best": scores[k],
                        "mean": sum(scores) / len(scores),
                        "runs": len(xs) * len(objective.speeds)})  # fmt: skip

    es = search()
    if journal is not None:  # the generations done before: their objectives, told again
        # those past --generations are kept in it: finished work, not lost to a shorter tune
        for before in journal.generations[:generations]:
            xs = es.ask()
            if [list(map(float, x)) for x in xs] != before["xs"]:  # not the recorded search
                es, history, best = search(), [], None
                journal.generations = []
                break
            es.tell(xs, before["scores"])
            record(before["xs"], before["scores"], before["best_runs"])
    start = {b.name: b.start for b in bounds}
    begun: tuple[float, list[Any]] | None = None  # the file's own values: objective, runs
    ended, signal_name = "finished", None
    between: list[dict[str, Any]] | None = None  # the runs between the tuned speeds
    longer: list[dict[str, Any]] | None = None  # the runs twice as long at the tuned speeds
    unscored = ""  # which of those two is under way: an interruption there is in no generation
    tune_began = time.perf_counter()  # the elapsed time told counts the start's runs too
    try:
        # never more processes than a generation's runs (--jobs 100000 forked them all)
        lanes = min(workers, es.popsize * len(objective.speeds))
        with Workers(lanes, dask) as pool:
            if journal is not None and journal.start is not None:
                start_rows = journal.start
            else:
                (start_rows,) = runs(pool, [start], objective.speeds)
            begun = (score(start_rows, objective), start_rows)
            say(f"start: objective {begun[0]:.4g}")
            if short := short_window(start_rows, objective):  # the search could not see it
                warn(short)
            if history:
                assert best is not None
                say(f"generations 1 to {len(history)} from before: so far {best[0]:.4g}")
            if journal is not None:
                journal.start = start_rows
                journal.save()
            began, simulated = time.perf_counter(), 0.0  # this process's generations' runs
            while not es.stop():
                xs = es.ask()
                results = runs(pool, [values_of(x) for x in xs], objective.speeds)
                scores = [score(r, objective) for r in results]
                es.tell(xs, scores)
                xs = [list(map(float, x)) for x in xs]
                best_runs = results[min(range(len(scores)), key=scores.__getitem__)]
                record(xs, scores, best_runs)
                if journal is not None:
                    journal.add(xs, scores, best_runs)
                assert best is not None
                done, spent = len(history), time.perf_counter() - began
                simulated += sum(float(row["simulated"]) for rows in results for row in rows)
                left = time_left(spent, simulated, generations - done, len(xs) * len(objective.speeds),
                                 lanes, objective.duration, objective.speeds,
                                 halfway_speeds(objective.speeds))  # fmt: skip
                elapsed = time.perf_counter() - tune_began
                say(f"generation {done}/{generations}: best {history[-1]['best']:.4g}, so far "
                    f"{best[0]:.4g} ({wall(elapsed)}, about {wall(left)} left)")  # fmt: skip
            if len(history) < generations:  # else the report's few generations are unexplained
                alike = {begun[0]} | {h[k] for h in history for k in ("best", "mean")}
                if any(row["outcome"] != "ok" for row in begun[1]):  # falls alike: said so
                    alike.add(math.nan)
                say(f"CMA-ES stopped after generation {len(history)} of {generations}: "
                    f"{why_stopped(es.stop(), alike.pop() if len(alike) == 1 else None)}")  # fmt: skip
            # a tune fits the speeds it is given, and a gait may still fall between them (the
            # flat-footed biped tuned at 0, 1, 1.5, 2 and 2.5 m/s fell at 1.75): the values
            # kept run once more halfway between each two (not scored)
            if halfway := halfway_speeds(objective.speeds):
                say(
                    f"the tuned values halfway between the tuned speeds: {_more_runs(len(halfway))}"
                )
                unscored = "the runs between the tuned speeds"
                (rows,) = runs(pool, [kept(begun, best, start)[1]], halfway)
                between = [row | {"speed": v} for row, v in zip(rows, halfway, strict=True)]
            # a speed still settling at --time can average right over the window and miss for
            # good after it: a hopper variant tuned over 3 to 10 s ran 0.999 m/s there, 1.03
            # early and 0.96 from 6 s on. The values kept run twice as long once more (not
            # scored), so that the report says where the speed settles.
            twice, speeds = 2 * objective.duration, objective.speeds
            say(f"the tuned values for {twice:g} s, twice as long: {_more_runs(len(speeds))}")
            unscored = "the runs twice as long"
            (rows,) = runs(pool, [kept(begun, best, start)[1]], speeds, twice)
            longer = [row | {"speed": v} for row, v in zip(rows, speeds, strict=True)]
    except (KeyboardInterrupt, Interrupted) as stop:  # the workers are stopped by now
        if begun is None:  # not even the file's own values measured: nothing to keep
            raise
        ended, signal_name = STOPPED_BY[type(stop)], getattr(stop, "signal", None)
        where = unscored or f"generation {len(history) + 1} of {generations}"
        say(f"{ended} in {where}: the best so far is kept")
        between = longer = None
    best = kept(begun, best, start)
    return {
        "start": {"values": start, "objective": begun[0], "runs": begun[1]},
        "best": {"values": best[1], "objective": best[0], "runs": best[2]},
        "history": history,
        "ended": ended,
        **({"between": between} if between is not None else {}),
        **({"longer": longer} if longer is not None else {}),
        **({"signal": signal_name} if signal_name else {}),  # the one that terminated it
    }


def kept(begun: tuple[float, list[Any]], best: tuple[float, dict[str, float], list[Any]] | None,
         start: dict[str, float]) -> tuple[float, dict[str, float], list[Any]]:  # fmt: skip
    """The tune's result: its best candidate, unless none beats the file's own values."""
    if best is None or begun[0] <= best[0]:
        return (begun[0], start, begun[1])
    return best


def unsettled(
    scored: Sequence[dict[str, Any]], longer: Sequence[dict[str, Any]], speeds: Sequence[float]
) -> list[tuple[float, float, float]]:
    """(command, running speed the search scored, running speed over twice the time) at each
    tuned speed where the two differ by more than 1% of the command (of the slowest other
    command for 0, as ``score`` takes it), or the longer run did not last (its speed NaN), or
    measured no stride where the scored one did, or one where the scored one did not (its
    window too short: a stilt scored without a stride at 1 m/s ran 1.482 over twice the time,
    unsaid); not where the scored run itself did not last."""
    moving = [abs(s) for s in speeds if s]
    found = []
    for short, long, speed in zip(scored, longer, speeds, strict=True):
        a, b = float(short["running_speed"]), float(long["running_speed"])
        if short["outcome"] != "ok":  # the report says so already: it did not settle at all
            continue
        # a longer run that lasted without a whole stride, after a scored one without any
        # either, measured nothing to compare (it was said to have fallen)
        if long["outcome"] != "ok" or (math.isfinite(a) and not math.isfinite(b)):
            found.append((speed, a, math.nan))
        elif math.isfinite(b) and (  # moved, or measured a stride where the scored did not
            not math.isfinite(a) or abs(b - a) > 0.01 * (abs(speed) or min(moving, default=1.0))
        ):
            found.append((speed, a, b))
    return found


def short_window(rows: Sequence[dict[str, Any]], objective: Objective) -> str | None:
    """What to say where runs of the file's own values lasted without a whole stride in the
    scoring window (``--from`` to ``--time``): they have no running speed, each scores 2 as a
    run falling at its very end would, and the search cannot tune those speeds (a stilt's 0.7 s
    stride in a 1 s window at 1 m/s left a tune of 1 and 2 m/s tuning 2 alone, unsaid)."""
    none = [(s, r) for s, r in zip(objective.speeds, rows, strict=True)
            if r["outcome"] == "ok" and not math.isfinite(float(r["running_speed"]))]  # fmt: skip
    if not none:
        return None
    at = ", ".join(f"{s:g}" for s, _ in none)
    window = objective.duration - objective.start
    text = (f"the scoring window, from --from {objective.start:g} s to --time {objective.duration:g} s "
            f"({window:.3g} s), held no whole stride of the file's own values at {at} m/s: a "
            "run without a stride has no running speed and scores 2 there, as a run falling at "
            "its very end would, so the search cannot tune that speed; ")  # fmt: skip
    strides = [float(r.get("run_stride_duration", math.nan)) for _, r in none]
    if not all(map(math.isfinite, strides)):  # no stride over the whole run either
        return text + ("it made no whole stride over the whole run either: see with legdsl run "
                       "whether it steps at all (a longer window would not help)")  # fmt: skip
    stride = max(strides)
    need = math.ceil(3 * stride / 0.5) * 0.5  # three strides hold two whole ones, wherever
    if need <= window:  # strides that came late in the run: a window twice as long, then
        need = math.ceil(2 * window / 0.5) * 0.5
    fix = f"--time {objective.start + need:g}"
    if objective.duration - need >= 0:
        fix += f" (or --from {objective.duration - need:g})"
    return text + (f"a stride there takes about {stride:.2g} s over the whole run: give a "
                   f"window of three strides or more, {fix}")  # fmt: skip


def halfway_speeds(speeds: Sequence[float]) -> list[float]:
    """The speeds halfway between each two tuned ones, in order."""
    ordered = sorted(set(speeds))
    return [(a + b) / 2 for a, b in zip(ordered, ordered[1:], strict=False)]


FLAT = ("tolfun", "tolflatfitness", "tolfunhist", "tolstagnation")


def why_stopped(conditions: dict[str, Any], alike: float | None = None) -> str:
    """CMA-ES's termination conditions in words; ``alike``, the one objective every candidate
    and the file's own values scored, if they all did (the tuned parameters changed nothing)."""
    if alike is not None and any(c in conditions for c in FLAT):
        return (
            f"every candidate scored {alike:.4g}, as the file's own values did: the tuned "
            "parameters changed nothing in these runs (the controller reads them only where "
            "these runs never go, a limit they never reach or a state they never enter: see "
            "which with legdsl sweep, or tune other parameters)"
        )
    if any(c in conditions for c in FLAT):
        return (
            "the candidates' objectives no longer differ (if every run falls alike, what "
            "makes it fall is not what is tuned: tune other parameters, or widen the bounds)"
        )
    if "tolx" in conditions or "tolupsigma" in conditions:
        return "its steps have shrunk to nothing: the search has converged"
    return ", ".join(conditions) or "no reason given"


def plot_history(history: Sequence[dict[str, Any]], out: Path, start: float | None = None) -> Path:
    plt = pyplot()
    from matplotlib.ticker import MaxNLocator

    fig, ax = plt.subplots(figsize=(6.4, 4.0), dpi=110)
    gens = [h["generation"] for h in history]
    ax.plot(gens, [h["best"] for h in history], "o-", label="best of the generation")
    ax.plot(gens, [h["mean"] for h in history], ".--", label="mean of the generation")
    if start is not None:
        ax.axhline(start, color="grey", lw=1, ls=":", label="the file's own values")
    ax.set_xlabel("generation")
    ax.xaxis.set_major_locator(MaxNLocator(integer=True, min_n_ticks=1))  # no generation 1.5
    if gens:  # half a generation either side: one generation alone was ticked 0.945 to 1.05
        ax.set_xlim(min(gens) - 0.5, max(gens) + 0.5)
    ax.set_ylabel("objective")
    ax.set_yscale("log")
    # below the axes: inside, it hid the generations' points it fell on
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=3, fontsize="small",
              frameon=False)  # fmt: skip
    fig.tight_layout()
    with atomic_same_name(out) as drawn:  # matplotlib writes in place: no half PNG
        fig.savefig(drawn)
    plt.close(fig)
    return out


def _more_runs(n: int) -> str:
    return "1 more run" if n == 1 else f"{n} more runs"


def dump(result: dict[str, Any], path: Path) -> None:
    """``tune.json``, strict JSON: a metric a run did not measure (one that fell) is null, as in
    run.json, not Python's ``NaN``, which ``jq`` and JavaScript refuse."""
    write_atomic(path, json.dumps(_finite(result), indent=2, allow_nan=False) + "\n")


def _finite(value: Any) -> Any:
    if isinstance(value, dict):
        return {k: _finite(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_finite(v) for v in value]
    if isinstance(value, str | bool | int) or value is None:
        return value
    number = float(value)  # a float, or a numpy number (as json's default=float took them)
    return number if math.isfinite(number) else None
