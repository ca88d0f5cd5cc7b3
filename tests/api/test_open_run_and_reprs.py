"""An outside user's findings: ``legdsl.open_run`` ignored the folder of generated modules a
run was made with (run.json's ``generated``, which ``legdsl metrics`` reads) and wrote a whole
``./generated/NAME/`` into the current directory; and a run of a session or a batch copy
printed some 290 kB as its repr (the model and every array)."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest
from conftest import CREATURES, GENERATED

import legdsl
from legdsl.pipeline.batch import Batch
from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions


def test_open_run_reads_the_modules_the_run_was_made_with(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    gen = tmp_path / "gen"
    shutil.copytree(GENERATED / "hopper", gen / "hopper")
    run = legdsl.load(CREATURES / "hopper.leg", generated=gen).run(controller="hop", time=0.1)
    where = run.save(tmp_path / "runs" / "h")
    (tmp_path / "elsewhere").mkdir()
    monkeypatch.chdir(tmp_path / "elsewhere")
    again = legdsl.open_run(where)
    assert len(again.trajectory.t) == len(run.trajectory.t)
    assert not (tmp_path / "elsewhere" / "generated").exists()  # it wrote a whole one here
    shutil.rmtree(gen)  # the recorded folder gone: generated/ here, compiled as before
    assert len(legdsl.open_run(where).trajectory.t) == len(run.trajectory.t)
    assert (tmp_path / "elsewhere" / "generated" / "hopper" / "dynamics.py").is_file()


def test_a_session_run_and_a_batch_copy_have_a_short_repr(generated: Path) -> None:
    session = RunSession.from_file(CREATURES / "hopper.leg", generated=generated)
    run = session.run("hop", ["speed=1m/s"], options=RunOptions(duration=0.2))
    said = repr(run)
    assert (
        said
        == f"<legdsl run of 'hopper' (controller hop): ok, 0.200 s, {len(run.result.trajectory)} samples>"
    )
    batch = Batch(session, 2, "hop", vary={"speed": (np.array([0.5, 1.0]), "m/s")},
                  options=RunOptions(duration=0.1))  # fmt: skip
    copy = repr(batch.run(threads=1).run(1))
    assert copy.startswith("<legdsl run of 'hopper' (controller hop): ok, 0.100 s, ")
    assert len(copy) < 100
    drop = session.run(None, [], options=RunOptions(duration=0.05))
    assert repr(drop).startswith("<legdsl run of 'hopper' (passive): ")
