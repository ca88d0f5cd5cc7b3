"""The ``.leg`` ground as MuJoCo contact parameters (``solref``, ``solimp``, ``solreffriction``).

legdsl's ground (``sim/contact.py``) is a force law: a contact point ``p``
metres deep and sinking at ``p'`` is pushed out with ``K p + B p'`` (never
pulled), and held tangentially by a spring-damper. MuJoCo's contacts are soft
constraints instead. For one constraint row with impedance ``d`` (``solimp``),
reference ``aref = -B' v - K' d r`` (``solref``; with negative numbers
``(-s, -c)`` MuJoCo takes ``K' = s / dmax**2`` and ``B' = c / dmax``),
regulariser ``R = (1 - d) / d * A0`` and unconstrained acceleration ``a0``,
its force is ``f = (A + R)**-1 (aref - a0)``, where ``A0`` is MuJoCo's
diagonal estimate of the row's inverse inertia: for a contact between a body
and the world, the body's translational ``body_invweight0`` (computed at the
zero configuration). With a constant small impedance (``dmin = dmax = d``)
``R`` dwarfs ``A`` and the force becomes

    f = (s r + c v) / ((1 - d) A0)  -  d / (1 - d) * a0 / A0   (+ O(d) of the first term)

so ``s = K (1 - d) A0`` and ``c = B (1 - d) A0`` give legdsl's spring-damper,
up to a remainder of relative size ``d``: a soft constraint with a tiny
impedance *is* a spring. ``IMPEDANCE`` is that ``d``.

The paw pad (eq. 6) is stiffer the deeper it is pressed; MuJoCo lets the
impedance rise with the penetration (``solimp``'s width, midpoint and power),
and the curve below makes the force follow eq. (6) within 7%.

What MuJoCo's contact cannot carry over is the tangential spring's anchor
(friction rows have no position error): the export's anchor pads (``mjpads.py``)
carry the tangent spring-damper on slide joints and make the contact's friction
hard, so that the pad sticks (``FRICTION_IMPRATIO``). Without pads the tangent
law becomes its damper alone (``solreffriction``). The torsion spring is not
written, and no slip is a large friction coefficient.
``tests/export/test_mjcf_ground.py`` drops each shipped creature in both simulators.

``body_invweight0`` is computed here as MuJoCo does (trace of ``J M^-1 J^T`` / 3
at each body's mass centre, at the zero configuration, where every body frame
has the world's axes), with numpy, so the export needs no MuJoCo.
"""

from __future__ import annotations

import numpy as np

from legdsl.export.mjpads import AnchorPad, carrier_inertials
from legdsl.export.xml import nums
from legdsl.ir.model import Model, Pad

IMPEDANCE = 0.001  # solimp dmin = dmax: small, so the constraint acts as the declared spring
# Anchor pads' friction: MuJoCo divides the friction rows' regulariser by impratio (elliptic
# cones), which turns the soft rows of IMPEDANCE into hard ones: R = (1 - d) / d A0 / impratio.
FRICTION_IMPRATIO = 1e7
# 1/s: the hard row's velocity decay. legdsl sets its anchor the instant the foot touches
# down; the faster the pad stops the closer MuJoCo comes (the kangaroo's first landing: pitch
# within 0.4 degrees RMS at 1000/s, 0.08 at 5000/s). The decay is explicit in RK4, whose limit
# is 2.78 / dt: 5000/s is 2 / dt at the 0.4 ms step, the pads' own margin (mjpads.py).
FRICTION_RATE = 5000.0


def invweight0(model: Model, pads: tuple[AnchorPad, ...] = ()) -> dict[str, tuple[float, float]]:
    """MuJoCo's ``body_invweight0`` (translational, rotational) of each body of ``model``,
    and of each anchor pad's body when the export has ``pads`` (``mjpads.py``)."""
    inverse, jacobians = _inverse_mass(model, pads)
    return {
        name: (
            float(np.trace(jv @ inverse @ jv.T)) / 3.0,
            float(np.trace(jw @ inverse @ jw.T)) / 3.0,
        )
        for name, (jv, jw) in jacobians.items()
    }


def stop_parameters(model: Model, pads: tuple[AnchorPad, ...] = ()) -> dict[str, dict[str, str]]:
    """Per stopped coordinate: the MJCF joint attributes solreflimit and solimplimit that make
    MuJoCo's limit row the stop's spring-damper in N*m/rad (N/m), as the contacts' normal row
    is made the ground's spring: a direct solref is an acceleration's, so it is scaled by the
    row's ``A0``, MuJoCo's ``dof_invweight0`` (the inverse mass matrix's diagonal at zero)."""
    if not model.stops:
        return {}
    inverse, _ = _inverse_mass(model, pads)
    d = IMPEDANCE
    out = {}
    for stop in model.stops:
        scale = (1.0 - d) * float(inverse[stop.v_index, stop.v_index])
        out[stop.dof] = {
            "solreflimit": nums((-stop.k * scale, -stop.b * scale)),
            "solimplimit": nums((d, d, 0.001, 0.5, 2.0)),
        }
    return out


def _inverse_mass(
    model: Model, pads: tuple[AnchorPad, ...]
) -> tuple[np.ndarray, dict[str, tuple[np.ndarray, np.ndarray]]]:
    """MuJoCo's mass matrix at zero coordinates (the pads' slides after the model's
    velocities), inverted, and each body's (and pad's) Jacobians there."""
    origin: dict[str, np.ndarray] = {}
    chains: dict[str, list[tuple[str, np.ndarray, np.ndarray, int]]] = {}
    for body, joint in zip(model.bodies, model.joints, strict=True):
        if joint.parent is None:
            p = np.zeros(3) if joint.is_free_3d else np.asarray(joint.origin, float)
            chain: list[tuple[str, np.ndarray, np.ndarray, int]] = []
        else:
            p = origin[joint.parent] + np.asarray(joint.origin, float)
            chain = list(chains[joint.parent])
        if joint.is_free_3d:  # qvel: linear velocity in world axes, angular in body axes
            for k in range(3):
                chain.append(("slide", np.eye(3)[k], p, joint.v_start + k))
            for k in range(3):
                chain.append(("hinge", np.eye(3)[k], p, joint.v_start + 3 + k))
        else:
            for dof in joint.dofs:  # at q = 0 a dof's axis and position are its joint frame's
                chain.append((dof.motion, np.asarray(dof.axis, float), p, dof.v_index))
        origin[body.name] = p
        chains[body.name] = chain
    inertials = carrier_inertials(model, pads)
    nv = model.nv
    armature = []  # (velocity, armature) of each pad slide
    for pad in pads:  # its slides are further velocities, after the model's
        p = origin[pad.body] + np.asarray(pad.point, float)
        chain = list(chains[pad.body])
        if pad.level is not None:
            chain.append(("hinge", np.array([0.0, 1.0, 0.0]), p, nv))
            nv += 1
        for _, direction in pad.slides:
            chain.append(("slide", np.asarray(direction, float), p, nv))
            armature.append((nv, pad.mass))
            nv += 1
        origin[pad.name] = p
        chains[pad.name] = chain
        inertials[pad.name] = (pad.mass, np.zeros(3), pad.inertia * np.eye(3))

    mass = np.zeros((nv, nv))
    for i, extra in armature:
        mass[i, i] += extra
    jacobians = {}
    for name, (m, com, inertia) in inertials.items():
        jv = np.zeros((3, nv))
        jw = np.zeros((3, nv))
        x = origin[name] + com
        for kind, axis, at, i in chains[name]:
            if kind == "slide":
                jv[:, i] += axis
            else:
                jw[:, i] += axis
                jv[:, i] += np.cross(axis, x - at)
        mass += m * jv.T @ jv + jw.T @ inertia @ jw
        jacobians[name] = (jv, jw)
    try:
        inverse = np.linalg.inv(mass)
    except np.linalg.LinAlgError:
        # Singular at zero coordinates (a ball joint about x, y, x is in gimbal lock there,
        # though it starts elsewhere): MuJoCo's weights are the pseudo-inverse's then.
        inverse = np.linalg.pinv(mass)
    return inverse, jacobians


# The paw pad (eq. 6) through solimp's impedance curve, which MuJoCo lets rise with the
# penetration. With d << 1 the stiffness term of the force is s d(p)^2 p / (dmax^2 A0), so the
# pad's secant k / (T - p) asks for d(p) / dmax ~ 1 / sqrt(T - p). These solimp shape numbers
# (width in pad thicknesses, d0 / dmax, midpoint, power) and the scale PAD_SCALE fit that to
# within 7% from no penetration to 0.8 of the thickness (least squares on the force ratio);
# past the width the pad continues as a linear spring of its stiffness there.
PAD_WIDTH = 1.137
PAD_D0 = 0.3267
PAD_MID = 0.8889
PAD_POWER = 2.1835
PAD_SCALE = 9.9415


def _impedance(x: float, d0: float, dmax: float) -> float:
    """MuJoCo's solimp curve at ``x`` = depth / width (PAD_MID and PAD_POWER as its shape)."""
    x = min(max(x, 0.0), 1.0)
    mid, power = PAD_MID, PAD_POWER
    y = (
        x**power / mid ** (power - 1)
        if x <= mid
        else 1 - (1 - x) ** power / (1 - mid) ** (power - 1)
    )
    return d0 + y * (dmax - d0)


def contact_parameters(
    model: Model, pads: tuple[AnchorPad, ...] = (), friction_rate: float = FRICTION_RATE
) -> dict[str, dict[str, str]]:
    """Per contact name: the MJCF contact-pair attributes solref, solreffriction and solimp.

    With anchor ``pads`` each contact sphere is on its pad's body, whose ``A0`` it takes,
    and its friction is hard (``FRICTION_IMPRATIO``) so that the pad sticks, its sliding
    stopped at ``friction_rate`` (2 / the time step: FRICTION_RATE at the paper's 0.4 ms).
    """
    ground = model.ground
    if ground is None:
        return {}
    weights = invweight0(model, pads)
    carrier = {pad.contact: pad.name for pad in pads}
    d = IMPEDANCE
    normal = ground.normal
    out = {}
    for c in model.contacts:
        a0 = weights[carrier.get(c.name, c.body)][0]
        scale = (1.0 - d) * a0
        if isinstance(normal, Pad):
            t = normal.thickness
            load = model.total_mass * abs(model.gravity[2]) / max(1, len(model.contacts))
            static = t * load / (normal.k + load)  # eq. (6) inverted: the depth at rest
            at_rest = _impedance(static / (PAD_WIDTH * t), PAD_D0 * d, d) / d
            solref = (-PAD_SCALE * normal.k / t * scale, -normal.b * scale / at_rest)
            solimp = (PAD_D0 * d, d, PAD_WIDTH * t, PAD_MID, PAD_POWER)
        else:
            solref = (-normal.k * scale, -normal.b * scale)
            solimp = (d, d, 0.001, 0.5, 2.0)
        if c.name in carrier:
            # a hard friction row brings the pad's sliding velocity to zero at friction_rate
            # (its reference acceleration is -friction_rate v; direct solref divides by dmax)
            friction = (-friction_rate * d, -friction_rate * d)
        else:
            # friction rows have no position error: only the tangent damper carries over
            # (their regulariser is the normal row's, MuJoCo's impratio being 1)
            friction = (-ground.tangent.k * scale, -ground.tangent.b * scale)
        out[c.name] = {
            "solref": nums(solref),
            "solreffriction": nums(friction),
            "solimp": nums(solimp),
        }
    return out
