"""A stopped tune's journal that the command run again cannot go on from: a damaged one is said
to be set aside, another tune's is refused (its files are that tune's results)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from legdsl.api.tune_journal import JOURNAL, Journal
from legdsl.cli import main

ROOT = Path(__file__).resolve().parents[2]
PLAN = {"creature": "c1", "controller": "k1", "bounds": [[0, 1]], "objective": {"speeds": [1.5]},
        "popsize": 8, "seed": 1}  # fmt: skip
RUN = {"outcome": "ok", "simulated": 1.0}

pytestmark = pytest.mark.usefixtures("hopper_modules")


def stopped(out: Path, plan: dict[str, object]) -> None:
    """A journal as a tune stopped after its first generation leaves it."""
    journal = Journal(out / JOURNAL, plan, start=[RUN])
    journal.add([[0.5]], [0.1], [RUN])


def test_a_journal_of_the_same_tune_is_gone_on_from_unsaid(tmp_path: Path) -> None:
    stopped(tmp_path, PLAN)
    journal = Journal.open(tmp_path, PLAN)
    assert journal.set_aside is None and len(journal.generations) == 1


def test_a_journal_of_another_tune_says_which_option_differs(tmp_path: Path) -> None:
    """Run again with another --popsize (or --param bounds in other words), the tune started
    afresh without a word, where the user meant it to go on."""
    stopped(tmp_path, PLAN)
    journal = Journal.open(tmp_path, {**PLAN, "popsize": 6, "seed": 2})
    assert journal.generations == [] and journal.start is None
    assert journal.another == "of a tune with other --popsize, --seed"
    assert journal.set_aside is None


def test_a_damaged_journal_is_said_to_be(tmp_path: Path) -> None:
    (tmp_path / JOURNAL).write_text('{"plan": ')
    assert Journal.open(tmp_path, PLAN).set_aside == "it is damaged"
    assert Journal.open(tmp_path / "none", PLAN).set_aside is None  # no journal: nothing to say


def tune_args(
    tmp_path: Path, out: Path, generated: str = "generated", bounds: str = "0.02:0.2"
) -> list[str]:
    return ["tune", str(ROOT / "creatures" / "hopper.leg"), "--controller", "hop",
            "--param", f"k_speed={bounds}", "--speeds", "1", "--time", "1", "--from", "0.2",
            "--generations", "1", "--popsize", "2", "--jobs", "1", "--out", str(out),
            "--generated", str(tmp_path / generated)]  # fmt: skip


def test_the_command_notes_the_damaged_journal_it_sets_aside(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "tuned"
    out.mkdir()
    (out / JOURNAL).write_text('{"plan": ')
    assert main(tune_args(tmp_path, out)) == 0
    err = capsys.readouterr().err
    assert f"legdsl: note: not going on from {out / JOURNAL}: it is damaged" in err
    assert "this tune starts afresh and replaces it" in err
    # finished: kept, of this tune now, so that raising --generations goes on from it
    assert json.loads((out / JOURNAL).read_text())["generations"]


def test_an_out_holding_another_tune_is_refused_as_a_sweeps_is(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """An outside user's tune of kp=100:200 into tu/rep, then one of kp=100:300: it noted 'not
    going on from tu/rep/.tune-journal.json ... this tune starts afresh and replaces it', and
    replaced the first tune's hopper.leg, tune.json, tune.png and journal; docs/api.md said the
    journal was set aside. Refused now, before any run, as legdsl sweep refuses an --out
    holding another sweep; the files are as they were."""
    out = tmp_path / "tuned"
    assert main(tune_args(tmp_path, out)) == 0
    before = {f.name: f.read_bytes() for f in out.iterdir()}
    capsys.readouterr()
    assert main(tune_args(tmp_path, out, "none", "0.02:0.3")) == 2
    assert capsys.readouterr().err == (
        f"legdsl: {out} holds another tune (.tune-journal.json is of a tune with other --param "
        "bounds); choose another --out or remove it\n"
    )
    assert {f.name: f.read_bytes() for f in out.iterdir()} == before
    assert not (tmp_path / "none").exists()  # nothing compiled, nothing run


def test_a_finished_tune_goes_further_with_more_generations(tmp_path: Path) -> None:
    """A finished tune removed its journal: the same command with --generations raised ran
    every generation again, and overwrote the finished tune's files without a word. Its
    journal is kept now, and the longer tune goes on from it, to the files a tune of that
    length writes from the start."""

    def tuned(out: Path, generations: int) -> int:
        return main(["tune", str(ROOT / "creatures" / "hopper.leg"), "--controller", "hop",
                     "--param", "k_speed=0.02:0.2", "--speeds", "1", "--time", "1", "--from",
                     "0.2", "--generations", str(generations), "--popsize", "2", "--jobs", "1",
                     "--out", str(out), "--generated", str(tmp_path / "generated")])  # fmt: skip

    out, fresh = tmp_path / "tuned", tmp_path / "fresh"
    assert tuned(out, 1) == 0
    first = json.loads((out / JOURNAL).read_text())["generations"]
    assert len(first) == 1
    assert tuned(out, 2) == 0
    assert json.loads((out / JOURNAL).read_text())["generations"][:1] == first
    assert tuned(fresh, 2) == 0
    assert (out / "tune.json").read_bytes() == (fresh / "tune.json").read_bytes()
    assert (out / "hopper.leg").read_bytes() == (fresh / "hopper.leg").read_bytes()


def test_the_options_that_differ_are_each_named_alone(tmp_path: Path) -> None:
    """An outside user's tune with only --time changed was told '--speeds, --time, --from or
    objective weights'; after the file's kp was edited (the bounds as they were) it was told
    '--param bounds' beside the controller."""
    bound = {"name": "kp", "low": 50.0, "high": 300.0, "start": 150.0}
    plan = {
        **PLAN,
        "bounds": [bound],
        "objective": {"speeds": [1.5], "duration": 6.0, "start": 2.0},
    }
    stopped(tmp_path, plan)
    longer = {**plan, "objective": {**plan["objective"], "duration": 7.0}}
    assert Journal.open(tmp_path, longer).another == "of a tune with other --time"
    edited = {**plan, "controller": "k2", "bounds": [{**bound, "start": 160.0}]}
    said = Journal.open(tmp_path, edited).another
    assert said == "of a tune with other controller (or its file changed)"
    wider = {**plan, "bounds": [{**bound, "high": 400.0}]}
    assert Journal.open(tmp_path, wider).another == "of a tune with other --param bounds"
