"""legdsl tune: CMA-ES over controller parameters, reproducible with a seed."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import pytest

from legdsl.api.tune import Bound, Objective, pairs_apart, report, score
from legdsl.api.tuned_file import write_tuned
from legdsl.check.source import check_model
from legdsl.cli import main

ROOT = Path(__file__).resolve().parents[2]
HOPPER = ROOT / "creatures" / "hopper.leg"

pytestmark = pytest.mark.usefixtures("hopper_modules")


def tune(out: Path, generated: Path) -> int:
    return main([
        "tune", str(HOPPER), "--controller", "hop", "--param", "k_speed=0.02:0.2",
        "--speeds", "1m/s", "--time", "2.5", "--from", "0.8", "--generations", "2",
        "--popsize", "3", "--seed", "7", "--jobs", "2", "--out", str(out),
        "--generated", str(generated),
    ])  # fmt: skip


def test_a_two_generation_tune_is_reproducible(tmp_path: Path) -> None:
    generated = tmp_path / "generated"
    assert tune(tmp_path / "a", generated) == 0
    assert tune(tmp_path / "b", generated) == 0
    a = json.loads((tmp_path / "a" / "tune.json").read_text())
    b = json.loads((tmp_path / "b" / "tune.json").read_text())
    assert a == b
    assert len(a["history"]) == 2 and a["best"]["objective"] <= a["start"]["objective"]
    tuned = check_model(tmp_path / "a" / "hopper.leg").controller("hop")
    k = {c.name: c.value for c in tuned.params}["k_speed"]
    assert k == pytest.approx(a["best"]["values"]["k_speed"], rel=1e-5)
    # only that value changed in the file
    old = HOPPER.read_text().splitlines()
    new = (tmp_path / "a" / "hopper.leg").read_text().splitlines()
    changed = [i for i, (x, y) in enumerate(zip(old, new, strict=True)) if x != y]
    assert len(changed) <= 1 and all("k_speed" in new[i] for i in changed)
    assert (tmp_path / "a" / "tune.png").stat().st_size > 5_000


def test_one_parameter_tunes_past_the_step_limit(tmp_path: Path) -> None:
    """One --param, seed 1, 4 candidates: CMA-ES's step passes a third of the bounds in the
    second generation, which cma 4 could not handle in one dimension (internal error, exit 70)."""
    code = main([
        "tune", str(HOPPER), "--controller", "hop", "--param", "k_speed=0.01:0.2",
        "--speeds", "1", "--time", "3", "--from", "1", "--generations", "2", "--popsize", "4",
        "--seed", "1", "--jobs", "1", "--out", str(tmp_path / "t"),
        "--generated", str(tmp_path / "generated"),
    ])  # fmt: skip
    assert code == 0
    assert len(json.loads((tmp_path / "t" / "tune.json").read_text())["history"]) == 2


def test_falls_score_by_how_early_they_happen() -> None:
    objective = Objective(speeds=(2.0,), duration=10.0, start=3.0)
    ok = {"outcome": "ok", "running_speed": 1.9, "simulated": 10.0, "by_label": {}}
    late = {"outcome": "fell at 9.000 s", "simulated": 9.0, "running_speed": float("nan")}
    early = {**late, "outcome": "fell at 1.000 s", "simulated": 1.0}
    assert score([ok], objective) == pytest.approx(0.05)
    assert score([ok], objective) < score([late], objective) < score([early], objective)


def test_the_energy_weight_adds_the_cost_of_transport() -> None:
    row = {"outcome": "ok", "running_speed": 1.9, "simulated": 10.0, "by_label": {},
           "cost_of_transport": 0.4, "energy_per_metre": 40.0}  # fmt: skip
    plain = Objective(speeds=(2.0,), duration=10.0, start=3.0)
    weighted = Objective(speeds=(2.0,), duration=10.0, start=3.0, energy_weight=0.5)
    assert score([row], plain) == pytest.approx(0.05)
    assert score([row], weighted) == pytest.approx(0.05 + 0.5 * 0.4)
    standing = {**row, "cost_of_transport": float("nan")}  # no distance: the speed term says
    assert score([standing], weighted) == pytest.approx(0.05)


def test_the_tuned_file_keeps_units_and_comments(tmp_path: Path) -> None:
    hop = check_model(HOPPER).controller("hop")
    out = write_tuned(HOPPER, hop, {"kp": 212.5, "k_speed": 0.075}, tmp_path / "h.leg")
    text = out.read_text()
    assert "  param kp = 212.5 N*m/rad     # eq. (4)" in text  # the comment's column kept
    assert "  param k_speed = 0.075 s      # eq. (3) gain" in text


def test_a_parameter_of_a_shared_part_is_written_where_it_is_declared(tmp_path: Path) -> None:
    """The kangaroo's hop takes its gains from the shared part kangaroo_hop: the tuned file
    changes them there, and a value is never silently left as it was."""
    from legdsl.check.source import check_model

    source = ROOT / "creatures" / "kangaroo.leg"
    hop = check_model(source).controller("hop")
    out = write_tuned(source, hop, {"k_speed": 0.09, "kp": 48.0}, tmp_path / "k.leg")
    tuned = {p.name: p.value for p in check_model(out).controller("hop").params}
    assert tuned["k_speed"] == pytest.approx(0.09) and tuned["kp"] == pytest.approx(48.0)
    changed = [a for a, b in zip(source.read_text().splitlines(), out.read_text().splitlines(),
                                 strict=True) if a != b]  # fmt: skip
    assert len(changed) == 2


@pytest.mark.parametrize(
    "text",
    ["", "{", "[]", '{"plan": {"seed": 1}, "start": 3, "generations": []}',
     '{"plan": {"seed": 1}, "start": [], "generations": [{"xs": [[0.5]], "scores": ["x"]}]}',
     '{"plan": {"seed": 2}, "start": [], "generations": []}'],
    ids=["empty", "cut", "a list", "start", "a generation", "another tune's"],
)  # fmt: skip
def test_a_damaged_or_foreign_journal_starts_the_tune_afresh(tmp_path: Path, text: str) -> None:
    from legdsl.api.tune_journal import JOURNAL, Journal

    (tmp_path / JOURNAL).write_text(text)
    journal = Journal.open(tmp_path, {"seed": 1})
    assert journal.start is None and journal.generations == []
    journal.start = [{"outcome": "ok"}]
    journal.add([[0.5]], [0.25], [{"outcome": "ok"}])
    again = Journal.open(tmp_path, {"seed": 1})
    assert again.start == journal.start and again.generations == journal.generations


NO_PARAMS = """creature arm {
  planar
  gravity 9.81 m/s^2
  body base fixed at (0 m, 1 m) { mass 5 kg  inertia 0.1 kg*m^2 }
  body upper on base via revolute shoulder at (0 m, 0 m) {
    length 0.4 m  com 0.2 m  mass 1 kg  inertia 0.02 kg*m^2
  }
  actuator s on shoulder servo(kp = 50 N*m/rad, kv = 2 N*m*s/rad)
}
controller hold {
  input speed = 1 m/s
  table {
    state A on time_in_state > 0.2 s: s.setpoint = 30 deg
    state B on time_in_state > 0.2 s: s.setpoint = -30 deg
  }
}
"""


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--popsize", "1"], r"--popsize 1: CMA-ES needs at least 2 candidates"),
        (["--popsize", "0"], r"--popsize 0: CMA-ES needs at least 2 candidates"),
        (["--speeds", "0"], r"--speeds 0: a speed of 0 has no relative speed error .* add a speed other than 0"),
        (["--speeds", "1kg"], r"--speeds 1kg: speed is a velocity"),
        # it ran, scored and printed every row twice
        (["--speeds", "1,2,1"], r"--speeds '1,2,1': 1 is given twice \(1 before it is the same value, and its runs would be alike\); give each speed once"),
        (["--speeds", "1:2:0"], r"--speeds '1:2:0': N, the number of values from LO to HI, is a whole number"),
        (["--param", "k_speed=0.03:0.1"], r"--param 'k_speed=0.03:0.1': k_speed's bounds are given twice \(--param k_speed=[^)]* before it\); give each parameter's bounds once\n    --param k_speed=0.03:0.1\n            \^~~~~~~\n"),
        (["--param", "speed=0.5:2"], r"speed is an input of 'hop', not a parameter"),
        (["--param", "k_sped=0.5:2"], r"--param k_sped: not a parameter of the controller; did you mean .k_speed.\? \(it has k_speed,"),
        # an actuator's setting is swept, not tuned: it was "not a parameter of the controller"
        (["--param", "leg_spring.k=1000:5000"], r"--param leg_spring.k: an actuator's setting, which a tune cannot write"),
        (["--table2-weight", "nan"], r"--table2-weight nan: give a weight of 0 or more"),
        (["--table2-weight", "-1"], r"--table2-weight -1: give a weight of 0 or more"),
        (["--from", "1"], r"--from 1 is not a time within the runs \(--time 1\)"),
        (["--seed", "0"], r"--seed 0: give a whole number from 1 to 4294967295"),
        (["--seed", "-1"], r"--seed -1: give a whole number from 1 to 4294967295"),
        (["--seed", str(2**32)], r"--seed 4294967296: give a whole number from 1"),
        (["--param", "stroke=1cm:2cm"],
         r"the file's value 0.03 m is outside the bounds \(0.01 to 0.02 m\); widen them"),
        (["--dask", "bogus"], r"--dask bogus: not the address of a Dask scheduler"),
    ],
)  # fmt: skip
def test_a_tune_that_cannot_search_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], extra: list[str], message: str
) -> None:
    """A population of 0 or 1 was an internal error inside cma (exit 70), a speed of 0 a
    division by zero, a --param given twice, a NaN weight or a --from at the runs' end (no
    speed measured) was taken without a word, a wrong --speeds was reported as a --grid, a
    --seed of 0 gave another search each time (cma's seed from the clock) and one below 0 or
    from 2**32 on was an internal error."""
    args = ["tune", str(HOPPER), "--controller", "hop", "--param", "k_speed=0.02:0.2",
            "--speeds", "1", "--time", "1", "--from", "0.2", "--generations", "1", "--jobs",
            "1", "--out", str(tmp_path / "t"), "--generated", str(tmp_path / "generated")]  # fmt: skip
    for flag in ("--speeds", "--from"):  # given once: a second value is refused as such
        if flag in extra:
            args[args.index(flag) : args.index(flag) + 2] = []
    assert main([*args, *extra]) == 2
    assert re.search(message, capsys.readouterr().err)
    assert not (tmp_path / "t" / "tune.json").exists()


def test_bounds_without_a_unit_for_an_angle_say_they_are_radians(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """stand = -40 deg tuned with --param stand=-50:-30 (meant in degrees, read in radians)
    was told only to widen the bounds; now it is told how to write them in degrees."""
    source = ROOT / "tests" / "good" / "outside" / "knee_runner.leg"
    code = main(["tune", str(source), "--controller", "run", "--param", "stand=-50:-30",
                 "--speeds", "1", "--time", "1", "--from", "0.2", "--out", str(tmp_path / "t"),
                 "--generated", str(tmp_path / "generated")])  # fmt: skip
    assert code == 2
    err = capsys.readouterr().err
    assert "(-50 to -30 rad); widen them; a bare number is in rad: to give them in deg" in err
    assert "stand=-50deg:-30deg" in err
    assert main(["tune", str(source), "--controller", "run", "--param", "stand=-1:-0.5",
                 "--param", "k_speed=1:2", "--speeds", "1", "--time", "1", "--from", "0.2",
                 "--out", str(tmp_path / "t")]) == 2  # fmt: skip
    err = capsys.readouterr().err  # stand's bounds hold its -40 deg: noted as radians, but
    assert "note" not in err  # only once no refusal comes (the notes are of a tune that runs)
    refusal = err.splitlines()[-3]  # (its option echoed with a caret after it)
    assert "k_speed" in refusal and "bare number" not in refusal  # seconds: usual unit is SI


def test_bounds_without_a_unit_say_the_unit_the_file_writes(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The hopper's stroke = 3 cm tuned with --param stroke=1:5 (meant in centimetres, read in
    metres) was told only to widen the bounds, though they were the file's own unit away."""
    code = main(["tune", str(HOPPER), "--controller", "hop", "--param", "stroke=1:5",
                 "--speeds", "1", "--time", "1", "--from", "0.2", "--out", str(tmp_path / "t"),
                 "--generated", str(tmp_path / "generated")])  # fmt: skip
    assert code == 2
    err = capsys.readouterr().err
    assert "(1 to 5 m); widen them; a bare number is in m: to give them in cm" in err
    assert "write stroke=1cm:5cm" in err


def test_a_controller_with_no_parameters_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "arm.leg").write_text(NO_PARAMS)
    code = main(["tune", str(tmp_path / "arm.leg"), "--controller", "hold", "--param",
                 "amp=10deg:40deg", "--speeds", "1", "--out", str(tmp_path / "t"),
                 "--generated", str(tmp_path / "generated")])  # fmt: skip
    assert code == 2
    assert "controller 'hold' has no parameters to tune" in capsys.readouterr().err


def test_a_backward_speed_scores_its_error_as_a_forward_one() -> None:
    """Relative to a command of -1 m/s, running at -1.2 m/s scored -0.2: better than
    perfect, so CMA-ES was drawn to the worst candidates."""
    row = {"outcome": "ok", "running_speed": -1.2, "simulated": 10.0, "by_label": {}}
    backward = Objective(speeds=(-1.0,), duration=10.0, start=3.0)
    assert score([row], backward) == pytest.approx(0.2)


def test_a_speed_of_0_scores_its_drift_against_the_slowest_other_speed() -> None:
    """--speeds 0,0.5,1 was refused, so a trot could not be tuned to stay in place as well
    (tuned at 0.5 to 2 m/s only, the knee quadruped drifted and rolled 10 deg in place)."""
    in_place = {"outcome": "ok", "running_speed": 0.05, "simulated": 10.0, "by_label": {}}
    moving = {**in_place, "running_speed": 0.5}
    objective = Objective(speeds=(0.0, 0.5, -1.0), duration=10.0, start=3.0)
    assert score([in_place, moving, {**moving, "running_speed": -1.0}], objective) == (
        pytest.approx(0.1 / 3)
    )


def test_a_parameter_of_another_file_is_overridden_in_the_tuned_controller(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A gain from a shared part of a used file was refused ("declared in gains.leg"), though
    the controller may override it: the tuned file now declares it in the tuned controller,
    in the used file's unit, and leaves the used file as it was."""
    gains = "shared gains {\n  param k_speed = 60 ms\n}\n"
    (tmp_path / "gains.leg").write_text(gains)
    text = HOPPER.read_text().replace("  param k_speed = 0.06 s       # eq. (3) gain\n", "")
    text = text.replace("controller hop {\n", "controller hop {\n  include gains\n")
    (tmp_path / "uses.leg").write_text('use "gains.leg"\n' + text)
    code = main(["tune", str(tmp_path / "uses.leg"), "--controller", "hop", "--param",
                 "k_speed=0.02:0.2", "--speeds", "1", "--time", "1", "--from", "0.2",
                 "--generations", "1", "--popsize", "2", "--jobs", "1", "--out",
                 str(tmp_path / "t"), "--generated", str(tmp_path / "generated")])  # fmt: skip
    assert code == 0
    assert "the tuned file overrides it in controller 'hop'" in capsys.readouterr().err
    best = json.loads((tmp_path / "t" / "tune.json").read_text())["best"]["values"]["k_speed"]
    tuned = (tmp_path / "t" / "uses.leg").read_text()
    assert re.search(r"controller hop \{\n  param k_speed = [0-9.e-]+ ms\n  include gains", tuned)
    assert (tmp_path / "gains.leg").read_text() == gains
    k = {c.name: c.value for c in check_model(tmp_path / "t" / "uses.leg").controller("hop").params}
    assert k["k_speed"] == best


def test_a_controller_the_creature_lacks_is_named_with_what_it_has(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A creature without controllers (its file uses another's): tune said "'other' has "
    and stopped there."""
    (tmp_path / "uses.leg").write_text(
        f'use "{HOPPER}"\n' + "creature other {\n  planar\n  gravity 9.81 m/s^2\n"
        "  body b free { mass 1 kg  inertia 1 kg*m^2 }\n}\n"
    )
    code = main(["tune", str(tmp_path / "uses.leg"), "--controller", "hop", "--param",
                 "k_speed=0.02:0.2", "--speeds", "1", "--time", "1", "--out", str(tmp_path / "t"),
                 "--generated", str(tmp_path / "generated")])  # fmt: skip
    assert code == 2
    err = capsys.readouterr().err
    assert "creature 'other' has no such controller (it has none)" in err, err


def test_a_search_that_stops_early_says_why(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A hopper tipped over at the start falls at once whatever its gains: CMA-ES stopped after
    one of three generations, and the report gave one generation without a word."""
    source = tmp_path / "tipped.leg"
    source.write_text(HOPPER.read_text().replace("pitch = 0 deg", "pitch = 75 deg"))
    code = main(["tune", str(source), "--controller", "hop", "--param", "kp=100:200",
                 "--speeds", "1", "--time", "1", "--from", "0.1", "--generations", "3",
                 "--popsize", "3", "--jobs", "1", "--out", str(tmp_path / "t"),
                 "--generated", str(tmp_path / "generated")])  # fmt: skip
    assert code == 0
    out = capsys.readouterr().out
    assert "CMA-ES stopped after generation 1 of 3: the candidates' objectives no longer" in out
    assert json.loads((tmp_path / "t" / "tune.json").read_text())["start"]["objective"] == 3.0


def test_a_speed_that_is_no_running_speed_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """An input 'speed' in rad/s was commanded in m/s by every run: each refused it after the
    compile, as a --set the user never wrote."""
    text = NO_PARAMS.replace("input speed = 1 m/s", "input speed = 1 rad/s\n  param amp = 30 deg")
    (tmp_path / "arm.leg").write_text(text.replace("= 30 deg\n    state B", "= amp\n    state B"))
    code = main(["tune", str(tmp_path / "arm.leg"), "--controller", "hold", "--param",
                 "amp=10deg:40deg", "--speeds", "1", "--out", str(tmp_path / "t"),
                 "--generated", str(tmp_path / "generated")])  # fmt: skip
    assert code == 2
    assert "input 'speed' of controller 'hold' is angular velocity (rad/s), not a running" in (
        capsys.readouterr().err
    )


def test_a_parameter_of_the_controller_extended_is_overridden_not_changed(tmp_path: Path) -> None:
    """Tuning tripod_fast (extends tripod) changed kp in tripod's declaration: the tuned file's
    tripod changed too, unsaid."""
    source = ROOT / "tests" / "good" / "outside" / "hexapod.leg"
    fast = check_model(source).controller("tripod_fast")
    out = write_tuned(source, fast, {"kp": 150.0, "k_speed": 0.08}, tmp_path / "h.leg")
    tuned = check_model(out)
    values = {
        c: {p.name: p.value for p in tuned.controller(c).params} for c in ("tripod", "tripod_fast")
    }
    assert values["tripod_fast"]["kp"] == pytest.approx(150.0)
    assert values["tripod_fast"]["k_speed"] == pytest.approx(0.08)
    before = {p.name: p.value for p in check_model(source).controller("tripod").params}
    assert values["tripod"] == before  # the controller extended is as it was
    assert "  param kp = 150 N*m/rad\n  input speed = 1 m/s" in out.read_text()


def test_an_out_that_would_replace_the_file_itself_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--out at the file's own directory wrote the tuned file over the one tuned."""
    source = tmp_path / "hopper.leg"
    source.write_text(HOPPER.read_text())
    code = main(["tune", str(source), "--controller", "hop", "--param", "kp=100:200",
                 "--speeds", "1", "--time", "1", "--from", "0.2", "--generations", "1",
                 "--popsize", "2", "--jobs", "1", "--out", str(tmp_path / "." ),
                 "--generated", str(tmp_path / "generated")])  # fmt: skip
    assert code == 2
    assert "would replace" in capsys.readouterr().err
    assert source.read_text() == HOPPER.read_text()


def test_a_parameter_of_a_shared_part_is_said_to_change_for_every_includer(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Tuning the kangaroo's kp, declared in its shared part kangaroo_hop, changes it for every
    controller that includes the part (documented, but not said); a controller's own is not.
    The note comes once no refusal does: not before --seed 0's refusal."""
    import legdsl.api.tune_cli as tune_cli

    kangaroo = HOPPER.parent / "kangaroo.leg"
    args = ["--speeds", "3", "--seed", "0", "--out", str(tmp_path)]
    assert main(["tune", str(kangaroo), "--controller", "hop", "--param", "kp=30:300", *args]) == 2
    assert "note" not in capsys.readouterr().err
    monkeypatch.setattr(tune_cli, "_tune_into", lambda *a: 0)  # the notes, then no search
    args[3] = "1"
    assert main(["tune", str(kangaroo), "--controller", "hop", "--param", "kp=30:300", *args]) == 0
    assert (
        "legdsl: note: kp is declared in shared part 'kangaroo_hop': the tuned file changes it "
        "for every controller that includes 'kangaroo_hop'"
    ) in capsys.readouterr().err
    assert main(["tune", str(HOPPER), "--controller", "hop", "--param", "kp=30:300", *args]) == 0
    assert "note" not in capsys.readouterr().err


def test_the_tuned_file_elsewhere_still_finds_the_files_it_uses(tmp_path: Path) -> None:
    """A creature that uses a file of its own by a relative path, tuned into another folder:
    the tuned file's 'use' is pointed at the same file from there (it could not be found, and
    every name of the used file's shared parts was then unknown)."""
    (tmp_path / "mine" / "parts").mkdir(parents=True)
    (tmp_path / "mine" / "parts" / "extra.leg").write_text(
        "use raibert\naction settle_leg(leg) { relax(leg, 0 m) }\n"
    )
    source = tmp_path / "mine" / "hopper.leg"
    source.write_text(HOPPER.read_text() + '\nuse "parts/extra.leg"  # mine\n')
    hop = check_model(source).controller("hop")
    out = write_tuned(source, hop, {"kp": 212.5}, tmp_path / "tuned" / "hopper.leg")
    assert 'use "../mine/parts/extra.leg" # mine' in out.read_text()
    tuned = {p.name: p.value for p in check_model(out).controller("hop").params}
    assert tuned["kp"] == pytest.approx(212.5)


def test_the_elapsed_time_told_counts_the_start_runs(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """The progress line's elapsed seconds began after the file's own values were measured, so a
    slow start (one run per speed, as long as a generation's) was missing from it."""
    import time

    import legdsl.api.tune as tuning

    scored = []

    def slow_start(rows, objective):  # type: ignore[no-untyped-def]
        if not scored:
            time.sleep(3.0)
        scored.append(rows)
        return score(rows, objective)

    monkeypatch.setattr(tuning, "score", slow_start)
    code = main(["tune", str(HOPPER), "--controller", "hop", "--param", "k_speed=0.02:0.2",
                 "--speeds", "1", "--time", "0.3", "--from", "0.1", "--generations", "1",
                 "--popsize", "2", "--jobs", "1", "--out", str(tmp_path / "t"),
                 "--generated", str(tmp_path / "generated")])  # fmt: skip
    assert code == 0
    told = re.search(r"generation 1/1: .*\((\d+) s, about", capsys.readouterr().out)
    assert told is not None and int(told.group(1)) >= 3


def test_a_tuned_value_at_its_bound_is_said_to_be_there() -> None:
    """The knee quadruped's leg_k came out at 299.97 of --param leg_k=100:300 and the report
    showed it as any other value: a search held back by its bounds went unnoticed."""
    result = {
        "start": {"values": {"leg_k": 152.7, "kp": 436.3, "kv": 35.9}, "objective": 1.0,
                  "runs": []},
        "best": {"values": {"leg_k": 299.97, "kp": 400.0, "kv": 10.05}, "objective": 0.01,
                 "runs": []},
    }  # fmt: skip
    bounds = [Bound("leg_k", 100.0, 300.0, 152.7), Bound("kp", 200.0, 900.0, 436.3),
              Bound("kv", 10.0, 80.0, 35.9)]  # fmt: skip
    lines = report(result, {"leg_k": "N*m/rad"}, bounds).splitlines()
    assert lines[1].endswith("N*m/rad  (at its upper bound: widen it to search past it)")
    assert "bound" not in lines[2]
    assert lines[3].endswith("(at its lower bound: widen it to search past it)")


def test_a_gait_of_pairs_scores_its_pairs_landing_apart() -> None:
    """A tune with --table2 "quadruped trot" scored speed alone: tunes holding the speed with
    the diagonal feet landing apart (14% of steps within 10 ms) came out best."""
    objective = Objective(speeds=(1.0,), duration=10.0, start=3.0, table2="quadruped trot")
    row = {"outcome": "ok", "running_speed": 1.0, "simulated": 10.0}
    together = {**row, "by_label": {"unison_diagonal_a": 1.0, "unison_diagonal_b": 1.0}}
    apart = {**row, "by_label": {"unison_diagonal_a": 0.14, "unison_diagonal_b": 0.5}}
    assert score([apart], objective) - score([together], objective) == pytest.approx(0.68)
    assert pairs_apart({"speed": 1.0}, "quadruped trot") == 0.0  # no pairs measured: nothing


def test_a_pair_that_never_lands_together_lands_apart_and_the_biped_has_no_pairs() -> None:
    """A pair whose feet never touched together has no stance of both (its unison row n/a):
    it was left out, and scored as landing in unison. The biped's run measures one virtual leg
    of both feet, which take turns: its unison row was scored as a pair's."""
    never = {"unison_diagonal_a": math.nan, "unison_diagonal_b": 1.0}
    assert pairs_apart(never, "quadruped trot") == pytest.approx(0.5)
    assert pairs_apart({"unison_either": 0.0}, "biped run") == 0.0
    assert pairs_apart({"unison_either": math.nan}, "biped run") == 0.0
    assert pairs_apart({"unison_front": 0.5}, "kangaroo hop") == 0.0  # measured without pairs


def test_the_runs_of_a_gait_of_pairs_are_measured_on_its_pairs(generated: Path) -> None:
    import legdsl
    from legdsl.analysis.table2 import virtual_legs
    from legdsl.api.sweep import Job, _row

    source = ROOT / "creatures" / "quadruped.leg"
    pairs, first = virtual_legs("quadruped trot", check_model(source))
    groups = tuple(f"{n}={','.join(legs)}" for n, legs in pairs.items())
    assert groups[0].startswith(f"{first}=")
    job = Job(index=0, source=str(source), creature=None, controller="trot", values={},
              units={}, fixed=(), duration=3.0, start=1.0, generated=str(generated), keep=None,
              groups=groups)  # fmt: skip
    run = legdsl.load(source, generated=generated).run(controller="trot", time=3.0)
    unison = {k: v for k, v in _row(job, run)["by_label"].items() if k.startswith("unison_")}
    assert sorted(unison) == sorted(f"unison_{n}" for n in pairs) and all(
        0.9 <= v <= 1.0 for v in unison.values()
    )


def test_the_tuned_values_also_run_between_the_tuned_speeds_and_twice_as_long(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A tune fits the speeds it is given; the flat-footed biped tuned at 0, 1, 1.5, 2 and
    2.5 m/s fell at 1.75 without a word. Halfway between each two, the tuned values run once
    more (not scored), shown and kept in tune.json; and at each tuned speed for twice --time
    (a random hopper variant scored 0.999 m/s over 3-10 s ran 0.96 from 6 s on)."""
    code = main([
        "tune", str(HOPPER), "--controller", "hop", "--param", "k_speed=0.02:0.2",
        "--speeds", "0.5,1.5", "--time", "2", "--from", "0.8", "--generations", "1",
        "--popsize", "2", "--seed", "3", "--jobs", "1", "--out", str(tmp_path / "t"),
        "--generated", str(tmp_path / "generated"),
    ])  # fmt: skip
    assert code == 0
    (between,) = json.loads((tmp_path / "t" / "tune.json").read_text())["between"]
    assert between["speed"] == 1.0 and between["outcome"] == "ok"
    best = json.loads((tmp_path / "t" / "tune.json").read_text())["best"]["values"]
    assert between["k_speed"] == pytest.approx(best["k_speed"])
    done = json.loads((tmp_path / "t" / "tune.json").read_text())
    assert [r["speed"] for r in done["longer"]] == [0.5, 1.5]
    assert all(r["simulated"] == pytest.approx(4.0) for r in done["longer"])
    assert all(r["k_speed"] == pytest.approx(best["k_speed"]) for r in done["longer"])
    out = capsys.readouterr().out
    assert re.search(r"between the tuned speeds \(not scored\)\n  at 1 +\d", out), out
    assert "over 0.8 to 4 s, twice the tune's time (not scored)" in out
    assert "9 runs; wrote" in out  # the start 2, the generation 4, between 1, twice as long 2


def test_a_fall_between_the_tuned_speeds_is_said(capsys: pytest.CaptureFixture[str]) -> None:
    from legdsl.api.tune_cli import _say_between

    between = [{"speed": 1.75, "outcome": "fell at 0.714 s", "running_speed": float("nan")}]
    _say_between(between, tuned_fell=False)
    told = capsys.readouterr()
    assert "at 1.75      n/a (fell at 0.714 s) pitch n/a\n" in told.out  # no 'n/a deg'
    assert "did not last at 1.75 m/s, between the tuned speeds" in told.err


def test_tuned_values_that_fall_at_a_tuned_speed_are_said(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """A tune whose every candidate fell exited saying only that the runs between the speeds
    fell, and to add speeds there: no help where the tuned speeds fall too."""
    from legdsl.api.tune_cli import _say_between, _say_fell

    best = [{"speed": 0.5, "outcome": "fell at 1.142 s"}, {"speed": 1.0, "outcome": "ok"}]
    between = [{"speed": 0.75, "outcome": "fell at 1.074 s", "running_speed": float("nan")}]
    _say_between(between, _say_fell(best))
    err = capsys.readouterr().err
    assert "the tuned values do not last at 0.5 m/s (fell at 1.142 s), nor does the tuned" in err
    assert "add speeds there" not in err
    assert not _say_fell([{"speed": 1.0, "outcome": "ok"}])


def test_a_second_tune_into_the_same_out_is_refused_while_the_first_runs(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Two tunes given one --out both read and wrote its journal; the second is now told."""
    import fcntl

    out = tmp_path / "t"
    out.mkdir()
    with (out / ".tune.lock").open("w") as held:  # as the first tune holds it
        fcntl.flock(held, fcntl.LOCK_EX | fcntl.LOCK_NB)
        assert tune(out, tmp_path / "generated") == 2
    assert "another legdsl tune is writing" in capsys.readouterr().err
    assert not (out / "tune.json").exists()
