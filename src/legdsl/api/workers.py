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

from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from typing import Any, TypeVar

from legdsl.lang.errors import UsageError

T = TypeVar("T")
R = TypeVar("R")


class Workers:
    def __init__(self, workers: int, dask: str | None = None):
        self.workers = workers
        self.dask = dask
        self._pool: ProcessPoolExecutor | None = None
        self._client: Any = None
        self._cluster: Any = None

    def __enter__(self) -> Workers:
        if self.dask is None:
            return self  # the processes start with the first as_completed
        try:
            from distributed import Client, LocalCluster
        except ImportError:
            raise UsageError("--dask needs Dask: pip install 'dask[distributed]'") from None
        if self.dask == "local":
            self._cluster = LocalCluster(
                n_workers=self.workers, threads_per_worker=1, processes=True, dashboard_address=None
            )
            self._client = Client(self._cluster)
        else:
            try:
                self._client = Client(self.dask, timeout="10s")
            except OSError as e:
                raise UsageError(f"--dask {self.dask}: cannot reach the scheduler ({e})") from None
        return self

    def __exit__(self, *exc: object) -> None:
        if self._pool is not None:
            # Left by an exception (Ctrl-C): the work not yet started is dropped, or shutting
            # down would first run all of it, its results thrown away.
            self._pool.shutdown(cancel_futures=exc[0] is not None)
        if self._client is not None:
            self._client.close()
        if self._cluster is not None:
            self._cluster.close()

    def as_completed(self, fn: Callable[[T], R], items: Sequence[T]) -> Iterator[R]:
        """``fn`` of each item, in the order they finish."""
        if not items:
            return
        if self.dask is None:
            if self._pool is None:
                self._pool = ProcessPoolExecutor(max_workers=self.workers)
            pending = {self._pool.submit(fn, item) for item in items}
            while pending:
                ready, pending = wait(pending, return_when=FIRST_COMPLETED)
                for future in ready:
                    yield future.result()
            return
        from distributed import as_completed

        for future in as_completed(self._client.map(fn, list(items), pure=False)):
            yield future.result()
