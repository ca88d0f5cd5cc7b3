"""A trajectory.npz that is not a legdsl trajectory: a text file saved under that name made
``legdsl metrics`` pass on numpy's advice to "load it unsafely using the allow_pickle=
keyword argument"; an empty file, "EOFError: No data left in file"; a bare .npy array, "'numpy.
ndarray' object does not support the context manager protocol". Each is said to be no legdsl
trajectory, saying what it is, and numpy's advice to unpickle is never passed on."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from legdsl.lang.errors import UsageError
from legdsl.sim.trajectory import ARRAYS, Trajectory


def _refusal(directory: Path) -> str:
    with pytest.raises(UsageError) as e:
        Trajectory.load(directory)
    return str(e.value)


@pytest.mark.parametrize(
    ("content", "said"),
    [
        (b"hello world\n", "it is text"),
        (b"", "it is empty"),
        (b"\x7fELF\x02\x01\x01\x00\x00\x00\xff\xfe", "it is not a zip of arrays"),
    ],
)
def test_a_file_that_is_no_zip_is_said_to_be_no_trajectory(
    tmp_path: Path, content: bytes, said: str
) -> None:
    (tmp_path / "trajectory.npz").write_bytes(content)
    told = _refusal(tmp_path)
    assert told.startswith(f"{tmp_path / 'trajectory.npz'} is not a legdsl trajectory: {said}")
    assert "pickle" not in told


def test_a_bare_npy_array_is_said_to_be_one(tmp_path: Path) -> None:
    with open(tmp_path / "trajectory.npz", "wb") as f:
        np.save(f, np.arange(3.0))
    assert "it is a single numpy array (.npy)" in _refusal(tmp_path)


def test_python_objects_in_it_are_refused_without_numpys_advice(tmp_path: Path) -> None:
    arrays = {name: np.array([{"a": 1}], dtype=object) for name in (*ARRAYS, "meta")}
    with open(tmp_path / "trajectory.npz", "wb") as f:
        np.savez(f, **arrays)  # type: ignore[arg-type]
    told = _refusal(tmp_path)
    assert "is not a legdsl trajectory: it holds Python objects" in told
    assert "pickle" not in told
