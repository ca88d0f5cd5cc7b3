"""Which backend runs a simulation: the Python runtime (``legdsl.sim.simulate``), or the same
steps in C (``legdsl.sim.c_backend``), chosen by ``legdsl run --backend c|python|auto``.

``auto``, the default, is the C backend where a C compiler is found and the Python backend
with a one-line notice where none is (docs/runtime.md, "The C backend"); ``python`` is the
readable reference the C is checked against, bit for bit.
"""

from __future__ import annotations

import errno
import numbers
import os
import shlex
from collections.abc import Callable, Iterator, Mapping, Sequence
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING, Any

from legdsl.codegen.c.build import DYNAMICS_FILES, STILL
from legdsl.files import cache_dir
from legdsl.ir.model import Model
from legdsl.lang import ast
from legdsl.lang.errors import InternalError, UsageError
from legdsl.pipeline.generated import c_sources, edited_by_hand
from legdsl.signals import signals_held
from legdsl.sim.run_loop import Interrupted, RunOptions, signal_of
from legdsl.sim.simulate import Controller, Simulation

if TYPE_CHECKING:
    from concurrent.futures import Future

BACKENDS = ("python", "c", "auto")
DEFAULT_BACKEND = "auto"


def chosen(backend: str | None) -> str:
    """``backend`` if given, else ``$LEGDSL_BACKEND`` if set, else ``DEFAULT_BACKEND``."""
    return backend or os.environ.get("LEGDSL_BACKEND") or DEFAULT_BACKEND


def python_backend_note() -> str | None:
    """What a sweep or tune says once where its runs will go on the Python backend for want
    of a C compiler (their runs, told nothing, went many times slower than a ``legdsl run``
    that says so); None where they go on C, or the Python backend was chosen."""
    if chosen(None) != "auto":
        return None
    from legdsl.sim.c_backend import available

    missing = available()
    return None if missing is None else f"{missing}: the runs go on the Python backend"


class CUnavailable(UsageError):
    """``--backend c`` where C cannot run: ``why``, and what to do first (``fix``), for a
    caller that asked for C in its own words (the API's ``run_copies()``)."""

    def __init__(self, why: str, fix: str = ""):
        super().__init__(f"--backend c: {why}; {fix}or use --backend python")
        self.why, self.fix = why, fix


def make_simulation(
    model: Model,
    dynamics: ModuleType,
    options: RunOptions,
    controller: Controller | None,
    backend: str | None,
    where: tuple[Path, Path, ast.SourceFile | None],
    log: Any = None,
    note: Callable[[str], None] | None = None,
) -> Simulation:
    """A simulation on ``backend`` (None: ``chosen``); ``where`` is (the .leg file, generated/,
    its syntax tree). Which backend runs, when not the one asked for, is told to ``log`` (a
    file: ``legdsl run``'s stderr), else to ``note`` (the API's ``LegdslWarning``)."""

    def tell(text: str) -> None:
        if log is not None:
            print(f"legdsl: {text}", file=log)
        elif note is not None:
            note(text)

    given, backend = backend, chosen(backend)
    if backend not in BACKENDS:
        named = f"--backend {backend}" if given else f"LEGDSL_BACKEND={backend}"
        raise UsageError(f"{named}: use one of {', '.join(BACKENDS)}")
    if backend == "python":
        return Simulation(model, dynamics, options, controller)
    from legdsl.codegen.c.build import BuildFailed, CompilerUnusable, NoCompiler
    from legdsl.sim.c_backend import CSimulation, available, load_library, python_version_note

    def python_instead(why: str, fix: str = "") -> Simulation:
        """Where C cannot run: an error with ``--backend c`` (``fix`` then says what to do
        first), else the Python backend with a one-line notice."""
        if backend == "c":
            raise CUnavailable(why, fix) from None
        tell(f"{why}: running on the Python backend")
        return Simulation(model, dynamics, options, controller)

    def refused(folder: Path, name: str | None, failure: Exception) -> Simulation:
        """The compiler refused the C: C edited by hand is the user's to fix; legdsl's own C
        is a bug, which ``--backend c`` stops at (exit 70) and ``auto`` runs past in Python."""
        error = _build_failed(model, where, folder, name, failure)
        if isinstance(error, UsageError) or backend == "c":
            raise error from None
        return python_instead(f"{error} (a bug in legdsl; please report it)")

    missing = available()
    if missing is not None:  # a LEGDSL_CC that is wrong is told what to do already
        return python_instead(missing, "" if missing.startswith("LEGDSL_CC") else "install gcc ")
    from legdsl.sim.c_mirrors import machine_matches, step_matches

    if not step_matches():  # the Python runtime was edited since step.c was brought in line
        tell("the C runtime mirrors an older Python runtime (see legdsl/sim/c_mirrors.py): "
             "running on the Python backend")  # fmt: skip
        return Simulation(model, dynamics, options, controller)
    if controller is not None:  # read here, once: inside the run it was 40 ms of its wall time
        machine_matches()
    source, generated, syntax = where
    # a library per controller (a switching run's: one per controller it switches between)
    names = list(getattr(controller, "modules", None) or [
        getattr(getattr(controller, "module", None), "CONTROLLER", None)
    ])  # fmt: skip
    version_note = python_version_note()
    if version_note is not None:
        tell(version_note)
    libraries = {}

    def building(text: str) -> None:
        print(f"legdsl: {text}", file=log, flush=True)

    def still(text: str) -> None:
        if text.startswith(STILL):
            building(text)

    # on a terminal, a build's seconds (a minute for a large creature) are announced; a log
    # keeps to the one line a failed build is, and hears of a compiler that runs on (a hung
    # one said nothing until it was killed)
    said = None if log is None else building if log.isatty() else still
    for name in names:
        folder = _fresh_sources(model, source, generated, log, syntax, name)
        try:
            library = load_library(model, folder, name, trust=_BATCH[0] > 0, starting=said)
        except NoCompiler as e:  # the compiler went away between the check and the build
            raise UsageError(f"--backend {backend}: {e}") from None
        except CompilerUnusable as e:  # LEGDSL_CC is no compiler, or one without its headers
            return python_instead(str(e))
        except BuildFailed as e:
            return refused(folder, name, e)
        except OSError as e:  # the cache is full, unwritable, or on a file system without exec
            if "undefined symbol" in str(e):  # built, but calls a function nobody defines
                return refused(folder, name, e)
            return python_instead(
                f"cannot build or load the C library in {_cache_name()} ({e.strerror or e})",
                _cache_fix(e),
            )
        if log is not None and not library.built.cached:
            print(f"legdsl: built {library.built.path} in {library.built.seconds:.2f} s", file=log)
        libraries[name] = library
    return CSimulation(model, dynamics, options, controller, libraries)


def _cache_name() -> str:
    """The cache's directory, or what stands for it where there is none."""
    try:
        return str(cache_dir())
    except OSError:
        return "legdsl's cache"


def _cache_fix(e: OSError) -> str:
    """What to do about a cache the C library cannot be built or loaded in."""
    if e.errno in (errno.ENOSPC, errno.EDQUOT):
        return "free space there, set LEGDSL_CACHE to another directory, "
    try:
        folder = cache_dir()
    except OSError:  # no HOME and no home in the user database
        return "set LEGDSL_CACHE (or HOME) to a directory you can write, "
    in_way = next((p for p in (folder, *folder.parents) if p.exists() and not p.is_dir()), None)
    if in_way is not None:  # a file where a directory should be
        return f"move {in_way} (a file, not a directory) away, set LEGDSL_CACHE to a directory, "
    if e.errno in (errno.EMFILE, errno.ENFILE):
        return "raise the limit of open files (ulimit -n), "
    if "map segment" in str(e):  # the loader's words for a file system mounted noexec
        return ("its file system may not run programs (mounted noexec?): set LEGDSL_CACHE "
                "to a directory on one that may, ")  # fmt: skip
    return "set LEGDSL_CACHE to a directory you can write and run programs from, "


def _build_failed(
    model: Model,
    where: tuple[Path, Path, ast.SourceFile | None],
    folder: Path,
    controller: str | None,
    failure: Exception,
) -> Exception:
    """The C compiler refused generated C whose checksums match: the user's error when the
    files are not what legdsl generates (edited by hand, SHA256SUMS with them), else legdsl's
    bug, said in one line with the compiler's first error (``--backend auto`` runs on in Python
    with it as its notice; ``--backend c`` exits 70)."""
    source, _, syntax = where
    names = [*DYNAMICS_FILES] + ([f"control_{controller}.c"] if controller else [])
    edited = edited_by_hand(model, source, folder, syntax, names)
    lines = str(failure).splitlines()
    said = next((line for line in lines[1:] if "error" in line), lines[0] if lines else "")
    said = f": {said.strip()[:300]}" if said.strip() else ""
    if not edited:
        return InternalError(f"the C compiler refused the C legdsl generated in {folder}{said}")
    said = _in_generated(said, folder, controller)  # where an editor can go to the line
    # into the folder the run read (--generated gen2), not generated/
    out = "" if folder.parent == Path("generated") else f" -o {shlex.quote(str(folder.parent))}"
    return UsageError(
        f"the C library cannot be built from {folder / edited[0]}, which differs from what "
        f"legdsl generates from {source} (edited by hand?){said}; run "
        f"'legdsl compile {shlex.quote(str(source))}{out}' to write it again"
    )


def _in_generated(said: str, folder: Path, controller: str | None) -> str:
    """The compiler's words (': file:line:col: ...') with the file named as the user knows it: the
    build compiles copies of ``folder``'s files, the controller's as ``control.c``
    (``control.c:37:37: error: ...`` is ``generated/hopper/control_hop.c:37:37: ...``)."""
    unit, colon, rest = said.removeprefix(": ").partition(":")
    named = {name: name for name in DYNAMICS_FILES}
    if controller:
        named["control.c"] = f"control_{controller}.c"
    return f": {folder / named[unit]}{colon}{rest}" if colon and unit in named else said


# (model, controller, generated/) -> (the model, the stats of its C files when found fresh):
# fingerprinting a model takes tens of milliseconds, which a batch of short runs would feel
_FRESH: dict[tuple[int, str | None, str], tuple[Model, tuple[Any, ...]]] = {}
_BATCH = [0]  # run_batch calls under way: their runs trust the sources found fresh once


def _stats(folder: Path, controller: str | None) -> tuple[Any, ...]:
    names = [*DYNAMICS_FILES] + ([f"control_{controller}.c"] if controller else [])
    found = []
    for file in names:
        try:
            st = (folder / file).stat()
        except OSError:
            return ()
        found.append((file, st.st_mtime_ns, st.st_size))
    return tuple(found)


def _fresh_sources(
    model: Model,
    source: Path,
    generated: Path,
    log: Any,
    syntax: ast.SourceFile | None,
    controller: str | None,
) -> Path:
    """``c_sources``, skipped when this model's C files are unchanged since it last passed."""
    key = (id(model), controller, str(generated))
    folder = generated / model.name
    known = _FRESH.get(key)
    if (
        known is not None
        and known[0] is model
        and known[1]
        and (_BATCH[0] > 0 or known[1] == _stats(folder, controller))
    ):
        return folder  # in a batch, files found fresh once are not looked at again
    folder = c_sources(model, source, generated, log, syntax, controller)
    _FRESH[key] = (model, _stats(folder, controller))
    return folder


def batches_in_c() -> bool:
    """Whether the runs of a batch go on the C backend (``chosen``, and a compiler found)."""
    if chosen(None) == "python":
        return False
    from legdsl.sim.c_backend import available

    return available() is None


def run_batch(
    session: Any,
    jobs: Sequence[Mapping[str, Any]],
    threads: int | None = None,
) -> list[Any]:
    """Run many copies of a session's creature on the C backend at once, ``threads`` at a time.

    Each job is the keyword arguments of ``RunSession.run`` (``controller``, ``settings``,
    ``paths``, ``options``, ...): its own inputs, parameters, actuator settings and start
    (``options.drop``). Returns the ``Run`` of each job, in order; ``iter_batch`` gives them
    as they finish.
    """
    done = dict(iter_batch(session, jobs, threads))
    return [done[i] for i in range(len(jobs))]


def _check_jobs(session: Any, jobs: object, threads: object) -> None:
    """A batch's jobs and threads as ``run_batch`` takes them, else a ``UsageError`` (a
    thread pool's ValueError, or a TypeError from inside a thread, named nothing of yours)."""
    import inspect

    if threads is not None and (
        isinstance(threads, bool) or not isinstance(threads, numbers.Integral) or threads < 1
    ):
        raise UsageError(f"run_batch: threads is a whole number, 1 or more (or None: one per "
                         f"core), not {threads!r}")  # fmt: skip
    if isinstance(jobs, str | bytes | Mapping) or not isinstance(jobs, Sequence):
        raise UsageError(f"run_batch: jobs is a list of RunSession.run's keyword arguments, "
                         f"not {jobs!r}")  # fmt: skip
    known = [k for k in inspect.signature(session.run).parameters if k != "progress"]
    for i, job in enumerate(jobs):
        if not isinstance(job, Mapping):
            raise UsageError(f"run_batch: job {i} is a dict of RunSession.run's keyword "
                             f"arguments ({', '.join(known)}), not {job!r}")  # fmt: skip
        for key in job:
            if key not in known:
                from legdsl.check.values import did_you_mean

                raise UsageError(f"run_batch: job {i} has '{key}'; a job takes "
                                 f"{', '.join(known)}{did_you_mean(str(key), known)}")  # fmt: skip


def iter_batch(
    session: Any,
    jobs: Sequence[Mapping[str, Any]],
    threads: int | None = None,
) -> Iterator[tuple[int, Any]]:
    """``run_batch``'s runs as they finish: (the job's index, its ``Run``).

    The runs go on in ``threads`` parallel threads (default: one per core): the C loop
    releases the GIL, and with the state machine in C a run enters Python only to start, to
    grow its recording and every 20000 steps, so N runs on k cores take about N/k times one
    run. (The copies are separate simulations, each with its own arrays: an
    array-of-structures batch.) Within a batch the sources and library found fresh for the
    first run are not looked at again. A run that raises stops the batch: the runs not yet
    started are cancelled, and the error is raised here. Without the C backend
    (``batches_in_c``) the runs go one after another in this thread (threads would only take
    turns at the GIL). At Ctrl-C (or the CLI's SIGTERM) the runs going on stop where they are
    and come back ``interrupted``, as a single run does, and no other run starts: the
    iterator ends after them.
    """
    _check_jobs(session, jobs, threads)
    for name in dict.fromkeys(j.get("controller") for j in jobs):
        if name is not None:
            session.control(name)  # compiled and loaded here, not by two threads at once
    workers = (threads or os.cpu_count() or 1) if batches_in_c() else 1
    if workers > 1:
        # Each C library built here first: a Ctrl-C comes to this thread, which stops and reaps
        # the compiler processes; a worker thread's build went on, and a Ctrl-C held down cut
        # short the pool's wait for it, leaving them running after the call (seed 21055).
        told = session.log, session.note
        session.log = session.note = None  # a run's notes come once, with the run
        try:
            for job in _one_per_library(jobs):
                session.prepare(**{k: v for k, v in job.items() if k != "progress"})
        finally:
            session.log, session.note = told
    _BATCH[0] += 1
    try:
        if workers == 1:  # a Ctrl-C lands in the run going on, which says so
            for i, job in enumerate(jobs):
                done = session.run(**job)
                yield i, done
                if done.result.status == "interrupted":
                    return
            return
        yield from _in_threads(session, jobs, workers)
    finally:
        _BATCH[0] -= 1


def _in_threads(
    session: Any, jobs: Sequence[Mapping[str, Any]], workers: int
) -> Iterator[tuple[int, Any]]:
    """``iter_batch`` in ``workers`` threads. A signal comes to this thread, waiting for the
    runs; each run asks for it as it reports its progress (at least every 20000 steps in C)
    and ends there as a run Ctrl-C stops in the main thread (``Simulation.run``)."""
    from concurrent.futures import ThreadPoolExecutor

    stop: list[str] = []  # the signal, once one came

    def asked() -> str:
        return stop[0] if stop else ""

    def run(job: Mapping[str, Any]) -> Any:
        plan = session.prepare(**job)
        return plan.finish(plan.sim.run(stop=asked))

    pool = ThreadPoolExecutor(max_workers=workers)
    futures: dict[Future[Any], int] = {}
    told: set[int] = set()
    leaving = False
    try:
        try:
            with signals_held():  # each run known once started: a Ctrl-C finds them all
                for i, job in enumerate(jobs):
                    futures[pool.submit(run, job)] = i
            for future in _as_completed(futures):
                told.add(futures[future])
                yield futures[future], future.result()
        except (KeyboardInterrupt, Interrupted) as sig:
            stop.append(signal_of(sig))
            for future in futures:
                future.cancel()  # those not started
            going = {f: i for f, i in futures.items() if not f.cancelled() and i not in told}
            for future in _as_completed(going):
                yield futures[future], future.result()
    except GeneratorExit:  # the caller left the loop (a break, its own Ctrl-C)
        leaving = True
        raise
    finally:  # a run that raised, or a caller that stopped: start no more, stop the others
        stop.append("the caller stopped")
        try:
            with signals_held():  # they stop at their next report; a Ctrl-C meanwhile waits
                pool.shutdown(wait=True, cancel_futures=True)
        except (KeyboardInterrupt, Interrupted):
            if not leaving:  # else the caller's own exception is on its way out
                raise


def _as_completed(futures: Mapping[Future[Any], int]) -> Iterator[Future[Any]]:
    """The futures as they finish (those found at one wake in the jobs' order), waking every
    0.1 s. A Ctrl-C taken by another thread of the process (one not holding it back: a
    kernel's, Dask's) runs its handler in this one only when this one runs Python again;
    waiting without a timeout, it came as the first run ended, 20 s on, the third run
    already started."""
    from concurrent.futures import FIRST_COMPLETED, wait

    left = set(futures)
    while left:
        done, left = wait(left, timeout=0.1, return_when=FIRST_COMPLETED)
        yield from sorted(done, key=futures.__getitem__)


def _one_per_library(jobs: Sequence[Mapping[str, Any]]) -> list[Mapping[str, Any]]:
    """The first job of each controller, switches and backend: those name the C libraries."""
    first: dict[str, Mapping[str, Any]] = {}
    for job in jobs:
        named = repr([job.get(k) for k in ("controller", "switches", "backend")])
        first.setdefault(named, job)
    return list(first.values())
