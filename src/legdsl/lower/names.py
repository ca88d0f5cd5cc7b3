"""The names under which a generated dynamics function assigns its results.

One name per returned value, in the order ``symbolic`` returns them (the
leaves of its nested lists and tuples): ``toe_x`` for a contact's position,
``m_hip_knee`` for an entry of the mass matrix, ``thigh_r13`` for an entry of a
body's rotation matrix, and so on, from the model's coordinate, body and
contact names. ``Block.finish`` assigns a value to its name only if it is more
than a number, an input or ``2*x``, and a value returned twice (the mass
matrix is symmetric) is assigned once, under its first name.
"""

from __future__ import annotations

from legdsl.ir.model import Model

AXES = ("x", "y", "z")


def output_names(model: Model, function: str) -> list[str]:
    """The names of ``function``'s results, in the order it returns them."""
    v, q = model.v_names, model.q_names
    contacts = [c.name for c in model.contacts]
    bodies = [b.name for b in model.bodies]
    if function == "mass_matrix":
        return [f"m_{a}_{b}" for a in v for b in v]
    if function == "bias_forces":
        return [f"h_{a}" for a in v]
    if function == "forward_dynamics":
        return [f"qdd_{a}" for a in v]
    if function == "state_derivative":
        return [f"qdot_{a}" for a in q]
    if function == "contact_positions":
        return [f"{c}_{k}" for c in contacts for k in AXES]
    if function == "contact_velocities":
        return [f"{c}_v{k}" for c in contacts for k in AXES]
    if function == "contact_jacobians":
        return [f"{c}_j{k}_{a}" for c in contacts for k in AXES for a in v]
    if function == "contact_angular_jacobians":
        return [f"{c}_jw{k}_{a}" for c in contacts for k in AXES for a in v]
    if function == "body_poses":
        rotation = [f"r{i}{j}" for i in (1, 2, 3) for j in (1, 2, 3)]
        return [f"{b}_{part}" for b in bodies for part in (*AXES, *rotation)]
    if function == "body_velocities":
        return [f"{b}_{kind}{k}" for b in bodies for kind in ("v", "w") for k in AXES]
    if function == "center_of_mass":
        return [f"com_{k}" for k in AXES]
    if function == "center_of_mass_velocity":
        return [f"com_v{k}" for k in AXES]
    return []  # one value: returned as it is
