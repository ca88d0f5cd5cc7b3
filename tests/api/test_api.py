"""The public Python API: docs/api.md's examples run as doctests, and the API matches the CLI."""

from __future__ import annotations

import doctest
import filecmp
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import legdsl

ROOT = Path(__file__).resolve().parents[2]


def test_the_api_document_runs(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)
    failures, tried = doctest.testfile(
        str(ROOT / "docs" / "api.md"),
        module_relative=False,
        optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE,
    )
    assert tried >= 20 and failures == 0


def test_an_api_run_is_the_cli_run(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The same settings through legdsl.load(...).run(...) and `legdsl run` write the same files."""
    monkeypatch.chdir(ROOT)
    run = legdsl.load("creatures/hopper.leg").run(
        controller="hop", set={"speed": "1.2 m/s", "speed@0.5s": "0.8 m/s"}, time=1
    )
    api = run.save(tmp_path / "api")
    cli = tmp_path / "cli"
    subprocess.run(
        [sys.executable, "-m", "legdsl", "run", "creatures/hopper.leg", "--controller", "hop",
         "--set", "speed=1.2m/s", "--set", "speed=0.8m/s@0.5s", "--time", "1", "--out", str(cli)],
        check=True, capture_output=True, env={**os.environ, "PYTHONHASHSEED": "0"},
    )  # fmt: skip
    for name in ("trajectory.npz", "trajectory.csv", "run.json"):
        assert filecmp.cmp(api / name, cli / name, shallow=False), name


def test_samples_and_pandas(monkeypatch: pytest.MonkeyPatch) -> None:
    pd = pytest.importorskip("pandas")
    monkeypatch.chdir(ROOT)
    run = legdsl.load("creatures/hopper.leg").run(controller=None, time=0.2, drop=0.1)  # passive
    frame = run.to_pandas()
    assert isinstance(frame, pd.DataFrame) and len(frame) == len(run)
    assert frame.index.name == "t" and "com.z" in frame.columns and "t" not in frame.columns
    assert frame["com.z"].iloc[-1] < frame["com.z"].iloc[0]  # it falls
    with pytest.raises(KeyError, match="did you mean 'com.z'"):
        run["com.zz"]
    assert "<iframe" in run._repr_html_()


def test_run_many_gives_each_run_as_run_gives_it(monkeypatch: pytest.MonkeyPatch) -> None:
    """A batch (threads through the C backend where there is one) returns every run as it
    finishes, each with its index and the same samples as the same run alone."""
    monkeypatch.chdir(ROOT)
    hopper = legdsl.load("creatures/hopper.leg")
    asked = [
        {"controller": "hop", "set": {"speed": f"{v} m/s"}, "time": 0.6} for v in (0.5, 1, 1.5)
    ]
    done = dict(hopper.run_many(asked, threads=2))
    assert sorted(done) == [0, 1, 2]
    for i, kwargs in enumerate(asked):
        alone = hopper.run(**kwargs)
        assert done[i].samples.keys() == alone.samples.keys()
        for name, values in alone.samples.items():
            assert done[i][name].tobytes() == values.tobytes(), name
    from legdsl.lang.errors import UsageError

    with pytest.raises(UsageError, match="speed"):
        list(hopper.run_many([*asked, {"controller": "hop", "set": {"speed": "2 kg"}}]))


def test_a_copy_is_found_by_its_index_and_no_other(monkeypatch: pytest.MonkeyPatch) -> None:
    """copies[-1] was a run of no samples (the rows before copy 0's), copies[5] of 2 an
    IndexError from a list inside, copies['a'] a TypeError about lists."""
    import numpy as np

    monkeypatch.chdir(ROOT)
    copies = legdsl.load("creatures/hopper.leg").run_copies(
        2, "hop", vary={"speed": (np.array([0.5, 1.0]), "m/s")}, time=0.2
    )
    assert copies[-1]["com.x"].tobytes() == copies[1]["com.x"].tobytes()
    assert copies[-2].info["inputs"]["speed"] == 0.5
    assert len(copies[-1]) == len(copies[1]) > 0
    with pytest.raises(IndexError, match=r"copy 2: the batch has 2 copies \(0 to 1\)"):
        copies[2]
    with pytest.raises(IndexError, match="copy -3"):
        copies[-3]
    with pytest.raises(TypeError, match="a copy is found by its index"):
        copies["a"]  # type: ignore[index]
    assert [len(c) for c in copies] == [len(copies[0]), len(copies[1])]  # iterating stops


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda c: c.run(controller=5, time=0.1), "controller= takes a text, not 5"),
        (lambda c: c.run(controller="hop", switch=["1s=hop"], time=0.1), "switch= maps times"),
        (lambda c: list(c.run_many(5)), "runs= is a list of run"),
        (lambda c: list(c.run_many(["x"])), "each run is a dict"),
        (
            lambda c: list(c.run_many([{"controller": None, "time": 0.1}], threads=-1)),
            "threads= is how many",
        ),
        (
            lambda c: list(c.run_many([{"controller": None, "time": 0.1}], threads="2")),
            "threads= is how many",
        ),
        (lambda c: c.run_copies(2, "hop", time=0.1, threads=0), "threads= is how many"),
        (lambda c: c.run_copies(2, "hop", time=0.1, switch={"0.05 s": "hop"}), "run_many"),
        (lambda c: c.run(time=0.1, backend="python"), "no option 'backend' .*LEGDSL_BACKEND"),
        (lambda c: c.run(time=0.1, dtt=0.001), "no option 'dtt'.*did you mean 'dt'"),
        (
            lambda c: c.run_copies(
                2, "hop", time=0.1, path="circle(center = (0, 5) m, radius = 5 m)"
            ),
            "controller hop has no path",
        ),
        (lambda c: c.run_copies(1, "hop", time=0.1, vary=[("speed", ([1], "m/s"))]), "vary= maps"),
        (lambda c: c.run_copies(1, "hop", time=0.1, q0=[["a"] * 5]), "q0: its values are not"),
        (lambda c: c.run_copies(1, "hop", time=0.1, v0=[["x"] * 5]), "v0: its values are not"),
        (
            lambda c: c.run(controller=None, time=0.1).metrics(start=float("nan")),
            "start= is seconds",
        ),
        (lambda c: c.run(controller=None, time=0.1).metrics(start=-1), "start= is seconds"),
        (lambda c: c.run(controller=None, time=0.1).metrics(end=float("inf")), "end= is seconds"),
        (lambda c: c.run(controller=None, time=0.1).metrics(start="1 kg"), "start='1 kg'"),
        (lambda c: c.run(controller=None, time=0.1).plot(start=None), "start= is seconds"),
        (lambda c: c.run(controller=None, time=0.1).save(ROOT / "README.md"), "this is a file"),
        (lambda c: legdsl.load(None), "load.*: give the path of a .leg file, not None"),
        (lambda c: legdsl.open_run(3), "give the path of a run directory, not 3"),
    ],
)
def test_misuse_is_a_usage_error(monkeypatch: pytest.MonkeyPatch, call, message: str) -> None:  # type: ignore[no-untyped-def]
    """Each of these was a TypeError, AttributeError, ValueError or FileExistsError from
    inside legdsl, or (NaN and negative metric windows) metrics of nothing."""
    from legdsl.lang.errors import UsageError

    monkeypatch.chdir(ROOT)
    hopper = legdsl.load("creatures/hopper.leg")
    with pytest.raises(UsageError, match=message):
        call(hopper)


def test_a_switch_time_takes_seconds_as_time_does(monkeypatch: pytest.MonkeyPatch) -> None:
    """{0.5: "hop"} was refused (switch= took texts only), though time=0.5 is seconds."""
    from legdsl.lang.errors import UsageError

    monkeypatch.chdir(ROOT)
    hopper = legdsl.load("creatures/hopper.leg")
    bare = hopper.run(controller="hop", time=1.5, switch={0.5: "hop"})
    said = hopper.run(controller="hop", time=1.5, switch={"500 ms": "hop"})
    assert bare.info["switches"] == said.info["switches"] != []
    assert bare.trajectory.q.tobytes() == said.trajectory.q.tobytes()
    with pytest.raises(UsageError, match="switch= maps times"):
        hopper.run(controller="hop", time=1.5, switch={True: "hop"})


def test_a_metrics_window_takes_a_unit(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)
    run = legdsl.load("creatures/hopper.leg").run(controller="hop", time=2)
    assert run.metrics(start="500 ms").t_from == run.metrics(start=0.5).t_from == 0.5


def test_open_run_compiles_where_it_is_told(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """open_run wrote generated/NAME/ under the current directory, with no way to say where."""
    from conftest import CREATURES, GENERATED

    from legdsl.lang.errors import UsageError

    run = legdsl.load(CREATURES / "hopper.leg", generated=GENERATED).run(controller="hop", time=0.1)
    where = run.save(tmp_path / "run")
    monkeypatch.chdir(tmp_path)
    shutil.copytree(GENERATED / "hopper", tmp_path / "elsewhere" / "hopper")  # fresh: no compile
    again = legdsl.open_run(where, generated=tmp_path / "elsewhere")
    assert len(again.trajectory.t) == len(run.trajectory.t)
    assert (tmp_path / "elsewhere" / "hopper" / "dynamics.py").is_file()
    assert not (tmp_path / "generated").exists()
    with pytest.raises(UsageError, match="generated= is the directory"):
        legdsl.open_run(where, generated=3)  # type: ignore[arg-type]


def test_open_run_of_a_run_made_elsewhere_says_to_give_source(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """open_run told a Python caller 'pass the .leg file with --source FILE', a command-line
    flag: its own way is source=."""
    from conftest import CREATURES, GENERATED

    from legdsl.lang.errors import UsageError

    (tmp_path / "sub").mkdir()
    shutil.copy(CREATURES / "hopper.leg", tmp_path / "sub" / "hopper.leg")
    monkeypatch.chdir(tmp_path / "sub")
    legdsl.load("hopper.leg", generated=GENERATED).run(controller="hop", time=0.1).save("runs/h")
    monkeypatch.chdir(tmp_path)
    with pytest.raises(UsageError) as told:
        legdsl.open_run("sub/runs/h", generated=GENERATED)
    assert "--source" not in str(told.value)
    assert "with source=, as in open_run('sub/runs/h', source='path/to/the.leg')" in str(told.value)
    again = legdsl.open_run("sub/runs/h", source="sub/hopper.leg", generated=GENERATED)
    assert again.model.name == "hopper"
