"""A run goes through pickle (multiprocessing sends results so); metrics(groups=) takes a
dict of name -> legs as well as the texts NAME=LEG,LEG."""

from __future__ import annotations

import os
import pickle
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import CREATURES, ROOT

import legdsl
from legdsl.lang.errors import UsageError


@pytest.fixture(scope="module")
def run(generated: Path) -> legdsl.api.Run:
    return legdsl.load(CREATURES / "hopper.leg", generated=generated).run(controller="hop", time=1)


def test_a_run_goes_through_pickle(run: legdsl.api.Run, tmp_path: Path) -> None:
    again = pickle.loads(pickle.dumps(run))
    assert again.info == run.info and len(again) == len(run)
    assert np.array_equal(again["com.x"], run["com.x"])
    assert again.metrics(start=0.2).table() == run.metrics(start=0.2).table()
    saved = again.save(tmp_path / "again")
    assert (
        legdsl.open_run(saved, generated=Path(run._dynamics.__file__).parents[1]).info == run.info
    )
    assert again.animate(tmp_path / "a.html").read_text().startswith("<!DOCTYPE html>")


def test_a_pickled_run_plays_in_another_process(run: legdsl.api.Run, tmp_path: Path) -> None:
    (tmp_path / "run.pickle").write_bytes(pickle.dumps(run))
    script = ("import pickle, sys; r = pickle.load(open('run.pickle', 'rb')); "
              "print(len(r), r.animate('p.html'))")  # fmt: skip
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    done = subprocess.run([sys.executable, "-c", script], cwd=tmp_path, env=env,
                          capture_output=True, text=True, check=False)  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == [str(len(run)), "p.html"]


def test_a_pickled_run_whose_module_is_gone_says_what_to_do(
    run: legdsl.api.Run, tmp_path: Path
) -> None:
    again = pickle.loads(pickle.dumps(run))
    again._dynamics_file = str(tmp_path / "gone.py")
    with pytest.raises(UsageError, match=r"run.save\(DIR\).*legdsl.open_run\(DIR\)"):
        again.animate(tmp_path / "a.html")


def test_groups_are_a_dict_of_legs_or_texts(run: legdsl.api.Run) -> None:
    leg = run.trajectory.leg_names[0]
    as_dict = run.metrics(groups={"g": [leg]}).table()
    assert as_dict == run.metrics(groups=[f"g={leg}"]).table()
    assert as_dict == run.metrics(groups={"g": leg}).table()
    with pytest.raises(UsageError, match="no leg.*nope|nope"):
        run.metrics(groups={"g": ["nope"]})


@pytest.mark.parametrize("groups", [{"g": 3}, {"g": []}, {3: ["main"]}, ["g"], 5])
def test_a_wrong_groups_shows_both_forms(run: legdsl.api.Run, groups: object) -> None:
    with pytest.raises(UsageError, match=r"\{'front': \['fl', 'fr'\]\} or .*\['front=fl,fr'\]"):
        run.metrics(groups=groups)  # type: ignore[arg-type]


def test_plot_writes_the_format_its_name_says(run: legdsl.api.Run, tmp_path: Path) -> None:
    assert run.plot(tmp_path / "f.svg").read_text().lstrip().startswith("<?xml")
    with pytest.raises(UsageError, match="PNG, SVG or PDF; give a name ending in .png"):
        run.plot(tmp_path / "f")


def test_a_batchs_copies_go_through_pickle_as_their_runs(generated: Path) -> None:
    """``run_copies``' result held the batch's C structs, and pickle refused it ("cannot pickle
    'module' object"): multiprocessing could not send it back. It now goes as its runs."""
    hopper = legdsl.load(CREATURES / "hopper.leg", generated=generated)
    copies = hopper.run_copies(3, "hop", vary={"speed": ([0.5, 1.0, 1.5], "m/s")}, time=0.5)
    again = pickle.loads(pickle.dumps(copies))
    assert again.copies is None and len(again) == 3 and repr(again) == repr(copies)
    assert np.array_equal(again.status, copies.status)
    assert np.array_equal(again.sim_time, copies.sim_time)
    for k in range(3):
        assert again[k].info == copies[k].info
        assert np.array_equal(again[k]["com.x"], copies[k]["com.x"])
    assert again[2].metrics(start=0.1).table() == copies[2].metrics(start=0.1).table()
    assert pickle.loads(pickle.dumps(again))[1].info == copies[1].info  # and again
