"""Whole-simulation speed: a passive drop of each shipped creature, legdsl beside MuJoCo.

Run from the repository root:

    python benchmarks/bench_runtime.py

For each creature: a 3 s passive drop from 0.3 m with the paper's integration
step (semi-implicit Euler at 0.0004 s), timed in legdsl's runtime (generated
dynamics in pure Python, plus actuators and the paper's ground contact) and
in MuJoCo stepping the exported MJCF with its own contacts on, the same step
and its Euler integrator. Reports the real-time factor (simulated seconds per
wall second) of each, their ratio, and the run's final state as a sanity
check. The results replace the "runtime" section of docs/benchmarks.md.
"""

from __future__ import annotations

import argparse
import platform
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from report import DOC, replace_section  # noqa: E402

from legdsl.check.source import check_model  # noqa: E402
from legdsl.export.mjcf import model_to_mjcf  # noqa: E402
from legdsl.pipeline.session import RunSession  # noqa: E402
from legdsl.sim.run_loop import RunOptions  # noqa: E402

CREATURES = ("kangaroo", "biped", "quadruped", "hopper")
DURATION = 3.0
STEP = 0.0004


def legdsl_drop(name: str) -> tuple[float, float, list[float]]:
    session = RunSession.from_file(ROOT / "creatures" / f"{name}.leg", generated=ROOT / "generated")
    options = RunOptions(duration=DURATION, dt=STEP, drop=0.3, record_rate=200)
    result = session.run(options=options).result  # the simulation alone is timed (wall_time)
    assert result.status == "ok", result.message
    q = result.trajectory.q  # the first sample is the state after the drop's lift, the last the end
    z = session.model.q_names.index("z")
    return DURATION / result.wall_time, float(q[-1][z]), [float(x) for x in q[0]]


def mujoco_drop(name: str, start_q: list[float], pads: bool = False) -> tuple[float, float]:
    """MuJoCo's real-time factor and final root height for a drop from ``start_q``: by
    default on the bare tree with MuJoCo's own contacts (no anchor pads: their extra joints
    and constraints slow MuJoCo down); ``pads``: on the export as ``legdsl export`` writes
    it, whose anchor pads reproduce legdsl's ground (docs/export.md)."""
    import mujoco

    model = check_model(ROOT / "creatures" / f"{name}.leg")
    mj = mujoco.MjModel.from_xml_string(model_to_mjcf(model, pads=pads))
    mj.opt.timestep = STEP
    mj.opt.integrator = mujoco.mjtIntegrator.mjINT_EULER
    data = mujoco.MjData(mj)
    # The exported springs and servos are position actuators; the keyframe holds their rests.
    data.ctrl[:] = mj.key("initial").ctrl
    for i, q_name in enumerate(model.q_names):
        joint = (
            "root"
            if q_name in ("x", "y", "z", "qw", "qx", "qy", "qz") and not model.planar
            else q_name
        )
        if joint == "root":
            offset = ("x", "y", "z", "qw", "qx", "qy", "qz").index(q_name)
            data.qpos[mj.joint("root").qposadr[0] + offset] = start_q[i]
        else:
            data.qpos[mj.joint(joint).qposadr[0]] = start_q[i]
    steps = int(round(DURATION / STEP))
    wall = time.perf_counter()
    mujoco.mj_step(mj, data, nstep=steps)  # MuJoCo's own loop in C: no Python between steps
    wall = time.perf_counter() - wall
    body = mj.body(model.bodies[0].name).id
    return DURATION / wall, float(data.xpos[body][2])


def main() -> None:
    rows = []
    for name in CREATURES:
        print(f"{name}: legdsl ...", flush=True)
        rtf, z, start_q = legdsl_drop(name)
        print(f"{name}: mujoco ...", flush=True)
        mj_rtf, mj_z = mujoco_drop(name, start_q)
        rows.append((name, rtf, mj_rtf, z, mj_z))
        print(f"{name}: legdsl {rtf:.2f}x real time, MuJoCo {mj_rtf:.1f}x", flush=True)
    table = [
        "| creature | legdsl real-time factor | MuJoCo real-time factor | MuJoCo / legdsl | root height at 3 s, legdsl / MuJoCo (m) |",
        "|---|---|---|---|---|",
    ]
    for name, rtf, mj_rtf, z, mj_z in rows:
        table.append(
            f"| {name} | {rtf:.2f} | {mj_rtf:.0f} | {mj_rtf / rtf:.0f}x | {z:.3f} / {mj_z:.3f} |"
        )
    section = "\n".join(
        [
            "## Runtime: a passive drop (issue 4)",
            "",
            "Command: `python benchmarks/bench_runtime.py` "
            f"(Python {platform.python_version()}, {platform.machine()}, 2 cores shared with other work).",
            "",
            f"Each creature falls from 0.3 m and lands for {DURATION:g} s, integrated by semi-implicit Euler at "
            f"{STEP} s (the paper's step). legdsl: the generated dynamics in pure Python plus the actuators "
            "and the paper's spring-damper ground contact, recording at 200 Hz. MuJoCo: the exported MJCF "
            "with MuJoCo's own contacts on (a different contact model, so the final heights differ by the "
            "contact compliance), its Euler integrator, the same step, the springs and servos as MuJoCo "
            "position actuators held at the keyframe's rests and set points. The real-time factors compare "
            "the cost of stepping the same tree with its actuators and contact. Above 1 is faster than real time; the paper's "
            "simulations ran 7 to 10 times slower than real time on a SUN Sparc2.",
            "",
            *table,
            "",
            "MuJoCo is compiled C with a sparse solver; legdsl's runtime is plain Python calling generated "
            "straight-line code, so the ratio is the price of staying in readable, inspectable Python. "
            "Both are deterministic.",
        ]
    )
    replace_section("runtime", section)
    print(f"wrote {DOC}")


if __name__ == "__main__":
    # no options: --help says what it measures and where it writes, rather than starting
    argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    ).parse_args()
    main()
