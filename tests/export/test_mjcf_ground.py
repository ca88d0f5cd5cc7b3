"""The MJCF export's ground: MuJoCo's contact parameters against legdsl's ground law.

* ``body_invweight0``, which the solref mapping divides by, is MuJoCo's own.
* The exported paw pad's normal force follows eq. (6) at rest (within 10%).
* Every terrain feature (step, box, slope) is exported where legdsl puts it:
  MuJoCo's ray cast from above meets each surface at legdsl's height.
* The anchor pads (``mjpads.py``): each body with its pads at rest has the
  declared mass, mass centre and inertia; the keyframe puts the pads at rest;
  a planar creature's pads stay level.
* A passive 2 s drop from 0.3 m (``legdsl run FILE --drop 0.3 --time 2``)
  in both simulators: the root's height stays within 5 mm RMS of legdsl's
  for every shipped creature (docs/export.md has the numbers).
"""

from __future__ import annotations

import dataclasses
import math
import re
from pathlib import Path

import mujoco
import numpy as np
import pytest
from conftest import CREATURES
from mjhelpers import index_maps, quat_to_matrix

from legdsl.check.source import check_model
from legdsl.export.mjcf import TIMESTEP, model_to_mjcf
from legdsl.export.mjcontact import invweight0
from legdsl.export.mjpads import AnchorPad, anchor_pads, carrier_inertials
from legdsl.export.mjsizes import CONTACT_RADIUS
from legdsl.ir.model import Model, Pad, Terrain
from legdsl.lang.errors import LegError
from legdsl.pipeline.generated import load_dynamics
from legdsl.sim.contact import GroundContact, pad_force
from legdsl.sim.run_loop import RunOptions
from legdsl.sim.simulate import Simulation

ALL = ["hopper", "kangaroo", "biped", "quadruped"]
# RMS of the root height difference over the 2 s drop, metres. Measured (MuJoCo 4.0.0):
# hopper 0.75 mm, kangaroo 1.9 mm, biped 0.80 mm, quadruped 0.40 mm.
BOUND = 0.005


@pytest.mark.parametrize("pads", [True, False])
@pytest.mark.parametrize("name", ALL)
def test_invweight0_is_mujocos(name: str, pads: bool) -> None:
    model = check_model(CREATURES / f"{name}.leg")
    mj = mujoco.MjModel.from_xml_string(model_to_mjcf(model, pads=pads))
    anchors = anchor_pads(model, TIMESTEP, CONTACT_RADIUS) if pads else ()
    weights = invweight0(model, anchors)
    assert len(weights) == mj.nbody - 1  # every body, the pads' included
    for body, (tran, rot) in weights.items():
        assert mj.body(body).invweight0 == pytest.approx([tran, rot], rel=1e-9)


TAIL_XYX = """\
creature a {
  spatial
  body trunk free { mass 3 kg  inertia (0.1, 0.1, 0.1) kg*m^2  initial z = 1 m }
  body tail on trunk via ball wag at (-0.1 m, 0 m, 0 m) {
    axes (1, 0, 0), (0, 1, 0), (1, 0, 0)
    initial wag_2 = 20 deg
    direction (-1, 0, 0)  length 0.3 m  com 0.15 m  mass 0.3 kg  inertia (0.0002, 0.002, 0.002) kg*m^2
  }
  contact tip on tail at tip
  ground { normal spring(k = 1e4 N/m)  tangent spring(k = 1e4 N/m, b = 50 N*s/m) }
}
"""


@pytest.mark.parametrize("pads", [True, False])
def test_invweight0_of_a_joint_in_gimbal_lock_at_zero_is_mujocos(
    tmp_path: Path, pads: bool
) -> None:
    """The weights are taken at zero coordinates, where a ball joint about x, y, x (started
    elsewhere) is in gimbal lock: a singular mass matrix, which MuJoCo weighs too (the
    export raised numpy's LinAlgError, an internal error)."""
    leg = tmp_path / "a.leg"
    leg.write_text(TAIL_XYX)
    model = check_model(leg)
    mj = mujoco.MjModel.from_xml_string(model_to_mjcf(model, pads=pads))
    anchors = anchor_pads(model, TIMESTEP, CONTACT_RADIUS) if pads else ()
    for body, (tran, rot) in invweight0(model, anchors).items():
        assert mj.body(body).invweight0 == pytest.approx([tran, rot], rel=1e-9)


def test_pad_force_follows_eq6() -> None:
    model = check_model(CREATURES / "kangaroo.leg")
    assert model.ground is not None and isinstance(model.ground.normal, Pad)
    mj = mujoco.MjModel.from_xml_string(model_to_mjcf(model))
    data = mujoco.MjData(mj)
    mujoco.mj_resetDataKeyframe(mj, data, 0)
    qmap, _ = index_maps(model, mj)
    z = qmap[model.q_names.index("z")]
    force = np.zeros(6)
    for depth in (0.0005, 0.001, 0.002, 0.004, 0.006, 0.008):
        mujoco.mj_forward(mj, data)
        data.qpos[z] -= depth + data.site("toe").xpos[2]  # the toe `depth` under the floor
        data.qvel[:] = 0.0
        mujoco.mj_forward(mj, data)
        toe = mj.geom("toe").id
        (i,) = [
            i for i in range(data.ncon) if toe in (data.contact[i].geom1, data.contact[i].geom2)
        ]
        assert data.contact[i].dist == pytest.approx(-depth, abs=1e-9)
        mujoco.mj_contactForce(mj, data, i, force)
        assert force[0] == pytest.approx(pad_force(model.ground.normal, depth), rel=0.1)


def _pads(model: Model) -> tuple[AnchorPad, ...]:
    return anchor_pads(model, TIMESTEP, CONTACT_RADIUS)


def _inertia(mj: mujoco.MjModel, body: int) -> np.ndarray:
    """A MuJoCo body's inertia about its mass centre, in its frame (stored diagonalised)."""
    axes = quat_to_matrix(mj.body_iquat[body])
    return axes @ np.diag(mj.body_inertia[body]) @ axes.T


@pytest.mark.parametrize("name", ALL)
def test_a_body_with_its_pads_has_the_declared_mass_properties(name: str) -> None:
    model = check_model(CREATURES / f"{name}.leg")
    mj = mujoco.MjModel.from_xml_string(model_to_mjcf(model))
    pads = _pads(model)
    assert {pad.contact for pad in pads} == {c.name for c in model.contacts}
    for body in model.bodies:
        i = mj.body(body.name).id
        # the body and its pads at rest (zero slides: each pad at its contact point)
        parts = [(mj.body_mass[i], mj.body_ipos[i], _inertia(mj, i))]
        for pad in (pad for pad in pads if pad.body == body.name):
            j = mj.body(pad.name).id
            assert mj.body_parentid[j] == i
            np.testing.assert_array_equal(mj.body_pos[j], pad.point)
            parts.append((mj.body_mass[j], mj.body_pos[j] + mj.body_ipos[j], _inertia(mj, j)))
            # the armature (each slide's) is the pad's mass: see mjpads.PAD_STEP_EIGENVALUE
            for slide, _ in pad.slides:
                assert mj.dof_armature[mj.joint(slide).dofadr[0]] == mj.body_mass[j] > 0
        mass = sum(m for m, _, _ in parts)
        com = sum(m * c for m, c, _ in parts) / mass
        inertia = sum(
            inertia + m * (float((c - com) @ (c - com)) * np.eye(3) - np.outer(c - com, c - com))
            for m, c, inertia in parts
        )
        assert mass == pytest.approx(body.mass, rel=1e-13)
        np.testing.assert_allclose(com, body.com, atol=1e-14)
        scale = np.abs(body.inertia).max()
        np.testing.assert_allclose(inertia, body.inertia, rtol=1e-12, atol=1e-12 * scale)
    assert mujoco.mj_getTotalmass(mj) == pytest.approx(model.total_mass, rel=1e-13)


@pytest.mark.parametrize("name", ["kangaroo", "biped"])
def test_the_keyframe_has_the_pads_at_rest(name: str) -> None:
    model = check_model(CREATURES / f"{name}.leg")
    mj = mujoco.MjModel.from_xml_string(model_to_mjcf(model))
    data = mujoco.MjData(mj)
    mujoco.mj_resetDataKeyframe(mj, data, mj.key("initial").id)
    qmap, vmap = index_maps(model, mj)
    np.testing.assert_allclose(data.qpos[qmap], model.q0, atol=1e-15)
    others = sorted(set(range(mj.nq)) - set(qmap))
    assert len(others) == sum(len(p.slides) + (p.level is not None) for p in _pads(model)) > 0
    assert (
        not data.qpos[others].any() and not data.qvel[sorted(set(range(mj.nv)) - set(vmap))].any()
    )
    mujoco.mj_forward(mj, data)
    for c in model.contacts:  # each contact sphere at its contact point
        np.testing.assert_allclose(data.geom(c.name).xpos, data.site(c.name).xpos, atol=1e-15)
    if model.planar:  # the level constraints hold
        assert mj.neq == len(model.contacts)
        np.testing.assert_allclose(data.efc_pos[data.efc_type == 0], 0.0, atol=1e-12)


def test_a_pad_too_heavy_for_its_body_is_a_leg_error() -> None:
    model = check_model(CREATURES / "hopper.leg")
    assert model.ground is not None
    tangent = dataclasses.replace(model.ground.tangent, b=1000.0)  # a 0.2 kg pad
    heavy = dataclasses.replace(model, ground=dataclasses.replace(model.ground, tangent=tangent))
    with pytest.raises(LegError, match="anchor pad for contact 'toe'.*--no-anchor-pads"):
        model_to_mjcf(heavy)
    assert "toe_pad" not in model_to_mjcf(heavy, pads=False)


def test_every_pad_too_heavy_is_told_with_its_instance() -> None:
    """The quadruped's feet come from one template line: only the first foot was told, and
    without the "(in instance ...)" every other error on a template line ends with."""
    model = check_model(CREATURES / "quadruped.leg")
    assert model.ground is not None
    tangent = dataclasses.replace(model.ground.tangent, b=5000.0)
    heavy = dataclasses.replace(model, ground=dataclasses.replace(model.ground, tangent=tangent))
    with pytest.raises(LegError) as refused:
        model_to_mjcf(heavy)
    told = [d.message for d in refused.value.diagnostics]
    assert len(told) == len(model.contacts) == 4
    for leg in ("fl", "fr", "rl", "rr"):
        assert any(
            f"contact 'toe_{leg}'" in m and m.endswith(f"(in instance '{leg}' of template 'leg')")
            for m in told
        ), told


def test_a_planar_body_keeps_its_moment_about_y_under_a_heavy_pad() -> None:
    """A planar body's x and z moments never act: a pad that leaves its moment about y
    positive fits, though taking it out of the checker's (I, I, I) breaks the triangle
    inequality (the shank's tangent damper at 300 N*s/m: a 0.06 kg pad 0.25 m from its
    mass centre)."""
    model = check_model(CREATURES / "hopper.leg")
    assert model.ground is not None
    tangent = dataclasses.replace(model.ground.tangent, b=300.0)
    model = dataclasses.replace(model, ground=dataclasses.replace(model.ground, tangent=tangent))
    mj = mujoco.MjModel.from_xml_string(model_to_mjcf(model))
    shank = next(b for b in model.bodies if b.name == "shank")
    pad = next(p for p in anchor_pads(model, TIMESTEP, CONTACT_RADIUS) if p.contact == "toe")
    mass, centre, inertia = carrier_inertials(model, (pad,))["shank"]
    assert mass + pad.mass == pytest.approx(shank.mass)
    com, point = np.asarray(shank.com), np.asarray(pad.point)
    iyy = inertia[1, 1] + pad.inertia + pad.mass * float(((point - com)[[0, 2]] ** 2).sum())
    iyy += mass * float(((centre - com)[[0, 2]] ** 2).sum())
    assert iyy == pytest.approx(shank.inertia[1][1], rel=1e-12)
    assert mj.body("shank").mass[0] == pytest.approx(mass)


def _with_terrain(model: Model, *features: tuple[str, dict[str, float]]) -> Model:
    assert model.ground is not None
    span = model.ground.terrain[0].span if model.ground.terrain else model.span
    terrain = tuple(Terrain(kind, tuple(sorted(p.items())), span) for kind, p in features)
    return dataclasses.replace(model, ground=dataclasses.replace(model.ground, terrain=terrain))


TERRAINS = {
    "step": [("step", {"x": 0.5, "height": 0.1})],
    "boxes": [
        ("box", {"x0": -1.0, "x1": -0.6, "y0": -0.3, "y1": 0.2, "height": 0.2}),
        ("box", {"x0": 1.0, "x1": 1.5, "y0": -1.0, "y1": 1.0, "height": 0.05}),
        ("box", {"x0": 2.0, "x1": 2.5, "y0": -1.0, "y1": 1.0, "height": -0.05}),
    ],
    "slope": [("slope", {"angle": math.radians(10)})],
    "downhill": [("slope", {"angle": math.radians(-25)})],
}


@pytest.mark.parametrize("terrain", sorted(TERRAINS))
def test_terrain_is_exported_where_legdsl_has_it(terrain: str) -> None:
    model = _with_terrain(check_model(CREATURES / "quadruped.leg"), *TERRAINS[terrain])
    mj = mujoco.MjModel.from_xml_string(model_to_mjcf(model))  # loads (a slope crashed once)
    data = mujoco.MjData(mj)
    mujoco.mj_forward(mj, data)
    assert model.ground is not None
    ground = GroundContact(model.ground, ("p",), planar=False)
    group = np.array([1, 0, 0, 0, 0, 0], dtype=np.uint8)  # group 0: floor and terrain
    for x in np.linspace(-1.9, 2.9, 49):
        for y in (-0.25, 0.0, 0.5):
            start = np.array([x, y, 5.0])
            geomid = np.zeros(1, dtype=np.int32)
            hit = mujoco.mj_ray(mj, data, start, np.array([0.0, 0.0, -1.0]), group, 1, -1, geomid)
            assert hit >= 0
            assert mj.geom_bodyid[geomid[0]] == 0
            _, n = ground.surface(x, y)
            # the surface is CONTACT_RADIUS below legdsl's, along its normal
            expected = ground.height(x, y) - CONTACT_RADIUS / n[2]
            assert 5.0 - hit == pytest.approx(expected, abs=1e-9), (x, y)


def _drop(name: str, generated: Path, edit=lambda text: text) -> tuple[np.ndarray, np.ndarray]:
    """Root height over a passive 2 s drop from 0.3 m: legdsl's samples and MuJoCo's at their times."""
    source = CREATURES / f"{name}.leg"
    model = check_model(source)
    dynamics = load_dynamics(model, source, generated)
    sim = Simulation(model, dynamics, RunOptions(duration=2.0, drop=0.3))
    start = list(sim.q)
    result = sim.run()
    assert result.status == "ok", result.message
    times = result.trajectory.t
    z = model.q_names.index("z")

    mj = mujoco.MjModel.from_xml_string(edit(model_to_mjcf(model)))
    data = mujoco.MjData(mj)
    mujoco.mj_resetDataKeyframe(mj, data, 0)
    qmap, vmap = index_maps(model, mj)
    data.qpos[qmap] = start
    data.qvel[vmap] = model.v0
    heights = np.empty(len(times))
    step = mj.opt.timestep
    assert step == sim.options.dt
    slides = [mj.joint(name).id for pad in _pads(model) if pad.level for name, _ in pad.slides]
    tilt = 0.0  # of a planar creature's pad slides from the ground's tangent (+x)
    done = 0
    for k in range(round(times[-1] / step) + 1):
        while done < len(times) and times[done] <= k * step + 1e-9:
            heights[done] = data.qpos[qmap[z]]
            done += 1
        mujoco.mj_step(mj, data)
        if slides:
            tilt = max(tilt, float(np.abs(data.xaxis[slides, 2]).max()))
    assert done == len(times)
    assert tilt < 0.005, "a level pad's slide turned off the ground"
    return result.trajectory.q[:, z], heights


@pytest.mark.parametrize("name", ALL)
def test_mujoco_drop_follows_legdsl(name: str, generated: Path) -> None:
    legdsl, mj = _drop(name, generated)
    rms = float(np.sqrt(np.mean((mj - legdsl) ** 2)))
    print(f"{name}: MuJoCo drop vs legdsl, RMS root height difference {rms * 1000:.2f} mm")
    assert rms < BOUND
    assert abs(mj.min() - legdsl.min()) < 0.002  # the deepest point of the landing


def test_drop_check_is_not_vacuous(generated: Path) -> None:
    """With MuJoCo's default contact parameters (the export before the mapping) it fails."""

    def defaults(text: str) -> str:
        return re.sub(r' (solref|solimp|solreffriction)="[^"]*"', "", text)

    legdsl, mj = _drop("quadruped", generated, defaults)
    assert np.sqrt(np.mean((mj - legdsl) ** 2)) > 0.005
