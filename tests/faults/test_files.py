"""Writing files whole (``legdsl.files``) at the edges: a target whose name is as long as the
file system allows, and two writers of one run directory at the same moment."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import threading
from pathlib import Path

import numpy as np
import pytest

from legdsl import load
from legdsl.cli import main
from legdsl.files import NAME_MAX, atomic_path, is_leftover, leftovers, temp_sibling, write_atomic
from legdsl.sim.trajectory import Trajectory

ROOT = Path(__file__).resolve().parents[2]
HOPPER = ROOT / "creatures" / "hopper.leg"


def _longest(tmp_path: Path, end: str, letter: str = "a") -> str:
    """A file name of NAME_MAX bytes ending in ``end``, if this file system takes one."""
    name = letter * ((NAME_MAX - len(end.encode())) // len(letter.encode())) + end
    try:
        (tmp_path / name).touch()
        (tmp_path / name).unlink()
    except OSError as e:
        pytest.skip(f"this file system refuses a name of {NAME_MAX} bytes: {e}")
    return name


@pytest.mark.parametrize("letter", ["a", "é", "漢"], ids=["ascii", "two-byte", "three-byte"])
def test_the_longest_name_is_written_whole(tmp_path: Path, letter: str) -> None:
    name = _longest(tmp_path, ".json", letter)
    temp = temp_sibling(tmp_path / name)
    assert len(os.fsencode(temp.name)) <= NAME_MAX and temp.suffix == ".json"
    assert is_leftover(temp, name) and not is_leftover(temp, name[1:])
    write_atomic(tmp_path / name, "{}\n")
    assert [p.name for p in tmp_path.iterdir()] == [name]
    with atomic_path(tmp_path / name, suffix=".usda") as tmp:
        assert tmp.suffix == ".usda" and is_leftover(tmp, name)
        tmp.write_text("#usda 1.0\n")
    assert (tmp_path / name).read_text() == "#usda 1.0\n"


def test_a_dead_writers_shortened_leftover_is_found(tmp_path: Path) -> None:
    name = _longest(tmp_path, ".csv")
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True, check=True)  # fmt: skip
    temp = temp_sibling(tmp_path / name)
    leftover = temp.with_name(temp.name.replace(f"-{os.getpid()}-", f"-{dead.stdout.strip()}-"))
    leftover.touch()
    (tmp_path / "other.csv").touch()
    assert leftovers(tmp_path, name) == [leftover]
    assert leftovers(tmp_path, "other.csv") == []


def test_a_run_and_its_exports_under_the_longest_names(generated: Path, tmp_path: Path) -> None:
    out = tmp_path / _longest(tmp_path, "")
    assert main(["run", str(HOPPER), "--controller", "hop", "--time", "0.5",
                 "--generated", str(generated), "--out", str(out)]) == 0  # fmt: skip
    assert json.loads((out / "run.json").read_text())["status"] == "ok"
    for end in (".bvh", ".gltf", ".usda"):
        if end == ".usda":
            pytest.importorskip("pxr", reason="usd-core is in the test extra")
        target = tmp_path / _longest(tmp_path, end)
        assert main(["export-motion", str(out), "-o", str(target),
                     "--generated", str(generated)]) == 0, end  # fmt: skip
        assert target.stat().st_size > 0
    assert not [p for p in tmp_path.iterdir() if is_leftover(p)]


def test_two_writers_of_one_run_directory_take_turns(generated: Path, tmp_path: Path) -> None:
    """Two runs given the same --out, written at the same moment, again and again: the
    directory always holds one run's files, never run.json of one beside the other's arrays."""
    creature = load(HOPPER, generated=generated)
    runs = [creature.run("hop", set={"speed": s}, time="0.3 s") for s in ("0.5 m/s", "1.5 m/s")]
    out = tmp_path / "run"
    for _ in range(10):  # without the lock, mixed in 2 of 3 tries of 5
        threads = [threading.Thread(target=run.save, args=(out,)) for run in runs for _ in "ab"]
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join()
        info = json.loads((out / "run.json").read_text())
        written = Trajectory.load(out)
        mine = [r for r in runs if np.array_equal(written.q, r.trajectory.q)]
        assert len(mine) == 1  # the arrays of one run, the run.json and the table of the same
        assert "generated" in info.pop("generated")["from_run"]  # said where it is written
        assert info == json.loads(json.dumps(mine[0].info))
        table = np.loadtxt(out / "trajectory.csv", delimiter=",", skiprows=1, usecols=0)
        assert np.allclose(table, mine[0].trajectory.t)


def test_a_writer_that_waits_for_a_directory_says_so(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A run into a folder that another command holds (a video drawn from the run there, for
    minutes) waited without a word."""
    import fcntl

    from legdsl.files import writing_alone

    fd = os.open(tmp_path, os.O_RDONLY | os.O_DIRECTORY)
    fcntl.flock(fd, fcntl.LOCK_EX)  # another command's hold
    entered = threading.Event()

    def write() -> None:
        with writing_alone(tmp_path):
            entered.set()

    writer = threading.Thread(target=write)
    writer.start()
    try:
        assert not entered.wait(0.5)  # it waits...
    finally:
        os.close(fd)  # ...until the other lets go
    writer.join(timeout=10)
    assert entered.is_set()
    assert f"legdsl: {tmp_path} is in use by another legdsl command" in capsys.readouterr().err
