"""A mutation fuzzer over the shipped creatures' text, the command line's options, run
directories (issue 18, item 6) and the generated code a run loads.

Every case asserts: exit status 0 or 2 (3 or 4 for a run that diverges or falls, 130 never:
nothing is interrupted here), never 70 ("internal error") and never a traceback, and a run
that exits 0, 3 or 4 leaves a directory that reads back. The cases are drawn from a seeded
random generator, so a failure repeats; its message holds what to run to see it again.

The count is bounded for CI (``CI_CASES`` in all, a few tens of seconds); set
``LEGDSL_FUZZ=10000`` for a long run (run it niced and alone: it uses one core), and
``LEGDSL_FUZZ_SEED`` to draw other cases.
"""

from __future__ import annotations

import json
import os
import random
import re
import shutil
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
from runtime_helpers import legdsl_in_process

from legdsl.sim.trajectory import Trajectory, load_run_info

ROOT = Path(__file__).resolve().parents[2]
CREATURES = ("hopper", "kangaroo", "biped", "quadruped")
CI_CASES = 60
TOTAL = int(os.environ.get("LEGDSL_FUZZ", CI_CASES))
SEED = int(os.environ.get("LEGDSL_FUZZ_SEED", "18"))
# the share of each fuzzer: .leg text, command-line options, run directories, generated code
SHARES = {"leg": 0.47, "options": 0.3, "runfiles": 0.18, "generated": 0.05}
ALLOWED = {"leg": {0, 2}, "options": {0, 2, 3, 4}, "runfiles": {0, 2}, "generated": {0}}


def _count(kind: str) -> int:
    return max(1, round(TOTAL * SHARES[kind]))


def _assert_case(kind: str, code: int, err: str, what: str) -> None:
    assert "Traceback" not in err and "internal error" not in err, f"{what}\n{err}"
    assert code in ALLOWED[kind], f"{what}: exit {code}\n{err}"


# ------------------------------------------------------------------ .leg text
NUMBERS = ["nan", "inf", "-1", "0", "1e400", "1e-400", "-0", "1e9", "1e-9", "3.5.2", "1e", "99999999999999999999999"]  # fmt: skip
UNITS = ["kgg", "m/s/s", "deg^2", "N*m", "s^-1", "", "m^", "Hz", "rad/s", "kg*m^2", "mm", "%"]
JUNK = ["{", "}", "(", ")", ",", "=", "@", "\t", "é", "\x00", "#", "..", '"', "to", ";", "\\"]
_NUMBER = re.compile(r"(?<![A-Za-z_])\d+(?:\.\d+)?(?:[eE][-+]?\d+)?")
_WORD = re.compile(r"[A-Za-z_]\w*")
_UNIT = re.compile(r"(?<=\d )(?:kg|m|s|deg|rad|N|J|Hz)(?:[*/^][\w^]*)*")


def _mutate_leg(text: str, rng: random.Random) -> str | bytes:
    for _ in range(rng.randint(1, 3)):
        op = rng.randrange(12)
        lines = text.split("\n")
        if op == 0 and (nums := list(_NUMBER.finditer(text))):
            m = rng.choice(nums)
            text = text[: m.start()] + rng.choice(NUMBERS) + text[m.end() :]
        elif op == 1 and (units := list(_UNIT.finditer(text))):
            m = rng.choice(units)
            text = text[: m.start()] + rng.choice(UNITS) + text[m.end() :]
        elif op == 2 and (words := list(_WORD.finditer(text))):
            m, other = rng.choice(words), rng.choice(words)
            text = text[: m.start()] + other.group() + text[m.end() :]
        elif op == 3:
            del lines[rng.randrange(len(lines))]
            text = "\n".join(lines)
        elif op == 4:
            i = rng.randrange(len(lines))
            lines.insert(i, lines[rng.randrange(len(lines))])
            text = "\n".join(lines)
        elif op == 5:
            i, j = rng.randrange(len(lines)), rng.randrange(len(lines))
            lines[i], lines[j] = lines[j], lines[i]
            text = "\n".join(lines)
        elif op == 6:
            i = rng.randrange(len(text))
            text = text[:i] + text[i + rng.randint(1, 12) :]
        elif op == 7:
            i = rng.randrange(len(text))
            text = text[:i] + rng.choice(JUNK) + text[i:]
        elif op == 8:
            text = text[: rng.randrange(len(text))]
        elif op == 9 and (nums := list(_NUMBER.finditer(text))):
            m = rng.choice(nums)
            deep = rng.choice(["-" * rng.randint(50, 700), "(" * 300])
            closing = ")" * 300 if deep.startswith("(") else ""
            text = text[: m.start()] + deep + m.group() + closing + text[m.end() :]
        elif op == 10 and (nums := list(_NUMBER.finditer(text))):
            m = rng.choice(nums)
            text = (
                text[: m.start()] + " + ".join([m.group()] * rng.randint(2, 700)) + text[m.end() :]
            )
        elif op == 11:
            raw = text.encode()
            i = rng.randrange(len(raw))
            return raw[:i] + bytes([rng.choice([0xFF, 0xC3, 0x80, 0xFE])]) + raw[i:]
    return text


def test_fuzz_leg_text(tmp_path: Path) -> None:
    """Mutated shipped creatures: check (and show and export, when they check) never fail
    with an internal error."""
    texts = {c: (ROOT / "creatures" / f"{c}.leg").read_text() for c in CREATURES}
    for i in range(_count("leg")):
        rng = random.Random(f"{SEED}-leg-{i}")
        creature = rng.choice(CREATURES)
        mutated = _mutate_leg(texts[creature], rng)
        path = tmp_path / f"{creature}.leg"
        if isinstance(mutated, bytes):
            path.write_bytes(mutated)
        else:
            path.write_text(mutated, encoding="utf-8")
        keep = tmp_path / f"case-leg-{i}.leg"
        what = f"legdsl check {keep} (case {i}, seed {SEED}: LEGDSL_FUZZ_SEED={SEED})"
        code, err = legdsl_in_process(["check", str(path)])
        if code not in ALLOWED["leg"] or "internal error" in err or "Traceback" in err:
            shutil.copy(path, keep)
        _assert_case("leg", code, err, what)
        if code == 0 and rng.random() < 0.5:
            for argv in (["show", str(path)],
                         ["export", str(path), "--format", rng.choice(["mjcf", "urdf"]),
                          "-o", str(tmp_path / "out.xml")]):  # fmt: skip
                code, err = legdsl_in_process(argv)
                _assert_case("leg", code, err, f"legdsl {' '.join(argv)} (case {i})")


# ------------------------------------------------------------------ command-line options
VALUES: dict[str, list[str]] = {
    "--time": [
        "-1",
        "0",
        "nan",
        "inf",
        "1e400",
        "2kg",
        "0.05",
        "50ms",
        "0.04s",
        "abc",
        "",
        "1e-9",
        "=",
        "0.05 s",
    ],  # fmt: skip
    "--dt": ["0", "-1", "nan", "0.4ms", "0.001", "1s", "2e-4", "1m", "inf"],
    "--control-dt": ["0", "-2ms", "1e-9", "nan", "0.01", "1e400", "5ms"],
    "--record-rate": ["0", "-5", "nan", "100Hz", "1e9", "1s", "50"],
    "--drop": ["-1", "0.1", "1e400", "5cm", "1e6", "nan", "1kg", "0"],
    "--fall-height": ["-1", "5m", "0", "nan", "1e9", "2deg"],
    "--fall-tilt": ["nan", "0", "30deg", "1rad", "-5", "720", "1m"],
    "--integrator": ["euler", "rk4", "heun", ""],
    "--controller": ["hop", "run", "", "hop2"],
    "--creature": ["hopper", "nope"],
    "--set": [
        "speed=1m/s",
        "speed=1e400m/s",
        "leg_spring.k=-1N/m",
        "leg_spring.k=1e9N/m",
        "hip_servo.kp=1e9N*m/rad",
        "speed=nan",
        "=",
        "speed",
        "x=1",
        "speed=1m/s@-1s",
        "speed=2m/s@0.01s",
        "hip_servo.setpoint=1e300deg",
        "height=-5m",
        "k_speed=1e300s",
        "leg_spring.rest=2m",
        "hip_motor.force=1e6N",
        "speed=3kg",
    ],  # fmt: skip
    "--path": [
        "circle(center = (0, 5) m, radius = 5 m)",
        "polyline((0,0) m, (0,0) m)",
        "square(side = -1 m)",
        "garbage(",
        "/nonexistent.csv",
        "route=circle(",
    ],  # fmt: skip
}


def _check_run_dir(out: Path, what: str) -> None:
    info = load_run_info(out)
    trajectory = Trajectory.load(out)
    assert info["samples"] == len(trajectory), what
    assert info["status"] in ("ok", "fell", "diverged"), what


def test_fuzz_run_options(tmp_path: Path, generated: Path) -> None:
    """``legdsl run`` with random, often wrong, options: a user error or a readable run."""
    hopper = str(ROOT / "creatures" / "hopper.leg")
    a_file = tmp_path / "a_file"
    a_file.write_text("x")
    for i in range(_count("options")):
        rng = random.Random(f"{SEED}-options-{i}")
        out = tmp_path / f"run{i}"
        argv = ["run", hopper, "--generated", str(generated), "--time", "0.05"]
        for flag in rng.sample(sorted(VALUES), rng.randint(1, 3)):
            argv += [flag, rng.choice(VALUES[flag])]
        target = rng.choice([str(out)] * 6 + [str(a_file), str(a_file / "x"), "/proc/legdsl"])
        argv += ["--out", target]
        what = f"legdsl {' '.join(map(repr, argv))} (case {i})"
        code, err = legdsl_in_process(argv)
        _assert_case("options", code, err, what)
        if code in (0, 3, 4):
            _check_run_dir(Path(target), what)
        assert not [p for p in generated.iterdir() if p.name.startswith(".")], what


# ------------------------------------------------------------------ run directories
def _mutate_run(run: Path, rng: random.Random) -> str:
    npz, info = run / "trajectory.npz", run / "run.json"
    op = rng.randrange(8)
    if op == 0:
        data = npz.read_bytes()
        npz.write_bytes(data[: rng.randrange(len(data))])
        return "truncated trajectory.npz"
    if op == 1:
        data = bytearray(npz.read_bytes())
        for _ in range(rng.randint(1, 20)):
            data[rng.randrange(len(data))] = rng.randrange(256)
        npz.write_bytes(bytes(data))
        return "bytes of trajectory.npz changed"
    if op == 2:
        with np.load(npz) as d:
            arrays = {k: d[k] for k in d.files}
        name = rng.choice(sorted(arrays))
        how = rng.randrange(4)
        if how == 0:
            del arrays[name]
        elif how == 1:
            arrays[name] = arrays[name][: rng.randint(0, 3)]
        elif how == 2:
            arrays[name] = np.array(["text"] * 3)
        else:
            arrays[name] = np.full_like(arrays[name], np.nan, dtype=float)
        np.savez(npz, **arrays)  # type: ignore[arg-type]
        return f"array {name} changed ({how})"
    if op == 3:
        data = json.loads(info.read_text())
        key = rng.choice(sorted(data))
        data[key] = rng.choice([None, [], "x", 3, {"a": 1}, -1.5])
        info.write_text(json.dumps(data))
        return f"run.json's {key} replaced"
    if op == 4:
        text = info.read_text()
        info.write_text(text[: rng.randrange(len(text))])
        return "run.json truncated"
    if op == 5:
        info.write_text(rng.choice(["[]", "null", "3", '"x"', "{", "\x00\x01"]))
        return "run.json not an object"
    if op == 6:
        (npz if rng.random() < 0.5 else info).unlink()
        return "a file removed"
    with np.load(npz) as d:
        arrays = {k: d[k] for k in d.files}
    meta = json.loads(bytes(arrays["meta"]).decode())
    key = rng.choice(sorted(meta))
    meta[key] = rng.choice([None, [], "x", 3, ["a", "b"], {"a": 1}])
    arrays["meta"] = np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8)
    np.savez(npz, **arrays)  # type: ignore[arg-type]
    return f"meta {key} replaced"


@pytest.fixture(scope="module")
def a_run(tmp_path_factory: pytest.TempPathFactory, generated: Path) -> Path:
    out = tmp_path_factory.mktemp("fuzzrun") / "hopper"
    code, err = legdsl_in_process(["run", str(ROOT / "creatures" / "hopper.leg"), "--controller", "hop",
                       "--time", "1.2", "--generated", str(generated), "--out", str(out)])  # fmt: skip
    assert code == 0, err
    return out


def test_fuzz_run_directories(tmp_path: Path, a_run: Path, generated: Path) -> None:
    """metrics, animate and export-motion on damaged run directories: a user error or a result."""
    readers: list[Callable[[Path, random.Random], list[str]]] = [
        lambda run, rng: ["metrics", str(run), *rng.choice([[], ["--from", "0.5"], ["--to", "nan"],
                          ["--leg", "nope"], ["--joint", "hip", "--against", "leg"], ["--json"]])],
        lambda run, rng: ["animate", str(run), "--source", str(ROOT / "creatures" / "hopper.leg"),
                          "--generated", str(generated), "-o", str(tmp_path / "a.html")],
        lambda run, rng: ["export-motion", str(run), "--source",
                          str(ROOT / "creatures" / "hopper.leg"), "--generated", str(generated),
                          "-o", str(tmp_path / "m.glb")],
    ]  # fmt: skip
    for i in range(_count("runfiles")):
        rng = random.Random(f"{SEED}-runfiles-{i}")
        run = tmp_path / "run"
        shutil.rmtree(run, ignore_errors=True)
        shutil.copytree(a_run, run)
        change = _mutate_run(run, rng)
        argv = rng.choice(readers)(run, rng)
        what = f"legdsl {' '.join(argv)} after: {change} (case {i})"
        code, err = legdsl_in_process(argv)
        _assert_case("runfiles", code, err, what)


# ------------------------------------------------------------------ generated code
def _damage_generated(folder: Path, rng: random.Random) -> str:
    files = sorted(p for p in folder.iterdir() if p.is_file())
    path = rng.choice(files)
    data = path.read_bytes()
    op = rng.randrange(6)
    if op == 0:
        path.write_bytes(data[: rng.randrange(len(data))])
        return f"{path.name} cut short"
    if op == 1:
        changed = bytearray(data)
        for _ in range(rng.randint(1, 5)):
            changed[rng.randrange(len(changed))] = rng.randrange(256)
        path.write_bytes(bytes(changed))
        return f"bytes of {path.name} changed"
    if op == 2:
        path.write_bytes(data + rng.choice([b"\nx = (\n", b"\n}\n", b"\nimport nothing_here\n"]))
        return f"junk after {path.name}"
    if op == 3:
        path.unlink()
        return f"{path.name} removed"
    if op == 4:
        text = data.decode("utf-8", "replace")
        numbers = list(_NUMBER.finditer(text))
        if numbers:
            m = rng.choice(numbers)
            text = text[: m.start()] + rng.choice(NUMBERS) + text[m.end() :]
        path.write_text(text, encoding="utf-8")
        return f"a number in {path.name} edited"
    (folder / "SHA256SUMS").write_bytes(rng.choice([b"", b"\x00\xff", b"not a listing\n"]))
    return "SHA256SUMS damaged"


def test_fuzz_generated_code(tmp_path: Path) -> None:
    """A run over generated code that was cut short, edited or lost: whatever it reads is
    compiled again first (exit 0, never an internal error), so its trajectory is the one the
    intact code gives, byte for byte."""
    golden = ROOT / "generated" / "hopper"

    def run(generated: Path, backend: str, out: Path) -> tuple[int, str]:
        return legdsl_in_process(["run", str(ROOT / "creatures" / "hopper.leg"), "--controller", "hop",
                      "--time", "0.05", "--generated", str(generated), "--backend", backend,
                      "--out", str(out)])  # fmt: skip

    intact = {}
    for backend in ("python", "c"):
        shutil.copytree(golden, tmp_path / "intact" / "hopper", dirs_exist_ok=True)
        code, err = run(tmp_path / "intact", backend, tmp_path / f"intact-{backend}")
        assert code == 0, err
        intact[backend] = (tmp_path / f"intact-{backend}" / "trajectory.npz").read_bytes()
    for i in range(_count("generated")):
        rng = random.Random(f"{SEED}-generated-{i}")
        generated = tmp_path / f"generated{i}"
        shutil.copytree(golden, generated / "hopper")
        change = _damage_generated(generated / "hopper", rng)
        backend = rng.choice(["python", "c"])
        code, err = run(generated, backend, tmp_path / f"run{i}")
        what = f"legdsl run --backend {backend} after: {change} (case {i}, seed {SEED})"
        _assert_case("generated", code, err, what)
        assert (tmp_path / f"run{i}" / "trajectory.npz").read_bytes() == intact[backend], what
