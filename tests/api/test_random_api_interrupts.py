"""Ctrl-C landing inside the public Python API at a drawn moment, as in a Jupyter notebook.

Each draw runs, in its own process (``python -c``, its own ``LEGDSL_CACHE`` and a scratch
``generated/``: a copy of the shipped one, or empty so that the call compiles), one call of
docs/api.md: ``legdsl.load``, ``creature.run`` (C or Python backend, ``LEGDSL_BACKEND``),
``run_many``, ``run_copies``, ``run.metrics``, ``run.save``, ``legdsl.open_run``, and the
sweep's and tune's entry points (``legdsl.api.sweep.run_sweep``, ``legdsl.api.tune.tune``)
with tiny budgets. A thread of that process sends it SIGINT after a drawn delay: once, twice,
or held down (every 0.2 ms for 50 ms). The process catches the KeyboardInterrupt around the
call, as a notebook does (or receives the documented interrupted result: a run that says
``interrupted``, its samples the start of the undisturbed run's; a tune whose ``ended`` says
so), then makes the same call again, undisturbed, in the same process.

Checked: the repeated call gives what a fresh undisturbed process gives (byte-identical
samples, files, table rows, tune result); stderr shows no traceback and no "Exception
ignored"; no child process is left once the call is over; ``run.save``'s and the sweep's
outputs hold no half-written file; and the next process loading the creature recompiles
nothing in ``generated/``, rebuilds nothing in the C cache and runs as the undisturbed one.

``LEGDSL_RANDOM_API_INTERRUPTS=N`` checks N draws (default ``CI_DRAWS``) from seed
``LEGDSL_RANDOM_API_INTERRUPT_SEED``, +1, ...; a failure names its seed and how to repeat it.
"""

from __future__ import annotations

import functools
import json
import os
import shutil
import subprocess
import sys
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
import pytest
from runtime_helpers import needs_c_compiler
from seeded import told_with_seed

ROOT = Path(__file__).resolve().parents[2]
CI_DRAWS = 1
COUNT = int(os.environ.get("LEGDSL_RANDOM_API_INTERRUPTS", CI_DRAWS))
FIRST_SEED = int(os.environ.get("LEGDSL_RANDOM_API_INTERRUPT_SEED", "0"))
CREATURES = {"hopper": "hop", "kangaroo": "hop", "biped": "run"}
CALLS = ("load", "run", "run_many", "run_copies", "metrics", "save", "open_run", "sweep", "tune")
# CI keeps to calls of a second or two; a hunt draws every one
CI_CALLS = ("run", "run_copies", "metrics", "save", "open_run", "load")

# The process of one draw: the call, the Ctrl-C, the repeat; what it saw as JSON on stdout.
SCRIPT = r'''
import hashlib, json, os, signal, sys, threading, time
spec = json.loads(sys.argv[1])
import numpy as np
import legdsl

SOURCE, CONTROLLER, GEN = spec["source"], spec["controller"], spec["generated"]
SCRATCH = spec["scratch"]

def digest_arrays(arrays):
    h = hashlib.sha256()
    for name in sorted(arrays):
        a = np.ascontiguousarray(arrays[name])
        h.update(f"{name}|{a.dtype}|{a.shape}|".encode())
        h.update(a.tobytes())
    return h.hexdigest()

def digest_run(run):
    return f"{run.status}:{digest_arrays(run.samples)}"

def files_of(directory):
    out = {}
    for name in sorted(os.listdir(directory)):
        path = os.path.join(directory, name)
        if os.path.isfile(path):
            with open(path, "rb") as f:
                data = f.read()
            if name == "run.json":  # its own directory's path, and the wall time
                info = json.loads(data)
                for key in ("wall_time", "directory", "created", "written"):
                    info.pop(key, None)
                data = json.dumps(info, sort_keys=True).encode()
            out[name] = hashlib.sha256(data).hexdigest()
        else:
            out[name] = "dir"
    return out

def creature():
    return legdsl.load(SOURCE, generated=GEN)

def a_run(c, time_=None):
    return c.run(controller=CONTROLLER, set={"speed": spec["speed"]}, time=time_ or spec["time"])

kind, attempt = spec["call"], {"n": 0}
prepared = {}

def prepare():
    """What the call needs done before it, undisturbed."""
    if kind in ("run", "run_many", "run_copies", "metrics", "save", "sweep", "tune"):
        prepared["creature"] = creature()
    if kind in ("metrics", "save"):
        prepared["run"] = a_run(prepared["creature"])
    if kind == "open_run":
        run = a_run(creature())
        prepared["saved"] = str(run.save(os.path.join(SCRATCH, "saved")))
        prepared["generated"] = os.path.join(SCRATCH, "generated-open")

def call():
    attempt["n"] += 1
    if kind == "load":
        c = creature()
        return repr(c) + " " + digest_run(a_run(c, 0.3))
    c = prepared.get("creature")
    if kind == "run":
        return digest_run(a_run(c))
    if kind == "run_many":
        asked = [{"controller": CONTROLLER, "set": {"speed": v}, "time": spec["time"]}
                 for v in spec["speeds"]]
        return {str(i): digest_run(r) for i, r in c.run_many(asked, threads=spec["threads"])}
    if kind == "run_copies":
        speeds = np.array([float(v.split()[0]) for v in spec["speeds"]])
        copies = c.run_copies(len(speeds), CONTROLLER, vary={"speed": (speeds, "m/s")},
                              time=spec["time"], threads=spec["threads"])
        return [digest_run(copies[k]) for k in range(len(copies))]
    if kind == "metrics":
        m = prepared["run"].metrics(start=spec["time"] / 3)
        return [[s.key, repr(s.value), repr(getattr(s, "std", None))] for s in m.summaries]
    if kind == "save":
        out = os.path.join(SCRATCH, "out")
        prepared["run"].save(out)
        return files_of(out)
    if kind == "open_run":
        run = legdsl.open_run(prepared["saved"], generated=prepared["generated"])
        return digest_run(run)
    if kind == "sweep":
        from legdsl.api.sweep import Job, run_sweep
        from pathlib import Path
        jobs = [Job(index=i, source=SOURCE, creature=None, controller=CONTROLLER,
                    values={"speed": float(v.split()[0])}, units={"speed": "m/s"}, fixed=(),
                    duration=spec["time"], start=spec["time"] / 3, generated=GEN, keep=None)
                for i, v in enumerate(spec["speeds"])]
        table = Path(SCRATCH) / "sweep" / "sweep.csv"
        table.parent.mkdir(exist_ok=True)
        run_sweep(jobs, table, spec["threads"])
        return sorted(table.read_text().splitlines())
    if kind == "tune":
        from legdsl.api.sweep import Job
        from legdsl.api.tune import Bound, Objective, tune
        base = Job(index=0, source=SOURCE, creature=None, controller=CONTROLLER, values={},
                   units={"k_speed": "s"}, fixed=(), duration=spec["time"], start=spec["time"] / 3,
                   generated=GEN, keep=None)
        said = []  # CMA-ES's seed is not the draw's: the undisturbed reference is one for all
        result = tune(base, [Bound("k_speed", 0.02, 0.2, 0.06)],
                      Objective(speeds=(float(spec["speed"].split()[0]),), duration=spec["time"],
                                start=spec["time"] / 3),
                      generations=1, popsize=2, seed=3, workers=spec["threads"],
                      say=said.append)
        if result["ended"] != "finished":
            return "ended " + result["ended"]
        return json.dumps(result, sort_keys=True, default=repr)
    raise AssertionError(kind)

def children():
    me, found = str(os.getpid()), []
    for pid in os.listdir("/proc"):
        if pid.isdigit():
            try:
                with open(f"/proc/{pid}/stat") as f:
                    name, _, rest = f.read().partition(" (")[2].rpartition(")")
                    fields = rest.split()
            except OSError:
                continue
            if fields[1] == me and fields[0] != "X":
                try:
                    with open(f"/proc/{pid}/cmdline", "rb") as f:
                        command = f.read().replace(b"\0", b" ").decode()[:80]
                except OSError:
                    command = ""
                if "multiprocessing.resource_tracker" not in command:  # Python's, for good
                    found.append(f"{pid} {fields[0]} ({name}) {command}")  # a zombie: its name
    return found

sent = threading.Event()

def send(pulses, delay, gap):
    time.sleep(delay)
    for k in range(pulses):
        if k:
            time.sleep(gap if pulses == 2 else 0.0002)
        os.kill(os.getpid(), signal.SIGINT)
    sent.set()

prepare()
report = {"first": None, "late_interrupts": 0}
if spec["mode"] == "none":
    report["first"] = call()
else:
    n = {"once": 1, "twice": 2, "held": 250}[spec["mode"]]
    sender = threading.Thread(target=send, args=(n, spec["delay"], spec["gap"]),
                              daemon=True)
    outcome = None
    while True:  # a notebook: each Ctrl-C ends the cell it lands in, the prompt takes the rest
        try:
            try:
                if outcome is None:
                    sender.start()
                    outcome = ("done", call())
            except KeyboardInterrupt:
                outcome = ("KeyboardInterrupt", None)
            while not sent.is_set():  # (a join cut short by Ctrl-C may return early)
                time.sleep(0.01)
            sender.join()
            time.sleep(float(os.environ.get("SETTLE", "0.05")))  # the last ones handled
            break
        except KeyboardInterrupt:
            report["late_interrupts"] += 1
            if outcome is None:
                outcome = ("KeyboardInterrupt", None)
    report["first"] = outcome[1] if outcome[0] == "done" else outcome[0]
for _ in range(100):  # the processes a call started end with it
    report["children"] = children()
    if not report["children"]:
        break
    time.sleep(0.02)
if kind == "save":
    out = os.path.join(SCRATCH, "out")
    report["saved_after_interrupt"] = files_of(out) if os.path.isdir(out) else {}
    report["listing_after_interrupt"] = sorted(os.listdir(out)) if os.path.isdir(out) else []
    if os.path.isfile(os.path.join(out, "run.json")):  # whole JSON, "incomplete" while written
        with open(os.path.join(out, "run.json")) as f:
            report["run_json_status"] = json.load(f)["status"]
if kind == "sweep":
    table = os.path.join(SCRATCH, "sweep", "sweep.csv")
    report["table_after_interrupt"] = (
        open(table).read().splitlines() if os.path.exists(table) else [])
    report["sweep_listing"] = (
        sorted(os.listdir(os.path.dirname(table))) if os.path.isdir(os.path.dirname(table)) else [])
report["again"] = call()
report["children_after_again"] = children()
if spec["mode"] == "none":  # the reference of the next process's check, here
    report["check"] = digest_run(creature().run(controller=CONTROLLER, set={"speed": spec["speed"]}, time=0.3))
print(json.dumps(report))
'''

# The next process: loads the creature from the same generated/ and cache, and runs briefly.
CHECK = r"""
import json, sys
spec = json.loads(sys.argv[1])
import hashlib, numpy as np, legdsl
c = legdsl.load(spec["source"], generated=spec["generated"])
run = c.run(controller=spec["controller"], set={"speed": spec["speed"]}, time=0.3)
h = hashlib.sha256()
for name in sorted(run.samples):
    a = np.ascontiguousarray(run.samples[name])
    h.update(f"{name}|{a.dtype}|{a.shape}|".encode())
    h.update(a.tobytes())
print(json.dumps(run.status + ":" + h.hexdigest()))
"""


@dataclass
class Draw:
    seed: int
    call: str
    creature: str
    backend: str
    time: float
    speed: str
    speeds: list[str]
    threads: int
    mode: str  # once, twice, held
    delay: float
    gap: float
    empty_generated: bool
    empty_cache: bool

    def rerun(self) -> str:
        return (f"LEGDSL_RANDOM_API_INTERRUPTS=1 LEGDSL_RANDOM_API_INTERRUPT_SEED={self.seed} "
                "pytest tests/api/test_random_api_interrupts.py")  # fmt: skip


def draw(seed: int, ci: bool) -> Draw:
    rng = np.random.default_rng(seed)
    call = str(rng.choice(CI_CALLS if ci else CALLS))
    name = "hopper" if ci else str(rng.choice(list(CREATURES)))
    speed = {"hopper": 1.0, "kangaroo": 4.0, "biped": 1.5}[name]
    duration = round(float(rng.uniform(0.3, 0.6 if ci else 2.0)), 2)
    if call in ("sweep", "tune"):
        duration = min(duration, 0.8)
    mode = str(rng.choice(["once", "once", "twice", "held"]))
    # the whole of a call takes from 0.1 s to a few seconds: most moments land inside it
    delay = float(rng.choice([rng.uniform(0, 0.3), rng.uniform(0, 3.0), rng.uniform(0, 0.02)]))
    return Draw(
        seed=seed,
        call=call,
        creature=name,
        backend=str(rng.choice(["c", "python"])) if call in ("run", "load", "metrics") else "c",
        time=duration,
        speed=f"{speed} m/s",
        speeds=[
            f"{speed * f:.2f} m/s"
            for f in rng.choice([0.8, 1.0, 1.2], size=int(rng.integers(2, 4)))
        ],
        threads=int(rng.integers(1, 3)),
        mode=mode,
        delay=round(delay, 4),
        gap=round(float(rng.uniform(0, 0.5)), 4),
        empty_generated=bool(rng.random() < (0.0 if ci else 0.3)),  # CI: compiles are seconds
        empty_cache=bool(rng.random() < (0.2 if ci else 0.4)),
    )


def environment(cache: Path, backend: str) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith("LEGDSL_")}
    env.update(PYTHONPATH=str(ROOT / "src"), LEGDSL_CACHE=str(cache), LEGDSL_BACKEND=backend,
               PYTHONDONTWRITEBYTECODE="1")  # fmt: skip
    return env


def scratch(where: Path, d: Draw, empty_generated: bool) -> dict[str, str]:
    where.mkdir(parents=True)
    generated = where / "generated"
    generated.mkdir()
    if not empty_generated:
        shutil.copytree(ROOT / "generated" / d.creature, generated / d.creature)
    spec = asdict(d) | {
        "source": str(ROOT / "creatures" / f"{d.creature}.leg"),
        "controller": CREATURES[d.creature],
        "generated": str(generated),
        "scratch": str(where),
    }
    return spec


def launch(code: str, spec: dict, env: dict[str, str], cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", code, json.dumps(spec)], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=300,
                          start_new_session=True)  # fmt: skip


def snapshot(*dirs: Path) -> dict[str, tuple[int, int]]:
    """Each file's size and inode: a rebuild writes a new file in its place (a use of the C
    cache's library touches its time, on purpose: the least used go first)."""
    return {
        str(p): (p.stat().st_size, p.stat().st_ino)
        for d in dirs
        for p in sorted(d.rglob("*"))
        if p.is_file()
    }


@functools.cache
def reference(key: str, base: Path) -> dict:
    """What a fresh, undisturbed process gives for the draw (its mode "none")."""
    d = Draw(**json.loads(key))
    where = base / f"reference-{abs(hash(key))}"
    spec = scratch(where, d, empty_generated=False)
    env = environment(where / "cache", d.backend)
    proc = launch(SCRIPT, spec | {"mode": "none"}, env, where)
    assert proc.returncode == 0, f"the undisturbed reference failed:\n{proc.stderr}"
    got = json.loads(proc.stdout.splitlines()[-1])
    got["cache"] = str(where / "cache")
    return got


def check_draw(d: Draw, base: Path) -> None:
    neutral = {**asdict(d), "mode": "none", "delay": 0.0, "gap": 0.0, "seed": 0}
    neutral.update(empty_generated=False, empty_cache=False)
    if d.call != "tune":
        neutral["threads"] = 1 if d.call not in ("sweep",) else neutral["threads"]
    ref = reference(json.dumps(neutral, sort_keys=True), base)
    where = base / f"draw-{d.seed}"
    spec = scratch(where, d, d.empty_generated)
    cache = where / "cache"
    if not d.empty_cache and Path(ref["cache"]).is_dir():
        shutil.copytree(ref["cache"], cache)
    env = environment(cache, d.backend)
    proc = launch(SCRIPT, spec, env, where)
    stderr = proc.stderr
    assert proc.returncode == 0, f"exit {proc.returncode}:\n{stderr[-3000:]}"
    assert "Traceback" not in stderr, stderr[-3000:]
    assert "Exception ignored" not in stderr, stderr[-3000:]
    got = json.loads(proc.stdout.splitlines()[-1])
    assert got["children"] == [], f"child processes left after the call: {got['children']}"
    assert got["children_after_again"] == [], got["children_after_again"]
    assert got["again"] == ref["first"], (
        f"the call again gave another result:\n{got['again']}\nundisturbed:\n{ref['first']}"
    )
    first = got["first"]
    if first != "KeyboardInterrupt" and first != ref["first"]:
        interrupted_result(d, first, ref["first"])
    if d.call == "save":  # each file there is whole: the undisturbed one's
        for name, digest in got["saved_after_interrupt"].items():
            if name == "run.json" and got["run_json_status"] == "incomplete":
                continue  # written first, to say so until the trajectory is whole
            assert ref["first"].get(name) == digest, f"half-written {name} after Ctrl-C"
        assert set(got["listing_after_interrupt"]) <= set(ref["first"]), got[
            "listing_after_interrupt"
        ]
    if d.call == "sweep":  # every row kept is the undisturbed one's
        lines = got["table_after_interrupt"]
        assert not lines or set(lines) <= set(ref["first"]), lines
        assert set(got["sweep_listing"]) <= {"sweep.csv", "sweep.parquet"}, got["sweep_listing"]
    # the next process: nothing recompiled or rebuilt, the same run
    generated = Path(spec["generated"])
    before = snapshot(generated, cache)
    check = launch(CHECK, spec, env, where)
    assert check.returncode == 0, check.stderr[-3000:]
    assert json.loads(check.stdout) == ref["check"], "the next process runs differently"
    after = snapshot(generated, cache)
    changed = [p for p in before if after.get(p) != before[p]]
    added = [p for p in after if p not in before and not p.startswith(str(cache))]
    assert not changed and not added, f"the next process rebuilt {changed + added}"
    leftovers = [p for p in after if "tmp" in Path(p).name or Path(p).name.startswith(".")]
    assert not leftovers, f"half-written files left: {leftovers}"


def interrupted_result(d: Draw, first: object, reference_first: object) -> None:
    """A call that returned under Ctrl-C returned the documented interrupted result."""
    if d.call == "tune":
        assert first == "ended interrupted", first
    elif d.call == "run":
        assert isinstance(first, str) and first.startswith("interrupted:"), first
    elif d.call in ("run_many", "run_copies"):  # each run its own or cut short
        if isinstance(first, list):
            first, reference_first = dict(enumerate(first)), dict(enumerate(reference_first))
        assert isinstance(first, dict) and isinstance(reference_first, dict), first
        for k, got in first.items():
            assert got == reference_first[k] or got.startswith("interrupted:"), (k, got)
    else:
        raise AssertionError(f"{d.call} returned another result under Ctrl-C: {first}")


@needs_c_compiler
@pytest.mark.parametrize("seed", range(FIRST_SEED, FIRST_SEED + COUNT))
def test_ctrl_c_inside_the_api(seed: int, tmp_path_factory: pytest.TempPathFactory) -> None:
    d = draw(seed, ci="LEGDSL_RANDOM_API_INTERRUPTS" not in os.environ)
    base = tmp_path_factory.getbasetemp() / "api-interrupts"
    base.mkdir(exist_ok=True)
    with told_with_seed(f"draw {seed}", d.rerun(), lambda: json.dumps(asdict(d))):
        check_draw(d, base)
