"""Random creatures no one wrote, compiled and checked against MuJoCo on their exported MJCF.

The shipped creatures and the hand-written outside ones cover the shapes the team thought of;
this draws others from a seeded generator: planar and 3D, a free root or one welded to the
world, trees 1 to 5 deep of 2 to 9 bodies, every joint kind (revolute and prismatic about
skewed axes, gimbal and ball joints on axes at odd angles, welds), joints at points, at tips
or at the parent's origin, links in any direction, mass centres off the link, diagonal and
full inertia tensors, masses from 10 g to 50 kg, initial joint values and rates. Each is
compiled as ``legdsl run`` compiles it (a run session on a temporary generated tree) and, at
random states, its mass matrix, bias forces and accelerations (without and with random applied
forces) must equal MuJoCo's (contacts and actuators off, as in test_mujoco_oracle) to
``RTOL``; where a C compiler is found, the C ``forward_dynamics`` equals the Python one bit for
bit, and a creature with a contact falls 0.2 s onto the ground alike on both backends.

``LEGDSL_RANDOM_CREATURES=N`` checks N creatures (default ``CI_CREATURES``) from seeds
``LEGDSL_RANDOM_SEED``, +1, ...; a failure names its seed and prints the creature's text.
"""

from __future__ import annotations

import ctypes
import math
import os
from pathlib import Path

import numpy as np
import pytest
from mjhelpers import random_state
from random_creatures import Body, body_properties, child_head, num, random_point, root_head
from runtime_helpers import assert_same
from seeded import told_with_seed
from test_mujoco_oracle import Oracle, _err

from legdsl.codegen.c.build import build, find_compiler, sources
from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions

CI_CREATURES = 4  # seeds 4 and 5 (30 s of CI) with LEGDSL_RANDOM_CREATURES=6
COUNT = int(os.environ.get("LEGDSL_RANDOM_CREATURES", CI_CREATURES))
FIRST_SEED = int(os.environ.get("LEGDSL_RANDOM_SEED", "0"))
STATES = 6
RTOL = 1e-10


def _ground(rng: np.random.Generator, planar: bool) -> list[str]:
    """A linear or paw-pad normal, sticking or Coulomb friction, a torsional spring in 3D."""
    if rng.random() < 0.5:
        normal = "normal spring(k = 2e3 N/m, b = 20 N*s/m)"
    else:
        normal = f"normal pad(k = 100 N, thickness = {num(rng.uniform(0.5, 3))} cm, b = 20 N*s/m)"
    lines = ["  ground {", f"    {normal}", "    tangent spring(k = 1e3 N/m, b = 10 N*s/m)"]
    if not planar and rng.random() < 0.5:
        lines.append("    torsion spring(k = 5 N*m/rad, b = 0.1 N*m*s/rad)")
    if rng.random() < 0.5:
        lines.append(f"    friction {num(rng.uniform(0.2, 1.0))}")
    return [*lines, "  }", "}"]


def creature_text(seed: int) -> str:
    """A random valid creature, the same for the same seed."""
    rng = np.random.default_rng(seed)
    planar = bool(rng.random() < 0.35)
    bodies: list[Body] = []
    for i in range(int(rng.integers(2, 10))):
        body = Body(f"b{i}", 0)
        props = body_properties(rng, body, planar)
        if i == 0:
            head = root_head(rng, body, planar, props)
        else:
            head = child_head(rng, body, bodies, planar, props)
        body.lines = [f"  {head} {{", *(f"    {p}" for p in props), "  }"]
        bodies.append(body)
    lines = [f"creature rand{seed} {{", "  planar" if planar else "  spatial"]
    lines.append(f"  gravity {num(rng.uniform(1, 20))} m/s^2")
    contacts = []
    for k in range(int(rng.integers(0, 4))):
        body = bodies[int(rng.integers(len(bodies)))]
        where = " at tip" if body.length is not None and rng.random() < 0.6 else ""
        where = where or (f" at {random_point(rng, planar, 0.3)}" if rng.random() < 0.7 else "")
        contacts.append(f"  contact c{k} on {body.name}{where}")
    # bodies may be written in any order: a child before its parent too
    for i in np.random.default_rng([seed, 1]).permutation(len(bodies)):
        lines += bodies[i].lines
    lines += contacts
    lines += _ground(np.random.default_rng([seed, 2]), planar)
    return "\n".join(lines) + "\n"


def _forward_dynamics_c(lib: ctypes.CDLL, q, v, tau) -> list[float]:
    arrays = [(ctypes.c_double * len(x))(*x) for x in (q, v, tau)]
    out = (ctypes.c_double * len(v))()
    err = ctypes.c_int(0)
    lib.forward_dynamics(*arrays, out, ctypes.byref(err))
    assert err.value == 0, "the C forward_dynamics flagged an error"
    return list(out)


def _close(a: object, b: object, rtol: float = RTOL) -> bool:
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return bool(np.linalg.norm(a - b) <= rtol * max(1.0, float(np.linalg.norm(b))))


def _check_accelerations(what: str, a_gen, a_ref, m_ref, rhs) -> None:
    """Accelerations solve M a = rhs: a 10 g body beside 50 kg ones makes M ill-conditioned
    (cond 1e7), and two exact solvers then differ by up to cond * eps, so the agreement asked
    grows with cond; the residual of legdsl's answer in MuJoCo's M stays at rounding."""
    a_gen = np.asarray(a_gen, dtype=float)
    if not a_gen.size:  # nothing moves (seed 11100: a fixed root and a fixed joint)
        assert np.size(a_ref) == 0, f"{what}: {np.size(a_ref)} accelerations, legdsl none"
        return
    rtol = max(RTOL, 1e-15 * float(np.linalg.cond(m_ref)))
    assert _close(a_gen, a_ref, rtol), f"{what}, {_err(a_gen, a_ref)}, rtol {rtol:.1e}"
    residual = np.linalg.norm(m_ref @ a_gen - rhs)
    scale = np.linalg.norm(m_ref) * np.linalg.norm(a_gen) + np.linalg.norm(rhs)
    assert residual <= 1e-13 * scale, f"{what}: residual {residual:.3e} of {scale:.3e}"


def check_creature(seed: int, folder: Path) -> None:
    text = creature_text(seed)
    source = folder / f"rand{seed}.leg"
    source.write_text(text)
    session = RunSession.from_file(source, generated=folder / "generated")
    model, dyn = session.model, session.dynamics
    oracle = Oracle(model)
    lib = None
    if find_compiler() is not None:
        files = sources(folder / "generated" / model.name)
        lib = ctypes.CDLL(str(build(model.name, files).path))
    rng = np.random.default_rng(seed + 10**6)
    for k in range(STATES):
        q, v = random_state(model, rng)
        tau = rng.normal(scale=5.0, size=model.nv)
        qs, vs, taus = list(q), list(v), list(tau)
        oracle.forward(q, v)
        m_ref, h_ref, a_ref = oracle.mass_matrix(), oracle.bias(), oracle.qacc_smooth()
        n = len(model.contacts)
        points = np.reshape(np.asarray(dyn.contact_positions(qs), dtype=float), (n, 3))
        for c, point in zip(model.contacts, points, strict=True):
            site = oracle.data.site(c.name).xpos
            assert _close(point, site), f"state {k}: contact {c.name} at {point}, MuJoCo {site}"
        com = oracle.data.subtree_com[oracle.root]
        assert _close(dyn.center_of_mass(qs), com), f"state {k}: mass centre"
        m_gen = dyn.mass_matrix(qs)
        assert _close(m_gen, m_ref), f"state {k}: mass matrix, {_err(m_gen, m_ref)}"
        h_gen = dyn.bias_forces(qs, vs)
        assert _close(h_gen, h_ref), f"state {k}: bias forces, {_err(h_gen, h_ref)}"
        a_gen = dyn.forward_dynamics(qs, vs, [0.0] * model.nv)
        _check_accelerations(f"state {k}: qacc (tau = 0)", a_gen, a_ref, m_ref, -h_ref)
        oracle.forward(q, v, tau)
        a_ref = oracle.qacc_smooth()
        a_gen = dyn.forward_dynamics(qs, vs, taus)
        _check_accelerations(f"state {k}: qacc (random tau)", a_gen, a_ref, m_ref, tau - h_ref)
        if lib is not None:
            a_c = _forward_dynamics_c(lib, qs, vs, taus)
            assert [x.hex() for x in a_c] == [float(x).hex() for x in a_gen], f"state {k}: C"
    if lib is not None and model.contacts:
        drop = None if model.joints[0].kind == "fixed" else 0.02
        # a fall is no stop here: the whole 0.2 s is compared
        opts = RunOptions(duration=0.2, drop=drop, fall_height=0.0, fall_tilt=math.pi)
        python = session.run(options=opts, backend="python").result
        c = session.run(options=opts, backend="c").result
        assert_same(python, c)


SEEDS = range(FIRST_SEED, FIRST_SEED + COUNT)


@pytest.mark.parametrize("seed", SEEDS)
def test_random_creature_agrees_with_mujoco(seed: int, tmp_path: Path) -> None:
    rerun = f"LEGDSL_RANDOM_SEED={seed} LEGDSL_RANDOM_CREATURES=1"
    with told_with_seed(f"random creature of seed {seed}", rerun, lambda: creature_text(seed)):
        check_creature(seed, tmp_path)
