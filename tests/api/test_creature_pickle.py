"""A creature goes through pickle (a process pool sends its arguments so): as its file,
checked again on arrival; a file changed or gone since is said, never a different creature."""

from __future__ import annotations

import os
import pickle
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import CREATURES, ROOT

import legdsl
from legdsl.lang.errors import UsageError


@pytest.fixture()
def copied(tmp_path: Path, generated: Path) -> tuple[Path, legdsl.api.Creature]:
    source = tmp_path / "hopper.leg"
    shutil.copy(CREATURES / "hopper.leg", source)
    return source, legdsl.load(source, generated=generated)


def test_a_creature_goes_through_pickle_and_runs_the_same(copied) -> None:
    _, hopper = copied
    again = pickle.loads(pickle.dumps(hopper))
    assert again.name == hopper.name and again.controllers.keys() == hopper.controllers.keys()
    a, b = (c.run(controller="hop", time=0.5) for c in (hopper, again))
    assert np.array_equal(a["com.x"], b["com.x"])


def test_a_pickled_creature_runs_in_another_process(copied, tmp_path: Path) -> None:
    _, hopper = copied
    work = tmp_path / "elsewhere"
    work.mkdir()
    (work / "c.pickle").write_bytes(pickle.dumps(hopper))
    script = ("import pickle; c = pickle.load(open('c.pickle', 'rb')); "
              "print(c.name, c.run(controller='hop', time=0.2).info['status'])")  # fmt: skip
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    done = subprocess.run([sys.executable, "-c", script], cwd=work, env=env,
                          capture_output=True, text=True, check=False)  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["hopper", "ok"]


def test_a_file_changed_since_is_said(copied) -> None:
    source, hopper = copied
    sent = pickle.dumps(hopper)
    text = source.read_text()
    source.write_text(text.replace("param k_speed = 0.06 s", "param k_speed = 0.07 s"))
    assert source.read_text() != text
    with pytest.raises(UsageError, match=r"has changed since.*legdsl.load"):
        pickle.loads(sent)


def test_a_file_gone_is_said(copied) -> None:
    source, hopper = copied
    sent = pickle.dumps(hopper)
    source.unlink()
    with pytest.raises(UsageError, match=r"came through pickle, but its file .* is gone"):
        pickle.loads(sent)


def test_a_refused_creature_leaves_generated_as_it_was(tmp_path: Path, generated: Path) -> None:
    """The refusal came after the edited file was compiled into generated/: a run pickled
    before then failed ('dynamics.py was compiled since from another creature')."""
    source, mine = tmp_path / "hopper.leg", tmp_path / "gen"
    shutil.copy(CREATURES / "hopper.leg", source)
    shutil.copytree(generated / "hopper", mine / "hopper")  # fresh: nothing to compile
    sent = pickle.dumps(legdsl.load(source, generated=mine))
    before = {p: p.read_bytes() for p in (mine / "hopper").rglob("*") if p.is_file()}
    source.write_text(
        source.read_text().replace("mass 10 kg  inertia 0.4", "mass 12 kg  inertia 0.4")
    )
    with pytest.raises(UsageError, match="has changed since"):
        pickle.loads(sent)
    assert {p: p.read_bytes() for p in (mine / "hopper").rglob("*") if p.is_file()} == before
