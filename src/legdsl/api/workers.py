"""Where sweeps and tuning run their simulations: local processes, or a Dask cluster.

    with Workers(2) as pool:                 # or Workers(2, dask="tcp://host:8786"), "local"
        for result in pool.as_completed(fn, items): ...   # fn(item) for each, as each ends

``Workers(n)`` keeps ``n`` local processes
(``concurrent.futures``, started when first needed) for as long as it is open;
``dask="tcp://HOST:PORT"`` sends the work to that Dask distributed scheduler, and
``dask="local"`` starts a ``LocalCluster`` of ``n`` single-threaded worker processes for the
purpose. Every result is the same wherever it was computed: a run depends only on its inputs.
"""

from __future__ import annotations

import contextlib
import ctypes
import itertools
import logging
import multiprocessing
import os
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from typing import Any, TypeVar

from legdsl.lang.errors import UsageError, thread_refused
from legdsl.pipeline.optional import not_installed
from legdsl.signals import import_held, signals_held, unblock_stopping

IN_FLIGHT = 4  # items handed to the executor per local process at most, the rest queued here

T = TypeVar("T")
R = TypeVar("R")


def dask_address(text: str | None) -> str | None:
    """``--dask``: None (local processes), ``local`` or a scheduler's address, checked before
    any work with Dask at hand (a mistyped one was an internal error once the runs were about
    to start)."""
    if text is None:
        return None
    if text != "local" and text.strip().lower() == "local":
        raise UsageError(f"--dask {text}: did you mean --dask local?")
    try:
        from distributed.comm import get_address_host_port
    except ImportError as e:
        if not not_installed(e, "distributed"):
            raise
        raise UsageError("--dask needs Dask: pip install 'dask[distributed]'") from None
    if text == "local":
        return text
    try:
        _, port = get_address_host_port(text)
        if not 0 < int(port) < 65536:  # waited its 10 s to connect, and said it could not
            raise ValueError(f"port {port} is not one from 1 to 65535")
    except ValueError as e:
        raise UsageError(
            f"--dask {text}: not the address of a Dask scheduler ({e}); give tcp://HOST:PORT, "
            "or local for a cluster of --jobs processes on this machine"
        ) from None
    return text


class Workers:
    def __init__(self, workers: int, dask: str | None = None):
        self.workers = workers
        self.dask = dask_address(dask)
        self._pool: ProcessPoolExecutor | None = None
        self._client: Any = None
        self._cluster: Any = None
        self._started: set[Any] = set()  # the local processes, to read how one ended
        self._hook = threading.excepthook
        # called about every second while no result comes (a progress log's lines go on)
        self.waiting: Callable[[], None] | None = None

    def __enter__(self) -> Workers:
        if self.dask is None:
            self._hook = threading.excepthook  # restored at __exit__
            threading.excepthook = _quiet_when_refused
            return self  # the processes start with the first as_completed
        distributed = import_held("distributed")  # there: dask_address looked
        if self.dask == "local":
            with _ctrl_c_ignored():
                self._cluster = distributed.LocalCluster(
                    n_workers=self.workers,
                    threads_per_worker=1,
                    processes=True,
                    dashboard_address=None,
                    # no dashboard, but its HTTP server (health, metrics) took port 8787, and one
                    # in use let distributed's "Port 8787 is already in use" into the output
                    scheduler_kwargs={"dashboard_address": "127.0.0.1:0"},
                    silence_logs=logging.CRITICAL,  # its workers' lost scheduler, as it closes
                )
                self._client = distributed.Client(self._cluster)
            # the scheduler, here, times the garbage collector from a gc callback: a Ctrl-C
            # landing there was printed ("Exception ignored in: ...GCDiagnosis...") and lost
            import_held("distributed.gc").disable_gc_diagnosis(force=True)
        else:
            try:
                self._client = distributed.Client(self.dask, timeout="10s")
            except OSError as e:
                raise UsageError(f"--dask {self.dask}: cannot reach the scheduler ({e})") from None
        return self

    def __exit__(self, kind: type[BaseException] | None, *exc: object) -> None:
        if self.dask is None:
            threading.excepthook = self._hook
        if self._pool is not None:
            if kind is None:
                self._pool.shutdown()
            else:  # Ctrl-C, SIGTERM or an error: stop the runs under way, never wait for them
                self._stop_processes()
            # each process's finalizer closes its own pipes: left to the garbage collector, a
            # Ctrl-C that landed in it was "Exception ignored in: <Finalize object, dead>"
            with signals_held():
                for process in self._started:
                    with contextlib.suppress(ValueError):  # one not reaped: left as it was
                        process.close()
        dask = [part for part in (self._client, self._cluster) if part is not None]
        if dask:
            with _ctrl_c_ignored():  # a Ctrl-C held down: closed, not half closed
                for part in dask:
                    part.close()

    def _stop_processes(self) -> None:
        assert self._pool is not None
        # the executor's own processes (Python 3.14 names this terminate_workers); left
        # running, a worker of a parent killed by SIGTERM would wait for work forever
        processes = list((getattr(self._pool, "_processes", None) or {}).values())
        manager = getattr(self._pool, "_executor_manager_thread", None)
        with signals_held():  # a second Ctrl-C, in a future's cancel, left its lock taken
            self._pool.shutdown(wait=False, cancel_futures=True)
        for process in processes:
            process.terminate()  # SIGTERM, which a worker leaves at the system's default
        for process in processes:
            process.join()
        if manager is not None:
            # its pipe closes as it ends; Python's exit hook (3.11) wakes every pool's thread
            # without a lock, and wrote to the pipe as the thread closed it: a traceback under
            # "legdsl: interrupted" (OSError: Bad file descriptor), once in about 20 Ctrl-Cs
            manager.join(timeout=10.0)

    def as_completed(self, fn: Callable[[T], R], items: Sequence[T]) -> Iterator[R]:
        """``fn`` of each item, in the order they finish."""
        if not items:
            return
        if self.dask is None:
            yield from self._local(fn, items)
            return
        distributed = import_held("distributed")

        # a Ctrl-C inside map left a Future half made, whose __del__ then printed its
        # AttributeError as "Exception ignored"; it comes once the futures are whole
        with signals_held():
            futures = self._client.map(fn, list(items), pure=False)
        idle = _NoWorkers(str(self.dask))

        def dask_wait(pending: set[Any]) -> tuple[set[Any], set[Any]]:
            try:
                done = distributed.wait(pending, timeout=1.0, return_when="FIRST_COMPLETED")
            except TimeoutError:
                return set(), pending
            return set(done.done), set(done.not_done)

        def dask_idle() -> None:
            idle.check(len(self._client.scheduler_info()["workers"]) if self.dask != "local" else 1)

        def dask_result(future: Any) -> Any:
            try:
                return future.result()
            except distributed.KilledWorker as e:
                raise UsageError(
                    f"the Dask workers running a batch died ({e}; killed, out of memory?); "
                    "what was done is kept, and the same command again goes on from there"
                ) from None

        order = {f: k for k, f in enumerate(futures)}
        yield from self._as_they_end(order, dask_wait, dask_idle, dask_result)

    def _local(self, fn: Callable[[T], R], items: Sequence[T]) -> Iterator[R]:
        """``as_completed`` on the local processes: a few items at a time (``IN_FLIGHT`` per
        process) handed to the executor, more as they end. Every item submitted at once (a
        sweep of 1,000,000 runs) made each wait take the lock of every pending future, seconds
        of it: a Ctrl-C nearly always came in there, left a future's lock taken, and the
        executor's thread, then Python's exit waiting for it, waited for ever ('sweep
        interrupted', then no end). Each call into the executor and its futures is made with
        the stopping signals held, so none is cut short with a lock taken (a Ctrl-C waits at
        most the second of a wait)."""
        if self._pool is None:
            self._pool = ProcessPoolExecutor(max_workers=self.workers, initializer=_worker)
        pool = self._pool
        queued = iter(enumerate(items))
        order: dict[Any, int] = {}
        window = IN_FLIGHT * max(1, self.workers)

        def more(pending: set[Any]) -> None:
            if len(pending) >= window:
                return
            with signals_held():  # the first submit forks the processes
                for k, item in itertools.islice(queued, window - len(pending)):
                    future = pool.submit(fn, item)
                    order[future] = k
                    pending.add(future)
            # kept here: the executor forgets a process that died before its exit code is read
            self._started |= set((getattr(pool, "_processes", None) or {}).values())

        def local_wait(pending: set[Any]) -> tuple[set[Any], set[Any]]:
            with signals_held():
                return wait(pending, timeout=1.0, return_when=FIRST_COMPLETED)

        def local_result(future: Any) -> Any:
            del order[future]  # forgotten once read
            return self._local_result(future)

        yield from self._as_they_end(order, local_wait, self._check_manager, local_result, more)

    def _as_they_end(
        self,
        order: dict[Any, int],
        wait_some: Callable[[set[Any]], tuple[set[Any], set[Any]]],
        idle: Callable[[], None],
        result: Callable[[Any], Any],
        more: Callable[[set[Any]], None] | None = None,
    ) -> Iterator[Any]:
        """The results of the futures of ``order`` as they end, waking every second while none
        does (``idle``: the pool's check; ``waiting``: a progress log's lines go on); ``more``
        adds the next futures to those pending (and to ``order``) before each wait."""
        pending = set(order)
        if more is not None:
            more(pending)
        while pending:
            ready, pending = wait_some(pending)
            if not ready:
                idle()
                if self.waiting is not None:
                    self.waiting()
            # those done by one wake in the order given (a set's order put a table's rows
            # 0, 2, 1 on a loaded machine, and a resume test cut the wrong row)
            for future in sorted(ready, key=order.__getitem__):
                yield result(future)
            if more is not None:
                more(pending)

    def _local_result(self, future: Any) -> Any:
        try:
            with signals_held():  # not cut short with the future's lock taken
                return future.result()
        except BrokenProcessPool:
            self._killed()
            raise

    def _check_manager(self) -> None:
        """The executor feeds its processes from a thread that dies, its futures never to end,
        where a thread it starts cannot (``ulimit -v``: "can't start new thread"): a sweep
        waited for ever. Said as the shortage it is."""
        manager = getattr(self._pool, "_executor_manager_thread", None)
        if manager is not None and not manager.is_alive():
            raise UsageError(
                f"a thread could not start (out of memory?); what was done is kept, and the "
                f"same command again goes on from there: raise the memory limit (ulimit -v), "
                f"or give fewer --jobs than {self.workers}"
            )

    def _killed(self) -> None:
        """A worker killed from outside (SIGKILL: the system's out-of-memory killer, most
        often) is no bug of legdsl's: say so, and what to do (a crash is left as it is)."""
        for process in self._started:  # a process is reaped a moment after its pipes close,
            process.join(timeout=1.0)  # which is when the pool sees it is gone; the others end
        codes = {p.exitcode for p in self._started if p.exitcode is not None}  # the dead ones
        if -signal.SIGKILL in codes:
            raise UsageError(
                f"a worker process was killed (SIGKILL: out of memory?); what was done is kept, "
                f"and the same command again goes on from there: give fewer --jobs than "
                f"{self.workers}, or free memory"
            ) from None


NO_WORKERS_SAID = 10.0  # s without a worker before a Dask scheduler's emptiness is said
NO_WORKERS_STOP = 300.0  # s without a worker before the work stops (exit status 2)


class _NoWorkers:
    """A Dask scheduler with no worker (none started, or the only one killed) takes the work
    and waits for one: a sweep sat silent for ever. Said after ``NO_WORKERS_SAID`` s, and after
    ``NO_WORKERS_STOP`` s a ``UsageError`` (what was done is kept)."""

    def __init__(self, address: str) -> None:
        self.address = address
        self.since: float | None = None  # when the workers were last seen gone
        self.said = False

    def check(self, workers: int) -> None:
        now = time.monotonic()
        if workers:
            self.since, self.said = None, False
            return
        self.since = now if self.since is None else self.since
        gone = now - self.since
        if gone >= NO_WORKERS_STOP:
            raise UsageError(
                f"the Dask scheduler at {self.address} has had no workers for "
                f"{NO_WORKERS_STOP:g} s; what was done is kept, and the same command again "
                f"goes on from there: start some with `dask worker {self.address}` first"
            )
        if gone >= NO_WORKERS_SAID and not self.said:
            self.said = True
            clear = "\r\033[K" if sys.stderr.isatty() else ""  # a progress bar's line
            print(f"{clear}legdsl: the scheduler at {self.address} has no workers: start some "
                  f"with `dask worker {self.address}`; waiting for them ({NO_WORKERS_STOP:g} s "
                  "at most, then it stops with what was done kept)", file=sys.stderr, flush=True)  # fmt: skip


@contextlib.contextmanager
def _ctrl_c_ignored() -> Iterator[None]:
    """Ctrl-C ignored while a local Dask cluster starts or closes. A Ctrl-C in that second
    printed the traceback of each new process, importing, and left the cluster half made,
    which distributed's exit hook failed to close with another (AssertionError: Status.init).
    The processes are spawned, not forked (a signal blocked here is not blocked there), but
    start ignoring what this one ignores, and keep it: a worker that took Ctrl-C printed its
    KeyboardInterrupt's traceback; at a terminal's Ctrl-C, which they get too, this process
    stops them (``__exit__``). A Ctrl-C in that second is lost; the next one stops."""
    if threading.current_thread() is not threading.main_thread():  # signal.signal's only one
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


def _quiet_when_refused(args: threading.ExceptHookArgs) -> None:
    """The executor's thread that could not start another is told of by ``_check_manager``, in
    a line; Python would print its traceback first."""
    if args.exc_value is None or not thread_refused(args.exc_value):
        threading.__excepthook__(args)


def _worker() -> None:
    """A local worker's signals: Ctrl-C is its parent's to handle (which stops the workers, see
    ``Workers.__exit__``), and SIGTERM ends it at once, whatever handler it was forked with."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    unblock_stopping()  # forked under signals_held
    _end_with_parent()


def _end_with_parent() -> None:
    """SIGTERM when the parent ends, however it ends: a parent killed by SIGKILL has no
    ``__exit__`` to stop its workers, and a forked worker, left waiting for work forever,
    would keep the copy of ``OUT/.tune.lock`` (or ``.sweep.lock``) it inherited, refusing
    every later tune or sweep into that ``--out`` (Linux's ``PR_SET_PDEATHSIG``)."""
    if not sys.platform.startswith("linux"):
        return
    libc = ctypes.CDLL(None, use_errno=True)
    libc.prctl(1, signal.SIGTERM, 0, 0, 0)  # PR_SET_PDEATHSIG
    parent = multiprocessing.parent_process()
    if parent is not None and os.getppid() != parent.pid:  # it ended before the prctl
        os._exit(1)
