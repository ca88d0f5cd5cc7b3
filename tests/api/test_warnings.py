"""The notes ``legdsl run`` prints about a run reach the API's callers as ``LegdslWarning``s
(a ``UserWarning``: shown once by default, filterable, an error under ``pytest -W error``),
with the command line's text, at the caller's line; a session with a log prints them there
instead, never both."""

from __future__ import annotations

import io
import warnings
from pathlib import Path

import pytest

import legdsl
from legdsl.api import Creature, LegdslWarning
from legdsl.cli import main
from legdsl.lang.errors import UsageError
from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions

ROOT = Path(__file__).resolve().parents[2]
HOPPER = ROOT / "creatures" / "hopper.leg"


def _warned(call: object) -> list[warnings.WarningMessage]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        call()  # type: ignore[operator]
    return [w for w in caught if issubclass(w.category, LegdslWarning)]


def _api_words(notes: list[str]) -> list[str]:
    """The CLI's notes as the API words them (docs/api.md: its arguments, not the flags)."""
    return [note.replace("give a longer --time", "give a longer time=") for note in notes]


def _cli_notes(capsys: pytest.CaptureFixture[str], args: list[str]) -> list[str]:
    capsys.readouterr()
    main(["run", *args])
    err = capsys.readouterr().err
    return [line.partition(": ")[2].partition(": ")[2] for line in err.splitlines()
            if line.startswith(("legdsl: note: ", "legdsl: warning: "))]  # fmt: skip


def test_a_switch_to_the_running_controller_and_a_late_change_are_warned_as_the_cli_notes(
    generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Before, the API said nothing of either (its session had no log)."""
    hopper = legdsl.load(HOPPER, generated=generated)
    capsys.readouterr()
    caught = _warned(lambda: hopper.run(controller="hop", time=0.5, switch={"0.2 s": "hop"},
                                        set={"speed@3s": "1 m/s"}))  # fmt: skip
    assert "legdsl: note" not in capsys.readouterr().err  # not printed as well
    assert all(Path(w.filename) == Path(__file__) for w in caught)  # the caller's line
    said = _cli_notes(capsys, [str(HOPPER), "--controller", "hop", "--time", "0.5", "--switch",
                               "0.2s=hop", "--set", "speed=1m/s@3s", "--generated",
                               str(generated), "--out", str(tmp_path / "run")])  # fmt: skip
    # in the API's words: set= and time=, not --set and --time (docs/api.md)
    said[1] = said[1].replace("--set speed=1m/s@3s", "set={'speed@3s': '1m/s'}")
    assert len(said) == 2 and [str(w.message) for w in caught] == _api_words(said)


def test_a_drop_outlasting_the_run_and_a_passive_run_are_warned(
    generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    hopper = legdsl.load(HOPPER, generated=generated)
    caught = [str(w.message) for w in _warned(lambda: hopper.run(time=0.2, drop=0.5))]
    said = _cli_notes(capsys, [str(HOPPER), "--time", "0.2", "--drop", "0.5", "--generated",
                               str(generated), "--out", str(tmp_path / "run")])  # fmt: skip
    assert said[0].startswith("--drop 0.5m: the fall alone takes 0.319 s") and "--time" in said[0]
    assert caught[0] == (  # in the API's words (it was told --drop and --time as well)
        "drop=0.5: the fall alone takes 0.319 s, longer than the run (0.2 s), which ends with "
        "the creature in the air; give time=0.319 or more, or a lower drop="
    )
    assert caught[1].startswith("controller: none, a passive run: choose one with controller=")
    assert _warned(lambda: hopper.run(controller="hop", time=0.2)) == []


def test_a_passive_run_asked_for_with_controller_none_is_not_warned_of(generated: Path) -> None:
    """Before, every deliberate passive drop warned that it was passive."""
    hopper = legdsl.load(HOPPER, generated=generated)
    assert _warned(lambda: hopper.run(controller=None, time=0.2, drop=0.05)) == []
    assert _warned(lambda: hopper.run_copies(2, controller=None, time=0.05)) == []
    many = _warned(lambda: list(hopper.run_many([{"controller": None, "time": 0.05},
                                                 {"time": 0.05}])))  # fmt: skip
    assert [str(w.message).split(":")[0] for w in many] == ["controller"]  # the second only


def test_a_stop_too_stiff_is_warned_and_an_error_under_W_error(
    generated: Path, tmp_path: Path
) -> None:
    limits = "    limits -0.25 m to 0.1 m\n"
    path = tmp_path / "hopper.leg"
    path.write_text(HOPPER.read_text().replace(limits, limits + "    stop k = 1e12 N/m\n"))
    stiff = legdsl.load(path, generated=generated)
    caught = _warned(lambda: stiff.run(controller="hop", time=0.1))
    assert len(caught) == 1 and "a run that reaches it diverges there" in str(caught[0].message)
    with warnings.catch_warnings():
        warnings.simplefilter("error", LegdslWarning)
        with pytest.raises(LegdslWarning, match="too stiff"):
            stiff.run(controller="hop", time=0.1)
    assert issubclass(LegdslWarning, UserWarning)


def test_run_many_warns_for_each_run(generated: Path) -> None:
    hopper = legdsl.load(HOPPER, generated=generated)
    runs = [{"controller": "hop", "time": 0.3, "set": {"speed@1s": "1 m/s"}}] * 2
    caught = _warned(lambda: list(hopper.run_many(runs, threads=1)))
    assert len(caught) == 2 and "comes after the run's end" in str(caught[0].message)


@pytest.mark.parametrize("many", [False, True])
def test_a_batch_refused_is_told_its_mistake_alone(generated: Path, many: bool) -> None:
    """run_copies() and run_many() warned of a change after the run's end, then refused the
    batch's unknown name: run() tells a refused run its mistake alone; run_many() checks
    every run before any runs (it ran the first, and told its notes)."""
    hopper = legdsl.load(HOPPER, generated=generated)
    late, wrong = {"speed@3s": "1 m/s"}, {"bogus": "1 m"}
    if many:
        runs = [{"controller": "hop", "time": 0.3, "set": late},
                {"controller": "hop", "time": 0.3, "set": {**late, **wrong}}]  # fmt: skip
        call = lambda: list(hopper.run_many(runs, threads=1))  # noqa: E731
    else:
        call = lambda: hopper.run_copies(2, controller="hop", time=0.3, set=late,  # noqa: E731
                                         vary={"bogus": ([1.0, 2.0], "m")})  # fmt: skip
    with warnings.catch_warnings(record=True) as caught, pytest.raises(UsageError, match="bogus"):
        warnings.simplefilter("always")
        call()
    told = [str(w.message) for w in caught if issubclass(w.category, LegdslWarning)]
    assert told == []


def test_a_session_with_a_log_prints_the_notes_there_and_does_not_warn(generated: Path) -> None:
    log = io.StringIO()
    creature = Creature(RunSession.from_file(HOPPER, None, generated, log))
    caught = _warned(lambda: creature.run(controller="hop", time=0.3, switch={"0.1 s": "hop"}))
    assert caught == [] and "legdsl: note: the switch to hop at 0.1 s" in log.getvalue()


@pytest.mark.parametrize("drop", [-1.0, float("nan")])
def test_a_wrong_drop_is_still_a_usage_error(generated: Path, drop: float) -> None:
    """The note of a fall outlasting the run took the root of a negative drop: a TypeError."""
    hopper = legdsl.load(HOPPER, generated=generated)
    with pytest.raises(UsageError, match=r"^run\(\): drop=(-1.0|nan): "):
        hopper.run(controller="hop", time=0.1, drop=drop)


def test_run_many_in_threads_warns_at_the_callers_line(generated: Path) -> None:
    """A note made in a batch's thread pointed at concurrent/futures/thread.py."""
    hopper = legdsl.load(HOPPER, generated=generated)
    runs = [{"controller": "hop", "time": 0.3, "switch": {"0.1 s": "hop"}}] * 2
    caught = _warned(lambda: list(hopper.run_many(runs, threads=2)))
    restarts = [w for w in caught if "restarts hop's state machine" in str(w.message)]
    assert len(restarts) == 2 and all(Path(w.filename) == Path(__file__) for w in caught)


def test_a_run_session_given_a_log_prints_the_cli_notes_there(
    generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """RunSession.run (docs/runtime.md) told none of the notes legdsl run prints: the CLI and
    the API told them each on their own, around the session."""
    log = io.StringIO()
    session = RunSession.from_file(HOPPER, None, generated, log)
    log.truncate(0)  # its compile notes, if any
    run = session.run("hop", ["speed=1m/s@3s", "hip_servo.kv=5N*m*s/rad"], [],
                      RunOptions(duration=0.3, drop=2.0), switches=["0.1s=hop"])  # fmt: skip
    said = _cli_notes(capsys, [str(HOPPER), "--controller", "hop", "--time", "0.3", "--drop",
                               "2m", "--set", "speed=1m/s@3s", "--set", "hip_servo.kv=5N*m*s/rad",
                               "--switch", "0.1s=hop", "--generated", str(generated),
                               "--out", str(tmp_path / "run")])  # fmt: skip
    printed = [line.partition(": ")[2].partition(": ")[2] for line in log.getvalue().splitlines()
               if line.startswith("legdsl: note: ")]  # fmt: skip
    # the fifth: the switch still waiting when the run ended, a note as the others are
    assert run.status == "ok" and len(said) == 5 and printed == said


def test_a_scene_line_after_the_runs_end_is_warned_of_by_its_line_as_the_cli_notes(
    generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The API named a scene's 'at 2 s set speed' as '--set speed=1.5m/s@2.0s', a --set the
    caller never gave; the CLI names the scene's line."""
    path = tmp_path / "hopper.leg"
    scene = "\nscene late {\n  controller hop\n  at 2 s set speed = 1.5 m/s\n  time 3 s\n}\n"
    path.write_text(HOPPER.read_text() + scene)
    hopper = legdsl.load(path, generated=generated)
    caught = [str(w.message) for w in _warned(lambda: hopper.run(scene="late", time=0.2))]
    many = _warned(lambda: list(hopper.run_many([{"scene": "late", "time": 0.2}], threads=1)))
    said = _cli_notes(capsys, [str(path), "--scene", "late", "--time", "0.2", "--generated",
                               str(generated), "--out", str(tmp_path / "run")])  # fmt: skip
    line = f"{path}:{len(HOPPER.read_text().splitlines()) + 4}:3: 'at 2 s set speed' of scene late"
    said = _api_words(said)
    assert caught == said == [str(w.message) for w in many] and said[0].startswith(line)


def test_a_scene_line_its_controller_overwrites_is_named_as_written_scaled_or_not(
    generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A scene's 'set hip_servo.kv', which hop sets itself, was noted as '--set
    hip_servo.kv=2.0kg*m^2/s/rad' (a --set never given, in SI base units, no line), and under
    --scale 4 its 'at 1 s set speed' as 'at 2 s set speed', the scaled time as the file's."""
    path = tmp_path / "hopper.leg"
    scene = ("\nscene go {\n  controller hop\n  set hip_servo.kv = 2 N*m*s/rad\n"
             "  at 1 s set speed = 1.5 m/s\n  time 3 s\n}\n")  # fmt: skip
    path.write_text(HOPPER.read_text() + scene)
    end = len(HOPPER.read_text().splitlines())
    kv = f"{path}:{end + 4}:3: 'set hip_servo.kv' of scene go: controller 'hop' sets hip_servo.kv"
    speed = f"{path}:{end + 5}:3: 'at 1 s set speed' of scene go"
    hopper = legdsl.load(path, generated=generated)
    caught = [str(w.message) for w in _warned(lambda: hopper.run(scene="go", time=0.2))]
    argv = [str(path), "--scene", "go", "--time", "0.2", "--generated", str(generated)]
    said = _cli_notes(capsys, [*argv, "--out", str(tmp_path / "run")])
    assert caught == _api_words(said) and said[0].startswith(speed + " comes after")
    assert said[1].startswith(kv) and "--set" not in said[1]
    scaled = _cli_notes(capsys, [*argv, "--scale", "4", "--out", str(tmp_path / "run4")])
    assert scaled[0].startswith(f"{speed}, at 2 s once scaled, comes after the run's end")
    assert scaled[1].startswith(kv)


def test_a_player_whose_stances_get_few_keyframes_is_warned_of(
    generated: Path, tmp_path: Path
) -> None:
    """Run.animate() wrote the player legdsl animate notes, silently (the note was made and
    dropped)."""
    hopper = legdsl.load(HOPPER, generated=generated)
    run = hopper.run(controller="hop", time=3, record_rate=8)
    caught = _warned(lambda: run.animate(tmp_path / "a.html"))
    assert [str(w.message).split(" (")[0] for w in caught] == ["leg main's stances"]
    assert all(Path(w.filename) == Path(__file__) for w in caught)
