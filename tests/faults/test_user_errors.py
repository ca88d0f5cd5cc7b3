"""Mistakes on the command line and in run directories are user errors (issue 18, item 1):
exit status 2, one line saying what was wrong and what to do, never "internal error" (70),
and checked before any work starts where that can be."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from legdsl.cli import main

ROOT = Path(__file__).resolve().parents[2]
HOPPER = str(ROOT / "creatures" / "hopper.leg")


def _run(capsys: pytest.CaptureFixture[str], argv: list[str]) -> tuple[int, str]:
    code = main(argv)
    err = capsys.readouterr().err
    assert "internal error" not in err and "Traceback" not in err, err
    return code, err


RUN_MISTAKES = [
    (["--time", "-1"], "--time -1: --time must be more than zero"),
    (["--time", "nan"], "'nan' is not a number"),
    (["--time", "inf"], "'inf' is not a number"),
    (["--time", "0"], "must be more than zero"),
    (["--time", "1e400"], "too large"),
    (["--time", "1km^200"], "too large"),  # the unit's factor overflows, not the number
    (["--time", "1e-400"], "1e-400 is too small to be a number"),
    (["--drop", "1g^200/kg^200"], "too small"),
    (["--time", "2kg"], "--time is a time (s), but 2kg is a mass (kg); write e.g. --time 2s"),
    (["--dt", "0"], "--dt must be more than zero"),
    (["--dt", "-1"], "--dt must be more than zero"),
    (["--dt", "2s", "--time", "1s"], "longer than the run"),
    (["--control-dt", "0"], "--control-dt must be more than zero"),
    (["--dt", "0.4ms", "--control-dt", "0.1ms"], "shorter than the integration step"),
    (["--record-rate", "nan"], "not a number"),
    (["--record-rate", "-5"], "--record-rate must not be negative"),
    # one sample, the start: the summary said its end energy was its start's
    (["--record-rate", "1Hz", "--time", "0.5s"], "records only the start of a 0.5s run"),
    (["--fall-tilt", "nan"], "not a number"),
    (["--fall-tilt", "0deg"], "more than zero"),
    (["--fall-height=-1m"], "must not be negative"),
    (["--drop", "-1"], "--drop must not be negative"),
    (["--drop", "3s"], "--drop is a length (m)"),
    (
        ["--set", "leg_spring.k=-3000N/m"],
        "'k' must not be negative (as in the .leg file); give 0 or more",
    ),
    (["--controller", "hop", "--set", "speed=1e400m/s"], "too large"),
    (["--controller", "hop", "--set", "speed=1e-400m/s"], "too small"),
    (["--controller", "hop", "--set", "speed=1m/s@1e400s"], "too large"),
]


@pytest.mark.parametrize(
    ("extra", "message"), RUN_MISTAKES, ids=[" ".join(e) for e, _ in RUN_MISTAKES]
)
def test_a_bad_run_option_is_a_user_error(
    capsys: pytest.CaptureFixture[str],
    generated: Path,
    tmp_path: Path,
    extra: list[str],
    message: str,
) -> None:
    out = tmp_path / "run"
    argv = ["run", HOPPER, "--generated", str(generated), "--out", str(out), *extra]
    code, err = _run(capsys, argv)
    assert code == 2, err
    assert message in err
    assert not out.exists()  # refused before anything was simulated or written


def test_numeric_options_take_units(
    capsys: pytest.CaptureFixture[str], generated: Path, tmp_path: Path
) -> None:
    out = tmp_path / "run"
    argv = ["run", HOPPER, "--generated", str(generated), "--out", str(out), "--time", "50ms",
            "--dt", "0.4ms", "--control-dt", "2ms", "--record-rate", "1000Hz",
            "--fall-tilt", "30deg", "--drop", "2cm"]  # fmt: skip
    code, _ = _run(capsys, argv)
    assert code == 0
    options = json.loads((out / "run.json").read_text())["options"]
    assert options["duration"] == pytest.approx(0.05)
    assert options["dt"] == pytest.approx(0.0004)
    assert options["record_rate"] == pytest.approx(1000)
    assert options["fall_tilt"] == pytest.approx(np.radians(30))
    assert options["drop"] == pytest.approx(0.02)


@pytest.mark.parametrize("where", ["file", "under a file", "unwritable"])
@pytest.mark.parametrize("command", ["run", "compile", "export"])
def test_an_output_that_cannot_be_written_is_a_user_error(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, generated: Path, where: str, command: str
) -> None:
    a_file = tmp_path / "a_file"
    a_file.write_text("x")
    # /proc refuses new files even to root, for whom a mode of 0o500 means nothing
    target = {"file": a_file, "under a file": a_file / "x", "unwritable": Path("/proc/legdsl")}
    out = str(target[where])
    argv = {
        "run": ["run", HOPPER, "--generated", str(generated), "--out", out],
        "compile": ["compile", HOPPER, "--out", out],
        "export": ["export", HOPPER, "--format", "mjcf", "-o", out],
    }[command]
    if command == "export" and where == "file":
        argv[-1] = str(tmp_path)  # a directory where a file is meant
    code, err = _run(capsys, argv)
    assert code == 2
    assert any(w in err for w in ("is a file", "is a directory", "cannot write")), err
    assert a_file.read_text() == "x"


# ------------------------------------------------------------------ run files
@pytest.fixture(scope="module")
def a_run(tmp_path_factory: pytest.TempPathFactory, generated: Path) -> Path:
    out = tmp_path_factory.mktemp("run") / "hopper"
    assert main(["run", HOPPER, "--time", "0.3", "--generated", str(generated),
                 "--out", str(out)]) == 0  # fmt: skip
    return out


def _damage(run: Path, how: str) -> None:
    npz, info = run / "trajectory.npz", run / "run.json"
    if how == "truncated npz":
        npz.write_bytes(npz.read_bytes()[:2000])
    elif how == "empty npz":
        npz.write_bytes(b"")
    elif how == "npz without q":
        with np.load(npz) as data:
            arrays = {k: data[k] for k in data.files if k != "q"}
        np.savez(npz, **arrays)  # type: ignore[arg-type]
    elif how == "npz with bad meta":
        with np.load(npz) as data:
            arrays = {k: data[k] for k in data.files}
        arrays["meta"] = np.frombuffer(b"{not json", dtype=np.uint8)
        np.savez(npz, **arrays)  # type: ignore[arg-type]
    elif how == "npz with a short q":
        with np.load(npz) as data:
            arrays = {k: data[k] for k in data.files}
        arrays["q"] = arrays["q"][:3]
        np.savez(npz, **arrays)  # type: ignore[arg-type]
    elif how in ("npz without samples", "npz with complex q", "npz with text states",
                 "npz with q too large"):  # fmt: skip
        with np.load(npz) as data:
            arrays = {k: data[k] for k in data.files}
        if how == "npz without samples":
            arrays = {k: v if k == "meta" else v[:0] for k, v in arrays.items()}
        elif how == "npz with complex q":
            arrays["q"] = arrays["q"].astype(complex)
        elif how == "npz with text states":
            arrays["state"] = arrays["state"].astype(str)
        else:  # finite, but past what the exports can write as float32
            arrays["q"] = arrays["q"] * 1e200
        np.savez(npz, **arrays)  # type: ignore[arg-type]
    elif how == "run.json with a damaged path":
        data = json.loads(info.read_text())
        data["paths"] = [{"shape": "circle", "points": "x"}]
        info.write_text(json.dumps(data))
    elif how == "run.json nested too deeply":
        info.write_text("[" * 100_000 + "]" * 100_000)
    elif how == "run.json not JSON":
        info.write_text("{ this is not json")
    elif how == "run.json a list":
        info.write_text("[1, 2, 3]")
    elif how == "run.json not UTF-8":
        info.write_bytes(b"\xff\xfe\x00garbage")
    elif how == "run.json with a bad source":
        info.write_text(json.dumps({"source": 3, "creature": "hopper"}))
    elif how == "no run.json":
        info.unlink()
    elif how == "no trajectory":
        npz.unlink()
    elif how == "empty directory":
        npz.unlink()
        info.unlink()


DAMAGES = [
    "truncated npz", "empty npz", "npz without q", "npz with bad meta", "npz with a short q",
    "run.json not JSON", "run.json a list", "run.json not UTF-8", "run.json with a bad source",
    "no run.json", "no trajectory", "empty directory", "npz without samples",
    "npz with complex q", "npz with text states", "npz with q too large",
    "run.json with a damaged path", "run.json nested too deeply",
]  # fmt: skip
READERS = ["metrics", "plot", "animate", "export-motion"]


@pytest.mark.parametrize("command", READERS)
@pytest.mark.parametrize("how", DAMAGES)
def test_a_damaged_run_directory_is_a_user_error(
    capsys: pytest.CaptureFixture[str], a_run: Path, tmp_path: Path, how: str, command: str
) -> None:
    run = tmp_path / "run"
    shutil.copytree(a_run, run)
    _damage(run, how)
    argv = [command, str(run)]
    if command in ("animate", "export-motion"):
        argv += ["--source", HOPPER]
    if command == "export-motion":
        argv += ["-o", str(tmp_path / "m.glb")]
    code, err = _run(capsys, argv)
    if command == "metrics" and how.startswith("run.json") or how == "no run.json":
        # metrics and plot need only the trajectory; what they do read must still be sound
        assert code in (0, 2), err
    else:
        assert code == 2, err
    if code == 2:
        assert "run" in err  # says what to do: run the creature again, or give a run directory


@pytest.mark.parametrize(("extra", "message"), [
    (["--from", "nan"], "not a number"),
    (["--from", "-1"], "must not be negative"),
    (["--from", "2", "--to", "1"], "must come after"),
    (["--to", "1kg"], "is a time"),
])  # fmt: skip
@pytest.mark.parametrize("command", ["metrics", "plot"])
def test_a_bad_window_is_a_user_error(
    capsys: pytest.CaptureFixture[str], a_run: Path, command: str, extra: list[str], message: str
) -> None:
    code, err = _run(capsys, [command, str(a_run), *extra])
    assert code == 2 and message in err, err


# ------------------------------------------------------------------ .leg mistakes found late
def test_a_foot_under_the_ground_is_a_user_error(
    capsys: pytest.CaptureFixture[str], generated: Path, tmp_path: Path
) -> None:
    """The ground spring would launch the body 2.5 m into the air: refused, with what to do
    (the depth is known only from the kinematics, so after loading, before simulating)."""
    leg = tmp_path / "hopper.leg"
    text = (ROOT / "creatures" / "hopper.leg").read_text()
    leg.write_text(text.replace("z = 0.95 m", "z = 0.5 m"))
    out = tmp_path / "run"
    argv = ["run", str(leg), "--generated", str(generated), "--out", str(out)]
    code, err = _run(capsys, argv)
    assert code == 2
    line = text[: text.index("z = 0.95 m")].count("\n") + 1
    # at the root's 'initial', the line to change, with its caret (it named the file alone)
    assert (
        f"hopper.leg:{line}:5: error: contact 'toe' of creature 'hopper' starts 0.3 m under the ground"
        in err
    )
    assert "\n        initial x = 0 m, z = 0.5 m, pitch = 0 deg\n        ^~~~~~~\n" in err
    assert "--drop" in err and not out.exists()
    code, _ = _run(capsys, [*argv, "--drop", "0.1", "--time", "0.05"])  # lifted: fine
    assert code == 0


RIG = """\
creature rig {
  planar
  body frame fixed at (0 m, 0.4 m) { mass 5 kg  inertia 0.1 kg*m^2 }
  body shin on frame via prismatic knee { length 0.45 m  mass 1 kg  inertia 0.01 kg*m^2 }
  contact paw on shin at tip
  actuator kn on knee spring(k = 3000 N/m)
  ground { normal spring(k = 1e4 N/m)  tangent spring(k = 1e4 N/m) }
}
"""


def test_a_root_welded_to_the_world_cannot_be_dropped(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """A fixed root has no z to lift: --drop is a user error (it was an internal one), and a
    foot under the ground says to move the point after 'fixed at', not to use --drop."""
    leg = tmp_path / "rig.leg"
    leg.write_text(RIG)
    argv = ["run", str(leg), "--generated", str(tmp_path / "gen"), "--out", str(tmp_path / "r")]
    code, err = _run(capsys, [*argv, "--time", "0.05", "--drop", "0.1"])
    assert code == 2
    assert "--drop lifts a free root, but creature 'rig' is welded to the world" in err
    lifted = [*argv[:-1], str(tmp_path / "lifted"), "--time", "0.05", "--fall-height", "1"]
    leg.write_text(RIG.replace("0.4 m)", "0.5 m)"))
    code, err = _run(capsys, lifted)
    assert code == 0, err  # a welded root never falls (runtime.md): it 'fell' at t = 0, exit 4
    assert "note: --fall-height is left out: creature 'rig' is welded to the world" in err
    leg.write_text(RIG)
    code, err = _run(capsys, argv)
    assert code == 2
    assert (
        "rig.leg:3:14: error: contact 'paw' of creature 'rig' starts 0.05 m under the ground" in err
    )
    assert "raise the point after 'fixed at' of its root body 'frame'" in err
    assert "--drop" not in err
    leg.write_text(RIG.replace("0.4 m)", "0.5 m)"))
    code, err = _run(capsys, [*argv, "--time", "0.05"])
    assert code == 0, err


def test_deep_nesting_that_is_accepted_compiles_and_runs(
    capsys: pytest.CaptureFixture[str], generated: Path, tmp_path: Path
) -> None:
    """Just under the parser's nesting limit, every later stage copes (no recursion limit)."""
    from legdsl.lang.parser import MAX_NESTING

    text = (ROOT / "creatures" / "hopper.leg").read_text()
    deep = " + ".join(["0 m"] * (MAX_NESTING - 12))
    leg = tmp_path / "hopper.leg"
    leg.write_text(text.replace("relax(active, 0 m);", f"relax(active, {deep});", 1))
    argv = ["run", str(leg), "--controller", "hop", "--generated", str(generated),
            "--time", "0.05", "--out", str(tmp_path / "run")]  # fmt: skip
    code, err = _run(capsys, argv)
    assert code == 0, err


@pytest.mark.parametrize("where", ["a directory", "under a file", "unwritable"])
@pytest.mark.parametrize("command", ["animate", "animate --video", "export-motion", "plot"])
def test_a_reader_output_that_cannot_be_written_is_a_user_error(
    capsys: pytest.CaptureFixture[str], a_run: Path, tmp_path: Path, where: str, command: str
) -> None:
    a_file = tmp_path / "a_file"
    a_file.write_text("x")
    suffix = {"animate": ".html", "animate --video": ".gif", "export-motion": ".glb"}
    name = "out" + suffix.get(command, ".png")
    target = {"a directory": tmp_path, "under a file": a_file / name,
              "unwritable": Path("/proc") / name}[where]  # fmt: skip
    words = command.split()
    flag = "--video" if "--video" in words else "-o"
    argv = [words[0], str(a_run), flag, str(target)]
    if words[0] != "plot":
        argv += ["--source", HOPPER]
    code, err = _run(capsys, argv)
    assert code == 2, err
    assert str(target) in err


def test_a_creature_without_contacts_cannot_be_dropped(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """--drop places the lowest contact: without contacts it was ignored without a word."""
    leg = tmp_path / "ball.leg"
    leg.write_text(
        "creature ball {\n  planar\n  body b free { mass 1 kg  inertia 0.01 kg*m^2 "
        " initial x = 0 m, z = 1 m, pitch = 0 deg }\n}\n"
    )
    argv = ["run", str(leg), "--generated", str(tmp_path / "gen"), "--out", str(tmp_path / "r")]
    code, err = _run(capsys, [*argv, "--time", "0.05", "--drop", "0.1", "--backend", "python"])
    assert code == 2
    assert "creature 'ball' has no contacts: to start it higher" in err


@pytest.mark.parametrize("command", READERS)
def test_a_divergences_last_sample_past_float32_is_measured_not_exported(
    capsys: pytest.CaptureFixture[str], a_run: Path, tmp_path: Path, command: str
) -> None:
    """A random rig (seed 850000 of the random metrics) diverged between two checks to q of
    9e40: legdsl wrote it and every reader refused it as damaged ('holds values too large').
    Metrics and plots read it; an animation, whose numbers are 32-bit, says what to run."""
    run = tmp_path / "run"
    shutil.copytree(a_run, run)
    npz = run / "trajectory.npz"
    with np.load(npz) as data:
        arrays = {k: data[k] for k in data.files}
    arrays["q"][-1] = arrays["q"][-1] * 1e40 + 1e40  # the last sample, as a blow-up leaves it
    np.savez(npz, **arrays)  # type: ignore[arg-type]
    argv = [command, str(run)]
    if command in ("animate", "export-motion"):
        argv += ["--source", HOPPER, *(["-o", str(tmp_path / "m.glb")] * (command != "animate"))]
    code, err = _run(capsys, argv)
    if command in ("metrics", "plot"):
        assert code == 0 and "Warning" not in err, err
    else:
        assert code == 2 and "past what an animation's 32-bit numbers hold" in err, err
        assert "run it again with a --time before" in err


def test_a_fall_height_above_the_start_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """'--fall-height 5m' on a hopper starting at 0.95 m ran 0 steps and ended 'fell' (exit 4),
    where a negative one is refused; with --drop the start is the lifted one."""
    argv = ["run", str(ROOT / "creatures" / "hopper.leg"), "--time", "0.1",
            "--generated", str(tmp_path / "generated"), "--out", str(tmp_path / "r")]  # fmt: skip
    assert main([*argv, "--fall-height", "5m"]) == 2
    err = capsys.readouterr().err
    assert "--fall-height 5m: the root starts 0.95 m above the ground" in err, err
    assert "give a --fall-height below 0.95m" in err
    assert not (tmp_path / "r").exists()
    assert main([*argv, "--fall-height", "1.5m", "--drop", "1m"]) == 0
