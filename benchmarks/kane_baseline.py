"""The baseline for the dynamics benchmarks: Kane's method in sympy.physics.mechanics.

Built from a checked legdsl ``Model`` by code that shares nothing with
legdsl's own dynamics: every body is a ``RigidBody`` with its frame and mass
centre, every legdsl primitive (slide or hinge about an axis, applied in
order) is an intermediate frame or point with its own coordinate ``q`` and
speed ``u`` (``q' = u``), and gravity acts on every mass centre. A 3D free root
keeps legdsl's (and MuJoCo's) coordinates: its frame is oriented by the
quaternion (qw, qx, qy, qz), its speeds are the world velocity of its origin
and its angular velocity in body axes, and the quaternion's kinematic
equation is q' = q * (0, w) / 2.

``KanesMethod`` gives the mass matrix M(q) and forcing F(q, u) with
M u' = F + tau. As in PyDy, both are printed to a Python module after
``sympy.cse``; the module solves M u' = F + tau numerically with
``numpy.linalg.solve``.
"""

from __future__ import annotations

import time
from pathlib import Path

import sympy as sp
from sympy.physics.mechanics import (
    KanesMethod,
    Point,
    ReferenceFrame,
    RigidBody,
    dynamicsymbols,
    inertia,
)
from sympy.physics.vector import Vector
from sympy.printing.pycode import PythonCodePrinter

from legdsl.ir.model import Model


def _num(x: float) -> sp.Expr:
    """An exact integer where the number is one (so 1 * q stays q), else a float."""
    return sp.Integer(int(x)) if float(x).is_integer() else sp.Float(x)


def _vec(frame: ReferenceFrame, xyz: tuple[float, float, float]) -> Vector:
    out = Vector(0)
    for c, e in zip(xyz, (frame.x, frame.y, frame.z), strict=True):
        if c:
            out += _num(c) * e
    return out


def kane_equations(model: Model) -> tuple[list[sp.Symbol], list[sp.Symbol], sp.Matrix, sp.Matrix]:
    """(q symbols, u symbols, M, F) for ``model``, in legdsl's coordinate order."""
    world = ReferenceFrame("N")
    origin = Point("O")
    origin.set_vel(world, 0)
    qs: list[sp.Function] = []
    us: list[sp.Function] = []
    kde: list[sp.Expr] = []
    frames: dict[str, ReferenceFrame] = {}
    points: dict[str, Point] = {}
    bodies: list[RigidBody] = []
    loads: list[tuple[Point, sp.Expr]] = []
    gravity = _vec(world, model.gravity)
    for body, joint in zip(model.bodies, model.joints, strict=True):
        name = body.name
        if joint.parent is None:
            frame, point = world, origin
        else:
            frame, point = frames[joint.parent], points[joint.parent]
        if joint.is_free_3d:
            x, y, z, qw, qx, qy, qz = dynamicsymbols("x y z qw qx qy qz")
            vx, vy, vz, wx, wy, wz = dynamicsymbols("vx vy vz wx wy wz")
            b = ReferenceFrame(f"B_{name}")
            b.orient_quaternion(world, (qw, qx, qy, qz))
            b.set_ang_vel(world, wx * b.x + wy * b.y + wz * b.z)
            p = origin.locatenew(f"P_{name}", x * world.x + y * world.y + z * world.z)
            p.set_vel(world, vx * world.x + vy * world.y + vz * world.z)
            half = sp.Rational(1, 2)
            kde += [
                x.diff() - vx,
                y.diff() - vy,
                z.diff() - vz,
                qw.diff() + half * (qx * wx + qy * wy + qz * wz),
                qx.diff() - half * (qw * wx + qy * wz - qz * wy),
                qy.diff() - half * (qw * wy + qz * wx - qx * wz),
                qz.diff() - half * (qw * wz + qx * wy - qy * wx),
            ]
            qs += [x, y, z, qw, qx, qy, qz]
            us += [vx, vy, vz, wx, wy, wz]
            frame, point = b, p
        else:
            p = point.locatenew(f"P_{name}", _vec(frame, joint.origin))
            p.v2pt_theory(point, world, frame)
            point = p
            for d in joint.dofs:
                q, u = dynamicsymbols(f"q_{d.name} u_{d.name}")
                qs.append(q)
                us.append(u)
                kde.append(q.diff() - u)
                axis = _vec(frame, d.axis)
                if d.motion == "hinge":
                    f = ReferenceFrame(f"F_{d.name}")
                    f.orient_axis(frame, axis, q)
                    f.set_ang_vel(frame, u * axis)
                    frame = f
                else:
                    moved = point.locatenew(f"S_{d.name}", q * axis)
                    moved.set_vel(frame, u * axis)
                    moved.v1pt_theory(point, world, frame)
                    point = moved
        frames[name], points[name] = frame, point
        com = point.locatenew(f"C_{name}", _vec(frame, body.com))
        com.v2pt_theory(point, world, frame)
        i = body.inertia
        dyadic = inertia(
            frame, *(_num(v) for v in (i[0][0], i[1][1], i[2][2], i[0][1], i[1][2], i[0][2]))
        )
        mass = _num(body.mass)
        bodies.append(RigidBody(name, com, frame, mass, (dyadic, com)))
        loads.append((com, mass * gravity))
    kane = KanesMethod(world, q_ind=qs, u_ind=us, kd_eqs=kde)
    kane.kanes_equations(bodies, loads)
    q_syms = [sp.Symbol(f"q{i}") for i in range(len(qs))]
    u_syms = [sp.Symbol(f"u{i}") for i in range(len(us))]
    plain = dict(zip(qs + us, q_syms + u_syms, strict=True))
    mass_matrix = kane.mass_matrix.xreplace(plain)
    forcing = kane.forcing.xreplace(plain)
    return q_syms, u_syms, mass_matrix, forcing


def print_module(
    model: Model, q: list[sp.Symbol], u: list[sp.Symbol], m: sp.Matrix, f: sp.Matrix
) -> str:
    """A Python module with ``mass_forcing(q, v)`` and ``forward_dynamics(q, v, tau)``."""
    nv = len(u)
    entries = [(i, j, m[i, j]) for i in range(nv) for j in range(nv) if m[i, j] != 0]
    exprs = [e for _, _, e in entries] + list(f)
    temps, reduced = sp.cse(exprs, symbols=sp.numbered_symbols("c"))
    printer = PythonCodePrinter({"fully_qualified_modules": True})
    lines = [
        f'"""Kane baseline for {model.name}: sympy.physics.mechanics, printed after cse."""',
        "",
        "import math",
        "",
        "import numpy as np",
        "",
        f"NQ = {len(q)}",
        f"NV = {nv}",
        "",
        "",
        "def mass_forcing(q, v):",
        f"    {', '.join(map(str, q))}, = q",
        f"    {', '.join(map(str, u))}, = v",
    ]
    lines += [f"    {s} = {printer.doprint(e)}" for s, e in temps]
    lines.append(f"    M = np.zeros(({nv}, {nv}))")
    for (i, j, _), e in zip(entries, reduced[: len(entries)], strict=True):
        lines.append(f"    M[{i}, {j}] = {printer.doprint(e)}")
    forcing = ", ".join(printer.doprint(e) for e in reduced[len(entries) :])
    lines += [
        f"    F = np.array([{forcing}])",
        "    return M, F",
        "",
        "",
        "def forward_dynamics(q, v, tau):",
        "    M, F = mass_forcing(q, v)",
        "    return np.linalg.solve(M, F + np.asarray(tau, dtype=float))",
        "",
    ]
    text = "\n".join(lines)
    imports = sorted(printer.module_imports)
    if any(mod != "math" for mod in imports):
        raise RuntimeError(f"unexpected imports in the Kane module: {imports}")
    return text


def compile_kane(model: Model, out: Path) -> dict[str, float]:
    """Build, print and write the Kane module; the seconds each stage took."""
    t0 = time.perf_counter()
    q, u, m, f = kane_equations(model)
    t1 = time.perf_counter()
    text = print_module(model, q, u, m, f)
    t2 = time.perf_counter()
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(text)
    t3 = time.perf_counter()
    return {"kane": t1 - t0, "cse_print": t2 - t1, "write": t3 - t2}
