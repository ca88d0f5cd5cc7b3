"""A Dask scheduler with no worker (none started, or the only one killed mid-sweep) took the
work and waited for ever, silently: an outside user's sweep printed nothing for 45 s. Said
after a short wait, and stopped with what was done kept after a longer one (docs/api.md)."""

from __future__ import annotations

import logging

import pytest

from legdsl.api import workers
from legdsl.lang.errors import UsageError

distributed = pytest.importorskip("distributed")


def double(x: int) -> int:
    return 2 * x


def test_a_scheduler_without_workers_is_said_then_stops(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setattr(workers, "NO_WORKERS_SAID", 1.0)
    monkeypatch.setattr(workers, "NO_WORKERS_STOP", 4.0)
    with distributed.LocalCluster(
        n_workers=0,
        processes=False,
        protocol="tcp",
        dashboard_address=None,
        silence_logs=logging.CRITICAL,
    ) as cluster:
        address = cluster.scheduler_address
        ticks: list[int] = []
        stopped = "has had no workers for 4 s; what was done is kept"
        with pytest.raises(UsageError, match=stopped), workers.Workers(1, address) as pool:
            pool.waiting = lambda: ticks.append(1)
            list(pool.as_completed(double, [1, 2]))
    err = capsys.readouterr().err
    assert (
        f"the scheduler at {address} has no workers: start some with `dask worker {address}`" in err
    )
    assert err.count("has no workers") == 1
    assert len(ticks) >= 3  # a progress log goes on meanwhile


def test_a_worker_coming_is_used(monkeypatch: pytest.MonkeyPatch) -> None:
    with (
        distributed.LocalCluster(
            n_workers=1,
            processes=False,
            protocol="tcp",
            dashboard_address=None,
            silence_logs=logging.CRITICAL,
        ) as cluster,
        workers.Workers(1, cluster.scheduler_address) as pool,
    ):
        assert sorted(pool.as_completed(double, [1, 2, 3])) == [2, 4, 6]
