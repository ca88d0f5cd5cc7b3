"""--dask local (legdsl tune and sweep) with port 8787 taken: distributed's "Port 8787 is
already in use" warning came into the output, its HTTP server being started there though the
dashboard was off."""

from __future__ import annotations

import contextlib
import socket
import warnings

import pytest

from legdsl.api.workers import Workers

pytest.importorskip("distributed")


def test_a_local_cluster_takes_no_fixed_port() -> None:
    held = socket.socket()
    with contextlib.suppress(OSError):  # taken already by another: as good
        held.bind(("", 8787))
        held.listen()
    try:
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always")
            with Workers(1, "local") as pool:
                assert list(pool.as_completed(abs, [-1])) == [1]
    finally:
        held.close()
    assert not [w for w in said if "already in use" in str(w.message)]
