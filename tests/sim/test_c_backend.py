"""The C backend against the Python backend: the same run, bit for bit.

For every shipped creature and controller (and the ground's features no shipped creature uses:
friction and slip, terrain steps, boxes and a slope, the pad, RK4), a short run on both
backends must give the same status, message, step count and events, and every recorded array
equal byte for byte (so even the sign of a zero counts). A falling and a diverging run must
stop at the same time with the same cause. This is the test that catches any drift between
the hand-transliterated C runtime (legdsl/codegen/c/runtime/step.c) and the Python runtime.
"""

from __future__ import annotations

import dataclasses
import math
import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from conftest import CREATURES, GENERATED, ROOT, outside_session
from runtime_helpers import assert_same, needs_c_compiler

from legdsl.codegen.c.build import UNITS
from legdsl.ir.model import Terrain
from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions, RunResult

pytestmark = needs_c_compiler

# (creature, controller, --set) of the shipped controllers, with a speed they hold
CHOSEN_RUNS = [
    ("hopper", "hop", ["speed=1m/s"]),
    ("kangaroo", "hop", ["speed=3m/s", "speed=4m/s@0.5s"]),
    ("biped", "run", ["speed=1.5m/s"]),
    ("biped", "gallop", ["speed=1.5m/s"]),
    ("biped", "gallop_human", ["speed=1.5m/s"]),
]


def _every_controller() -> list[tuple[str, str, list[str]]]:
    """The chosen runs, and every other controller of a shipped creature at its defaults (a
    controller added to a .leg file is checked without editing this test)."""
    from conftest import SHIPPED, shipped_model

    chosen = {(name, controller) for name, controller, _ in CHOSEN_RUNS}
    more = [
        (name, c.name, [])
        for name in SHIPPED
        for c in shipped_model(name).controllers
        if (name, c.name) not in chosen
    ]
    return CHOSEN_RUNS + more


SHIPPED_RUNS = _every_controller()
DURATION = 1.0


def session(name: str) -> RunSession:
    return RunSession.from_file(CREATURES / f"{name}.leg", generated=GENERATED)


def both(
    sess: RunSession, controller: str | None, settings: list[str], **options: object
) -> RunResult:
    opts = RunOptions(duration=DURATION, **options)  # type: ignore[arg-type]
    python = sess.run(controller, settings, options=opts, backend="python").result
    c = sess.run(controller, settings, options=opts, backend="c").result
    assert len(python.trajectory) > 0
    assert_same(python, c)
    return python


@pytest.mark.parametrize(("name", "controller", "settings"), SHIPPED_RUNS)
def test_shipped_controllers_run_the_same(name: str, controller: str, settings: list[str]) -> None:
    both(session(name), controller, settings)


@pytest.mark.parametrize(
    "path",
    [
        "circle(center = (0, 5) m, radius = 5 m, turn = left)",
        "square(corner = (0, -2) m, side = 4 m)",  # a closed polyline
        "polyline((0, 0) m, (3, 0) m, (3, 3) m)",  # an open one, past its end
        # 720 sides round a circle from its start: windows found by bisection, across the start
        "polygon("
        + ", ".join(
            f"({5 * math.sin(a):.9f}, {5 - 5 * math.cos(a):.9f}) m"
            for a in (2 * math.pi * k / 720 for k in range(720))
        )
        + ")",
    ],
    ids=["circle", "square", "polyline", "polygon720"],
)
def test_paths_are_followed_the_same(path: str) -> None:
    sess = session("biped")
    opts = RunOptions(duration=DURATION * 2)
    python = sess.run("run", ["speed=1.5m/s"], [path], options=opts, backend="python").result
    c = sess.run("run", ["speed=1.5m/s"], [path], options=opts, backend="c").result
    assert_same(python, c)


def test_the_quadruped_drop_runs_the_same() -> None:
    both(session("quadruped"), None, [], drop=0.3, record_rate=0.0)


def test_rk4_and_every_step_recorded_run_the_same() -> None:
    both(session("kangaroo"), "hop", ["speed=2m/s"], integrator="rk4", record_rate=0.0)
    both(session("biped"), "run", ["speed=1m/s"], integrator="rk4")


def _with_ground(sess: RunSession, **changes: object) -> RunSession:
    model = sess.model
    assert model.ground is not None
    ground = dataclasses.replace(model.ground, **changes)  # type: ignore[arg-type]
    sess.model = dataclasses.replace(model, ground=ground)
    return sess


def _terrain(kind: str, **params: float) -> Terrain:
    return Terrain(kind, tuple(params.items()), session("hopper").model.ground.span)  # type: ignore[union-attr]


@pytest.mark.parametrize(
    ("name", "controller", "settings", "ground"),
    [
        ("hopper", "hop", ["speed=1.5m/s"], {"friction": 0.25}),  # it slips
        ("biped", "run", ["speed=1.5m/s"], {"friction": 0.3}),
        ("kangaroo", "hop", ["speed=3m/s"], {"friction": 0.2}),  # the pad, slipping
        ("hopper", "hop", ["speed=1m/s"], {"terrain": (_terrain("step", x=0.3, height=0.04),)}),
        (
            "biped",
            "run",
            ["speed=1.5m/s"],
            {
                "terrain": (
                    _terrain("box", x0=0.2, x1=0.8, y0=-1.0, y1=1.0, height=0.03),
                    _terrain("step", x=1.0, height=0.05),
                )
            },
        ),  # fmt: skip
        ("hopper", "hop", ["speed=1m/s"], {"terrain": (_terrain("slope", angle=0.05),)}),
    ],
)
def test_ground_features_run_the_same(
    name: str, controller: str, settings: list[str], ground: dict[str, object]
) -> None:
    plain = session(name).run(controller, settings, options=RunOptions(duration=DURATION))
    changed = both(_with_ground(session(name), **ground), controller, settings)
    # the feature must change the motion (the foot slips, meets the step...), or this tests nothing
    assert changed.trajectory.q.tobytes() != plain.result.trajectory.q.tobytes()


def test_a_jump_over_a_box_runs_the_same() -> None:
    """The jump controller reads the box ahead (terrain.ahead_*) and the height under the
    centre of mass, in C as in Python, and jumps it (3 s: it meets the box at about 2 s)."""
    box = _terrain("box", x0=2.0, x1=2.3, y0=-10.0, y1=10.0, height=0.2)
    sess = _with_ground(session("kangaroo"), terrain=(box,))
    opts = RunOptions(duration=3.0)
    python = sess.run("jump", ["speed=3m/s"], options=opts, backend="python").result
    c = sess.run("jump", ["speed=3m/s"], options=opts, backend="c").result
    assert_same(python, c)
    plain = session("kangaroo").run("jump", ["speed=3m/s"], options=opts).result
    assert c.trajectory.q.tobytes() != plain.trajectory.q.tobytes()  # the box changed the run


def test_a_fall_stops_the_same() -> None:
    sess = session("hopper")
    opts = RunOptions(duration=DURATION)
    placed_at_once = ["speed=6m/s", "max_step=100m/s"]  # no speed step limit: it falls
    python = sess.run("hop", placed_at_once, options=opts, backend="python").result
    c = sess.run("hop", placed_at_once, options=opts, backend="c").result
    assert python.status == "fell", python.message
    assert_same(python, c)


def test_a_fall_between_long_control_ticks_is_seen() -> None:
    """With a control interval longer than the run the controller acts at t = 0 only; the
    hopper topples, and the fall rule, looked at every 2 ms whatever the control interval,
    stops it (it was looked at on control ticks only: status ok, the root on its side)."""
    sess = session("hopper")
    opts = RunOptions(duration=1.5, control_dt=10.0)
    python = sess.run("hop", [], options=opts, backend="python").result
    c = sess.run("hop", [], options=opts, backend="c").result
    assert python.status == "fell", python.message
    assert "tilted" in python.message and python.sim_time < 1.1
    assert_same(python, c)


@pytest.mark.parametrize(
    ("name", "controller", "switches", "seconds"),
    [
        ("knee_hopper", "hop", [], 5.0),
        ("rig", "stomp", [], 2.0),
        ("hexapod", "tripod", ["1s=tripod_fast"], 2.0),
        ("pogo", "bounce", [], 4.0),
        ("knee_runner", "run", [], 5.0),
        ("tail_hopper", "hop", [], 5.0),
        ("dachs", "trot", ["2.5s=bound"], 5.0),
    ],
)
def test_creatures_written_outside_the_team_run_the_same(
    name: str,
    controller: str,
    switches: list[str],
    seconds: float,
) -> None:
    """Creatures none of the shipped ones resemble: a hopper whose leg is a revolute knee
    with a rotary spring (in cm, g and kN/m, with the standard library's hopping, speed and
    posture control); a rig welded to the world with a welded bracket, an oblique gimbal, a
    sliding shin on a joint stop, a force actuator, a ball joint and a paw pad on a box; a
    hexapod from a mirrored template whose virtual legs have three feet, switching gait; a
    pogo stick whose leg is a slide and nothing else; a planar runner on two knee-spring legs
    that take turns (active and idle swapped at each liftoff, the idle one tucked); a 3D hopper
    with a tail that swings against its leg, starting rolled and drifting sideways; a long,
    short-legged quadruped whose trot and bound take the shipped quadruped's shared parts
    through 'use', switching from the trot to the bound."""
    sess = outside_session(f"{name}.leg")
    opts = RunOptions(duration=seconds)
    python = sess.run(controller, [], options=opts, switches=switches, backend="python").result
    c = sess.run(controller, [], options=opts, switches=switches, backend="c").result
    assert python.status == "ok", python.message
    assert_same(python, c)
    if name == "knee_hopper":  # it hops forward at about its commanded 0.5 m/s
        x = python.trajectory.com[:, 0]
        assert 0.40 < (x[-1] - x[len(x) // 2]) / (seconds / 2) < 0.60
        assert len(python.events) >= 16
    if name == "pogo":  # its leg shortens and lengthens, and every state of its hop is entered
        length = python.trajectory.leg_length[:, 0]
        assert length.max() - length.min() > 0.08
        assert set(python.trajectory.state.tolist()) == {0, 1, 2, 3, 4}
        z = python.trajectory.root_pos[:, 2]
        apexes = [z[i] for i in range(1, len(z) - 1) if z[i - 1] < z[i] >= z[i + 1]]
        assert len(apexes) >= 6 and all(0.78 < a < 0.86 for a in apexes[2:])  # commanded 0.8 m
    if name == "knee_runner":  # each leg bears its own stances, at about its commanded 1 m/s
        x = python.trajectory.com[:, 0]
        assert 0.75 < (x[-1] - x[len(x) // 2]) / (seconds / 2) < 1.1
        for leg in (0, 1):  # each leg compresses in its stance and tucks for the other's
            length = python.trajectory.leg_length[:, leg]
            assert length.max() - length.min() > 0.15
    if name == "dachs":  # diagonal pairs, then front and rear pairs, at about 1 m/s
        _assert_dachs_trots_then_bounds(python)
    if name == "tail_hopper":  # it hops at about 1 m/s, levels its roll, and its tail swings
        x = python.trajectory.com[:, 0]
        assert 0.85 < (x[-1] - x[len(x) // 2]) / (seconds / 2) < 1.15
        roll = python.trajectory.root_rpy[:, 0]
        assert abs(roll[0]) > 0.04 and np.abs(roll[-100:]).max() < 0.01  # 3 deg, then level
        tail = python.trajectory.q[:, python.trajectory.q_names.index("tail_base")]
        assert tail.max() - tail.min() > 0.2


def test_a_divergence_stops_the_same() -> None:
    sess = session("hopper")
    opts = RunOptions(
        duration=DURATION, dt=0.01, control_dt=0.01
    )  # too coarse for the contact (not the leg spring)
    python = sess.run("hop", [], options=opts, backend="python").result
    c = sess.run("hop", [], options=opts, backend="c").result
    assert python.status == "diverged", python.message
    assert_same(python, c)


def test_the_library_is_cached_and_rebuilt_when_its_source_changes(tmp_path: Path) -> None:
    from legdsl.codegen.c.build import build, sources

    files = sources(GENERATED / "hopper")
    first = build("hopper", files)
    again = build("hopper", files)
    assert again.cached and again.path == first.path
    changed = dict(files, **{"dynamics.c": files["dynamics.c"] + "\n/* edited */\n"})
    other = build("hopper", changed)
    assert not other.cached and other.path != first.path


def test_a_library_is_built_for_its_processor(monkeypatch: pytest.MonkeyPatch) -> None:
    """-march=native where the compiler takes it, and the processor's features in the cache's
    key: a library built on one machine is not loaded on a machine without its instructions."""
    import legdsl.codegen.c.build as build_module

    compiler = build_module.find_compiler()
    assert compiler is not None
    files = build_module.sources(GENERATED / "hopper")
    march, features = build_module.native(compiler)
    assert ("-march=native" in build_module.flags(compiler)) == bool(march)
    key = build_module.library_key(files, compiler)
    monkeypatch.setattr(build_module, "native", lambda c: (march, features + "-elsewhere"))
    assert build_module.library_key(files, compiler) != key
    monkeypatch.setattr(build_module, "native", lambda c: ("", ""))
    assert "-march=native" not in build_module.flags(compiler)


def test_a_unit_that_does_not_compile_fails_the_build_and_leaves_no_library(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The units compile at once: one that fails is reported with the compiler's words, after
    the others are waited for, and nothing is left in the cache."""
    from legdsl.codegen.c.build import BuildFailed, build, sources

    monkeypatch.setenv("LEGDSL_CACHE", str(tmp_path / "cache"))
    files = sources(GENERATED / "hopper")
    broken = dict(files, **{"machine.c": files["machine.c"] + "\nthis is not C;\n"})
    with pytest.raises(BuildFailed, match="failed on the C of hopper .*machine.c"):
        build("hopper", broken)
    assert list((tmp_path / "cache").iterdir()) == []  # no library, no leftover sources
    assert not build("hopper", files).cached  # and the good sources still build


def test_a_damaged_library_in_the_cache_is_built_again(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A library cut short on the disk would crash the process that loads it (SIGBUS): its seal
    (its own digest at its end) no longer matches, so it is built again, in a process of its
    own here as a user's run would be."""
    from legdsl.codegen.c.build import build, sources
    from legdsl.codegen.c.cache import sealed

    monkeypatch.setenv("LEGDSL_CACHE", str(tmp_path / "cache"))
    files = sources(GENERATED / "hopper")
    first = build("hopper", files)
    assert sealed(first.path)
    whole = first.path.read_bytes()
    flipped = [bytearray(whole), bytearray(whole)]
    flipped[0][-1] ^= 1  # in the seal
    flipped[1][100] ^= 1  # in the ELF header
    for damaged in (whole[:4096], *map(bytes, flipped)):
        first.path.write_bytes(damaged)
        assert not sealed(first.path)
        code = (
            "import ctypes; from pathlib import Path; from legdsl.codegen.c.build import build, "
            f"sources; b = build('hopper', sources(Path({str(GENERATED / 'hopper')!r})));"
            "ctypes.CDLL(str(b.path)); print(b.cached)"
        )
        env = dict(os.environ, PYTHONPATH=str(ROOT / "src"))
        done = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
        assert (done.returncode, done.stdout.strip()) == (0, "False"), done.stderr
        assert first.path.read_bytes() == whole


def test_a_cache_that_cannot_take_the_library_falls_back_to_python(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """A full, unwritable or non-executable cache: the default backend runs in Python with a
    notice; ``--backend c`` asked for C, so it is a user error naming the cache and the fixes."""
    from legdsl.cli import main
    from legdsl.sim import c_library

    for known in ("_LOADED", "_BY_STAT", "_TRUSTED"):  # as in a new process: nothing loaded yet
        monkeypatch.setattr(c_library, known, {})
    (tmp_path / "file").write_text("a file where the cache's directory should be")
    monkeypatch.setenv("LEGDSL_CACHE", str(tmp_path / "file" / "cache"))
    argv = ["run", str(CREATURES / "hopper.leg"), "--controller", "hop", "--time", "0.1",
            "--generated", str(GENERATED), "--out", str(tmp_path / "run")]  # fmt: skip
    assert main(argv) == 0
    said = capsys.readouterr().err
    assert f"cannot build or load the C library in {tmp_path / 'file' / 'cache'}" in said
    assert "running on the Python backend" in said
    assert main([*argv, "--backend", "c"]) == 2
    said = capsys.readouterr().err
    assert (
        f"move {tmp_path / 'file'} (a file, not a directory) away, set LEGDSL_CACHE to a " in said
    )
    assert "or use --backend python" in said and "free space" not in said  # not a full disk
    assert "Traceback" not in said


def test_the_cache_keeps_the_most_recently_used_libraries(tmp_path: Path) -> None:
    from legdsl.codegen.c.cache import trim

    sizes = {f"old-{k}.so": 1000 for k in range(5)} | {"new.so": 1000, "keep.so": 1000}
    for k, (name, size) in enumerate(sizes.items()):
        (tmp_path / name).write_bytes(b"x" * size)
        os.utime(tmp_path / name, (1000 + k, 1000 + k))
    os.utime(tmp_path / "keep.so", (0, 0))  # the oldest, but the one just built
    (tmp_path / "notes.txt").write_text("not a library")
    trim(tmp_path, keep=tmp_path / "keep.so", most=2500)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["keep.so", "new.so", "notes.txt"]


def test_two_builds_at_once_both_load(tmp_path: Path) -> None:
    """Two processes building the same library into an empty cache: both end with a whole one."""
    env = dict(os.environ, LEGDSL_CACHE=str(tmp_path / "cache"), PYTHONPATH=str(ROOT / "src"))
    code = (
        "import ctypes; from pathlib import Path; from legdsl.codegen.c.build import build, sources;"
        f"b = build('hopper', sources(Path({str(GENERATED / 'hopper')!r})));"
        "ctypes.CDLL(str(b.path)); print(b.path)"
    )
    procs = [
        subprocess.Popen([sys.executable, "-c", code], env=env, stdout=subprocess.PIPE, text=True)
        for _ in range(2)
    ]
    outs = [p.communicate(timeout=120)[0].strip() for p in procs]
    assert [p.returncode for p in procs] == [0, 0]
    assert outs[0] == outs[1]
    cache = tmp_path / "cache"
    assert sorted(p.name for p in cache.iterdir()) == sorted(
        [Path(outs[0]).name, "compilers", "objects"]
    )
    kept = sorted(p.name.split("-")[0] for p in (cache / "objects").iterdir())
    assert kept == sorted(f"{unit}" for unit in UNITS)  # whole objects, no temporary left


def test_a_state_gone_infinite_between_checks_stops_the_same() -> None:
    """A hip torque of 1e300 N*m (its 'max' taken off) overflows the state to NaN within
    two steps, before the next check: the recorder's check, every step, stops it."""
    sess = session("hopper")
    model = sess.model
    free = [dataclasses.replace(a, max=None) if a.name == "hip_motor" else a
            for a in model.actuators]  # fmt: skip
    sess.model = dataclasses.replace(model, actuators=tuple(free))
    opts = RunOptions(duration=0.1, record_rate=0.0)
    settings = ["hip_motor.force=1e300N*m"]
    python = sess.run(None, settings, options=opts, backend="python").result
    c = sess.run(None, settings, options=opts, backend="c").result
    assert python.status == "diverged" and "no longer finite" in python.message
    assert python.steps < 5  # before the first check after the start
    assert_same(python, c)


def test_a_divergence_between_long_control_ticks_is_seen() -> None:
    """Checked only at its control ticks, once in 20 s, the biped on 12 ms steps (too
    coarse for the ground) ran on until its state overflowed; the checks every 2 ms find
    the runaway velocity first."""
    sess = session("biped")
    opts = RunOptions(duration=20.0, dt=0.012, control_dt=20.0, record_rate=0.1)
    python = sess.run(None, [], options=opts, backend="python").result
    c = sess.run(None, [], options=opts, backend="c").result
    assert python.status == "diverged" and "a velocity reached" in python.message
    assert_same(python, c)


@pytest.mark.parametrize(
    ("name", "controller", "in_c"),
    [
        ("hopper", "hop", True),
        ("kangaroo", "hop", True),
        ("kangaroo", "jump", True),  # it reads the terrain ahead
        ("quadruped", "trot", True),
        ("biped", "gallop", True),
        ("biped", "gallop_human", True),
        ("biped", "run", True),
    ],  # fmt: skip
)
def test_the_state_machine_runs_in_c_where_it_can(name: str, controller: str, in_c: bool) -> None:
    """Every control tick of these controllers is taken by the C state machine (with its
    kinematic solves and, for the run controller, its path tracker)."""
    from legdsl.pipeline.backend import make_simulation
    from legdsl.pipeline.settings import sort_settings
    from legdsl.sim.c_backend import CSimulation
    from legdsl.sim.machine import StateMachine

    sess = session(name)
    s = sort_settings(["speed=1.5m/s"], sess.model, controller)
    machine = StateMachine(sess.model, sess.control(controller), s.inputs, s.params, s.schedule)
    opts = RunOptions(duration=0.5)
    sim = make_simulation(sess.model, sess.dynamics, opts, machine, "c",
                          (sess.source, sess.generated, sess.syntax))  # fmt: skip
    assert isinstance(sim, CSimulation)
    result = sim.run()
    assert result.status == "ok"
    ticks = result.steps // 5 + 1
    assert sim.c.ctl_ticks == (ticks if in_c else 0)


def test_a_batch_runs_each_job_as_alone() -> None:
    from legdsl.pipeline.backend import run_batch

    sess = session("kangaroo")
    jobs = [
        {"controller": "hop", "settings": [f"speed={v}m/s"], "options": RunOptions(duration=0.4)}
        for v in (2, 3, 4, 5)
    ]
    runs = run_batch(sess, jobs, threads=2)
    for job, run in zip(jobs, runs, strict=True):
        alone = sess.run(**job, backend="python").result
        assert_same(alone, run.result)
    assert len({run.result.trajectory.speed_command.tobytes() for run in runs}) == 4


def test_a_missing_or_stale_c_file_is_compiled_again(generated: Path) -> None:
    folder = generated / "kangaroo"
    (folder / "control_hop.c").unlink()
    text = (folder / "dynamics.c").read_text()
    (folder / "dynamics.c").write_text(text.replace('legdsl_model_fingerprint[] = "', 'x[] = "'))
    sess = RunSession.from_file(CREATURES / "kangaroo.leg", generated=generated)
    run = sess.run("hop", ["speed=3m/s"], options=RunOptions(duration=0.2), backend="c")
    assert run.status == "ok"
    assert (folder / "control_hop.c").is_file()
    assert (folder / "dynamics.c").read_text() == (
        GENERATED / "kangaroo" / "dynamics.c"
    ).read_text()


def test_the_c_runtime_mirrors_the_python_runtime_as_it_is() -> None:
    """step.c and machine.c transliterate these Python functions; an edit of one of them must
    be followed in the C (the identity tests here check the result) and then recorded by
    updating the digests in legdsl/sim/c_mirrors.py (python -m legdsl.sim.c_mirrors prints
    them). Until then the C twin steps aside at run time, so no run differs."""
    from legdsl.sim import c_mirrors

    step = c_mirrors.digest(c_mirrors._step_functions())
    machine = c_mirrors.digest(c_mirrors._machine_functions())
    assert (step, machine) == (c_mirrors.STEP_DIGEST, c_mirrors.MACHINE_DIGEST), (
        "the Python runtime changed since codegen/c/runtime/step.c or machine.c was brought in "
        "line with it: make the same change there, run tests/sim/test_c_backend.py, then set "
        f'STEP_DIGEST = "{step}" and MACHINE_DIGEST = "{machine}" in legdsl/sim/c_mirrors.py'
    )


def test_an_interrupt_between_c_calls_stops_the_run_where_c_is() -> None:
    """A signal lands in Python between two calls into C (here from the progress callback,
    which runs at such a moment): the run is interrupted there, its time, steps, message and
    recording telling the same instant, as on the Python backend."""
    from legdsl.sim.run_loop import Interrupted

    calls = []

    def stop(t: float, duration: float) -> None:
        calls.append(t)
        if len(calls) == 2:  # the signal, once, after the report at the start (run() reports
            raise Interrupted("SIGTERM")  # once more at the end)

    sess = session("kangaroo")
    opts = RunOptions(duration=60.0, record_rate=10.0)
    result = sess.run("hop", [], options=opts, progress=stop, backend="c").result
    assert result.status == "interrupted" and result.cause == "SIGTERM"
    assert 0 < result.sim_time < 60.0
    assert result.sim_time == result.steps * opts.dt
    assert f"at t = {result.sim_time:.4f} s" in result.message
    assert result.trajectory.t[-1] <= result.sim_time < result.trajectory.t[-1] + 0.1 + 1e-9


def test_a_python_runtime_edited_since_the_c_steps_the_c_aside(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """With the digests of c_mirrors out of date, the C backend (for the step) or the C state
    machine (for the controller) is not used, and the run is still the Python backend's."""
    import io

    from legdsl.pipeline.backend import make_simulation
    from legdsl.pipeline.settings import sort_settings
    from legdsl.sim import c_mirrors
    from legdsl.sim.machine import StateMachine
    from legdsl.sim.simulate import Simulation

    sess = session("hopper")
    s = sort_settings(["speed=1m/s"], sess.model, "hop")
    where = (sess.source, sess.generated, sess.syntax)
    opts = RunOptions(duration=0.3)

    def simulation() -> Simulation:
        machine = StateMachine(sess.model, sess.control("hop"), s.inputs, s.params, s.schedule)
        return make_simulation(sess.model, sess.dynamics, opts, machine, "c", where, log)

    log = io.StringIO()
    monkeypatch.setattr(c_mirrors, "MACHINE_DIGEST", "edited")
    c_mirrors.machine_matches.cache_clear()
    c_mirrors.step_matches.cache_clear()
    try:
        _stepped_aside(simulation, sess, opts, log, monkeypatch)
    finally:  # the digests come back with monkeypatch; what was read from them must go too
        monkeypatch.undo()
        c_mirrors.machine_matches.cache_clear()
        c_mirrors.step_matches.cache_clear()


def _stepped_aside(simulation: Any, sess: RunSession, opts: RunOptions, log: Any,
                   monkeypatch: pytest.MonkeyPatch) -> None:  # fmt: skip
    from legdsl.sim import c_mirrors
    from legdsl.sim.c_backend import CSimulation
    from legdsl.sim.simulate import Simulation

    sim = simulation()
    assert isinstance(sim, CSimulation)
    result = sim.run()
    assert sim.c.ctl_ticks == 0 and not sim.c.c_control  # the Python state machine ran
    assert_same(sess.run("hop", ["speed=1m/s"], options=opts, backend="python").result, result)
    monkeypatch.setattr(c_mirrors, "STEP_DIGEST", "edited")
    c_mirrors.step_matches.cache_clear()
    sim = simulation()
    assert type(sim) is Simulation
    assert "mirrors an older Python runtime" in log.getvalue()


@pytest.mark.parametrize(
    ("name", "first", "switches", "settings"),
    [
        (
            "quadruped",
            "trot",
            ["1s=bound", "2s=gallop"],
            ["speed=1.5m/s", "speed=2m/s@1s", "speed=1.8m/s@1.5s", "speed=2.5m/s@2s"],
        ),
        ("biped", "run", ["1s=gallop", "2s=run"], ["speed=1.5m/s", "speed=2m/s@2.5s"]),
    ],
)
def test_a_switching_run_runs_the_same_its_machines_in_c(
    name: str, first: str, switches: list[str], settings: list[str], monkeypatch: Any
) -> None:
    """A run that changes controller: each controller's machine runs in C between the ticks
    its switches and commands are due at, which Python takes; the run is Python's."""
    from legdsl.sim.switching import SwitchingMachine

    sess = session(name)
    opts = RunOptions(duration=3.0)
    python = sess.run(first, settings, switches=switches, options=opts, backend="python")
    in_python = []
    tick = SwitchingMachine.__call__

    def counted(machine: SwitchingMachine, sim: Any) -> None:
        in_python.append(sim.t)
        tick(machine, sim)

    monkeypatch.setattr(SwitchingMachine, "__call__", counted)
    c = sess.run(first, settings, switches=switches, options=opts, backend="c")
    assert_same(python.result, c.result)
    assert python.machine is not None and c.machine is not None
    assert c.machine.segment_info(3.0) == python.machine.segment_info(3.0)
    assert [s["controller"] for s in c.machine.segments] == [first, *(w[3:] for w in switches)]
    # Python took the ticks of a command and of a liftoff while a switch waits for one
    ticks = c.result.steps // 5 + 1
    assert 0 < len(in_python) < ticks // 20


def _assert_dachs_trots_then_bounds(run: RunResult) -> None:
    """Before the switch at 2.5 s the diagonal feet are down together and the front ones
    never; after it the front feet together and a front with a rear one never; forward at
    about the commanded 1 m/s in each."""
    tr = run.trajectory
    down = {n: tr.contact[:, i].astype(bool) for i, n in enumerate(tr.contact_names)}

    def together(a: str, b: str, lo: float, hi: float) -> float:
        window = (tr.t > lo) & (tr.t < hi)
        either = (down[a] | down[b])[window].sum()
        return float((down[a] & down[b])[window].sum() / max(either, 1))

    assert together("toe_fl", "toe_rr", 1.0, 2.5) > 0.9
    assert together("toe_fl", "toe_fr", 1.0, 2.5) < 0.1
    assert together("toe_fl", "toe_fr", 3.2, 5.0) > 0.9
    assert together("toe_fl", "toe_rl", 3.2, 5.0) < 0.1
    for lo, hi in ((1.0, 2.5), (3.2, 5.0)):
        i, j = np.searchsorted(tr.t, lo), np.searchsorted(tr.t, hi) - 1
        assert 0.6 < (tr.com[j, 0] - tr.com[i, 0]) / (tr.t[j] - tr.t[i]) < 1.6
