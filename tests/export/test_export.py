"""MJCF and URDF export, checked by loading the files into MuJoCo.

These tests need no generated dynamics: MuJoCo's own kinematics, masses and
energies are compared with quantities computed here from the model IR.
The dynamics cross-check is in ``test_mujoco_oracle.py``.
"""

from __future__ import annotations

import os
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import mujoco
import numpy as np
import pytest
from conftest import CREATURES, ROOT
from mjhelpers import (
    forward_kinematics,
    index_maps,
    load_mjcf,
    quat_to_matrix,
    random_state,
    rotation,
    set_state,
)

from legdsl.check.source import check_model
from legdsl.cli import main
from legdsl.export.formats import export_text, write_atomic
from legdsl.export.mjcf import model_to_mjcf
from legdsl.export.urdf import model_to_urdf
from legdsl.ir.model import Model

SHIPPED = ["kangaroo", "biped", "quadruped"]

# A single free rigid body with an off-centre mass centre and a full inertia.
BRICK = """
creature brick {
  spatial
  gravity 9.81 m/s^2
  body block free {
    mass 2.5 kg
    com (0.03 m, -0.02 m, 0.05 m)
    inertia ((0.2 kg*m^2, 0.01 kg*m^2, -0.02 kg*m^2), (0.01 kg*m^2, 0.3 kg*m^2, 0.015 kg*m^2),
             (-0.02 kg*m^2, 0.015 kg*m^2, 0.25 kg*m^2))
    shape box(0.2 m, 0.3 m, 0.1 m)
  }
  contact corner on block at (0.1 m, 0.15 m, -0.05 m)
}
"""

# Every joint kind the exporter handles differently: a fixed root away from the
# origin, a ball with skewed axes, a prismatic along a skewed axis, a weld, a
# limited gimbal, and a full inertia away from the body axes.
ZOO = """
creature zoo {
  spatial
  gravity 9.81 m/s^2
  body base fixed at (0.1 m, -0.2 m, 1.5 m) {
    mass 4 kg  inertia (0.1, 0.12, 0.08) kg*m^2  shape box(0.3 m, 0.2 m, 0.1 m)
  }
  body arm on base via ball shoulder at (0.05 m, 0.1 m, -0.02 m) {
    axes (0, 0.6, 0.8), (1, 0, 0), (0, 0.8, -0.6)
    direction (0.6, 0, -0.8)
    length 0.4 m  com 0.18 m  mass 1.2 kg
    inertia ((0.02 kg*m^2, 0.001 kg*m^2, 0.002 kg*m^2), (0.001 kg*m^2, 0.018 kg*m^2, -0.001 kg*m^2),
             (0.002 kg*m^2, -0.001 kg*m^2, 0.006 kg*m^2))
  }
  body slider on arm via prismatic ext at tip {
    axis (0, 0.6, -0.8)
    length 0.2 m  com 0.1 m  mass 0.5 kg  inertia (0.002, 0.002, 0.0005) kg*m^2
    shape capsule(0.02 m)
  }
  body lump on slider via fixed glue at (0.01 m, 0.02 m, -0.2 m) {
    mass 0.3 kg  com (0.01 m, 0 m, 0 m)  inertia (0.001, 0.001, 0.001) kg*m^2
    shape sphere(0.04 m)
  }
  body fin on lump via gimbal wrist at (0 m, 0 m, -0.05 m) {
    length 0.15 m  com 0.07 m  mass 0.2 kg  inertia (0.0004, 0.0004, 0.0001) kg*m^2
    shape frustum(0.02 m, 0.01 m)
    limits (-1 rad, 1 rad), (-0.5 rad, 0.5 rad)
  }
  actuator wrist_servo on wrist_x servo(kp = 5 N*m/rad, kv = 0.2 N*m*s/rad, setpoint = 0.3 rad, max = 0.4 N*m)
  actuator push on ext force(max = 3 N)
  contact tip_point on fin at tip
  contact nub on lump at (0 m, 0.04 m, 0 m)
}
"""


def _model(name: str, tmp_path: Path) -> Model:
    if name in SHIPPED:
        return check_model(CREATURES / f"{name}.leg")
    path = tmp_path / f"{name}.leg"
    path.write_text({"brick": BRICK, "zoo": ZOO}[name])
    return check_model(path)


ALL = [*SHIPPED, "brick", "zoo"]


def _parents(mj: mujoco.MjModel) -> dict[str, str | None]:
    return {
        mj.body(i).name: (mj.body(int(mj.body_parentid[i])).name if i else None)
        for i in range(mj.nbody)
    }


@pytest.mark.parametrize("name", ALL)
def test_mjcf_tree_masses_and_inertias(name: str, tmp_path: Path) -> None:
    model = _model(name, tmp_path)
    mj = load_mjcf(model)
    assert mj.nbody == len(model.bodies) + 1  # + MuJoCo's world body
    assert (mj.nq, mj.nv) == (model.nq, model.nv)
    assert mujoco.mj_getTotalmass(mj) == pytest.approx(model.total_mass, rel=1e-14)
    parents = _parents(mj)
    for b in model.bodies:
        assert parents[b.name] == (b.parent or "world")
        i = mj.body(b.name).id
        assert mj.body_mass[i] == pytest.approx(b.mass, rel=1e-14)
        np.testing.assert_allclose(mj.body_ipos[i], b.com, atol=1e-14)
        # MuJoCo stores principal moments and the principal axes' orientation.
        axes = quat_to_matrix(mj.body_iquat[i])
        inertia = axes @ np.diag(mj.body_inertia[i]) @ axes.T
        scale = np.abs(b.inertia).max()  # MuJoCo diagonalizes: round-off at 1e-14 of that
        np.testing.assert_allclose(inertia, b.inertia, rtol=1e-12, atol=1e-12 * scale)
    # One MuJoCo joint per legdsl coordinate, with its name, kind and axis.
    for d in model.dofs:
        j = mj.joint(d.name)
        want = mujoco.mjtJoint.mjJNT_SLIDE if d.motion == "slide" else mujoco.mjtJoint.mjJNT_HINGE
        assert mj.jnt_type[j.id] == want
        assert mj.body(int(mj.jnt_bodyid[j.id])).name == model.joint(d.joint).child
        np.testing.assert_allclose(mj.jnt_axis[j.id], d.axis, atol=1e-15)
        # limits are enforced in MuJoCo where legdsl enforces them: with a stop only
        stopped = d.limits is not None and d.name in {s.dof for s in model.stops}
        assert bool(mj.jnt_limited[j.id]) is stopped
        if d.limits is not None:
            np.testing.assert_allclose(mj.jnt_range[j.id], d.limits)
    free = [j for j in model.joints if j.is_free_3d]
    assert mj.njnt == len(model.dofs) + len(free)
    np.testing.assert_allclose(mj.opt.gravity, model.gravity)
    assert mj.opt.timestep == 0.0004
    assert mj.opt.integrator == mujoco.mjtIntegrator.mjINT_RK4
    assert not mj.dof_damping.any() and not mj.dof_armature.any()
    assert not mj.dof_frictionloss.any()


@pytest.mark.parametrize("name", ALL)
def test_mjcf_body_and_contact_positions_match_ir_kinematics(name: str, tmp_path: Path) -> None:
    model = _model(name, tmp_path)
    mj = load_mjcf(model)
    data = mujoco.MjData(mj)
    maps = index_maps(model, mj)
    rng = np.random.default_rng(7)
    states = [np.asarray(model.q0)] + [random_state(model, rng)[0] for _ in range(20)]
    for q in states:
        set_state(mj, data, maps, q, np.zeros(model.nv))
        mujoco.mj_kinematics(mj, data)
        poses = forward_kinematics(model, q)
        for b in model.bodies:
            p, r = poses[b.name]
            i = mj.body(b.name).id
            np.testing.assert_allclose(data.xpos[i], p, atol=1e-12)
            np.testing.assert_allclose(data.xmat[i].reshape(3, 3), r, atol=1e-12)
            np.testing.assert_allclose(data.xipos[i], p + r @ np.asarray(b.com), atol=1e-12)
        for c in model.contacts:
            p, r = poses[c.body]
            want = p + r @ np.asarray(c.point)
            np.testing.assert_allclose(data.site(c.name).xpos, want, atol=1e-12)
            np.testing.assert_allclose(data.geom(c.name).xpos, want, atol=1e-12)


def test_fk_check_is_sensitive_to_joint_order(tmp_path: Path) -> None:
    """The IR kinematics above would catch joints applied in the wrong order."""
    model = _model("biped", tmp_path)
    q = np.zeros(model.nq)
    q[3] = 1.0  # identity quaternion
    hip = model.joint("hip_l")
    q[[d.q_index for d in hip.dofs]] = (0.7, -0.5, 0.9)
    in_order = forward_kinematics(model, q)["shank_l"][1]
    r = np.eye(3)
    for d in reversed(hip.dofs):
        r = r @ rotation(d.axis, q[d.q_index])
    assert np.abs(in_order - r).max() > 0.1


def test_free_body_kinetic_and_potential_energy(tmp_path: Path) -> None:
    """qvel of the free joint is (world linear velocity of the origin, body angular velocity)."""
    model = _model("brick", tmp_path)
    body = model.bodies[0]
    m, c, inertia = body.mass, np.asarray(body.com), np.asarray(body.inertia)
    mj = load_mjcf(model)
    mj.opt.enableflags |= mujoco.mjtEnableBit.mjENBL_ENERGY
    data = mujoco.MjData(mj)
    maps = index_maps(model, mj)
    rng = np.random.default_rng(3)
    for _ in range(20):
        q, v = random_state(model, rng)
        v *= 3
        set_state(mj, data, maps, q, v)
        mujoco.mj_forward(mj, data)
        r = quat_to_matrix(q[3:7])
        w_body = v[3:6]
        v_com = v[0:3] + r @ np.cross(w_body, c)
        kinetic = 0.5 * m * v_com @ v_com + 0.5 * w_body @ inertia @ w_body
        potential = m * 9.81 * (q[2] + (r @ c)[2])
        assert data.energy[1] == pytest.approx(kinetic, rel=1e-12)
        assert data.energy[0] == pytest.approx(potential, rel=1e-12, abs=1e-12)
        # Swapping the frames of the angular velocity changes the energy: the check bites.
        w_world = r @ w_body
        wrong = 0.5 * m * v_com @ v_com + 0.5 * w_world @ inertia @ w_world
        assert abs(wrong - kinetic) > 1e-6 * kinetic


@pytest.mark.parametrize("name", ["kangaroo", "biped", "zoo"])
def test_mjcf_actuators_apply_the_legdsl_laws(name: str, tmp_path: Path) -> None:
    """Springs and servos as position actuators: -(k (q - rest) + b qd), clipped to max."""
    model = _model(name, tmp_path)
    mj = load_mjcf(model)
    data = mujoco.MjData(mj)
    maps = index_maps(model, mj)
    rng = np.random.default_rng(11)
    clipped = 0
    for _ in range(20):
        q, v = random_state(model, rng)
        set_state(mj, data, maps, q, 3 * v)
        ctrl = {}
        for a in model.actuators:
            p = dict(a.params)
            target = p.get("rest", p.get("setpoint", p.get("value", 0.0))) + rng.uniform(-0.2, 0.2)
            ctrl[a.name] = target
            data.ctrl[mj.actuator(a.name).id] = target
        mujoco.mj_forward(mj, data)
        for a in model.actuators:
            p = dict(a.params)
            d = next(d for d in model.dofs if d.name == a.dof)
            qd, vd = q[d.q_index], 3 * v[d.v_index]
            if a.kind == "spring":
                f = -(p["k"] * (qd - ctrl[a.name]) + p["b"] * vd)
            elif a.kind == "servo":
                f = -p["kp"] * (qd - ctrl[a.name]) - p["kv"] * vd
            else:
                f = ctrl[a.name]
            if a.max is not None:
                clipped += abs(f) > a.max
                f = min(max(f, -a.max), a.max)
            assert data.actuator_force[mj.actuator(a.name).id] == pytest.approx(f, rel=1e-12)
    if name == "zoo":
        assert clipped > 0  # the saturation was exercised


@pytest.mark.parametrize("name", ALL)
def test_mjcf_keyframe_is_the_initial_state(name: str, tmp_path: Path) -> None:
    model = _model(name, tmp_path)
    mj = load_mjcf(model)
    data = mujoco.MjData(mj)
    mujoco.mj_resetDataKeyframe(mj, data, mj.key("initial").id)
    qmap, vmap = index_maps(model, mj)
    np.testing.assert_allclose(data.qpos[qmap], model.q0, atol=1e-15)
    np.testing.assert_allclose(data.qvel[vmap], model.v0, atol=1e-15)


def _urdf_in_mujoco(model: Model) -> mujoco.MjModel:
    """MuJoCo refuses moving massless bodies; give the intermediate links 1e-12 kg.

    MuJoCo fuses bodies welded to the world into it by default for URDF, which
    would drop a fixed root's mass from the total; keep them.
    """
    spec = mujoco.MjSpec.from_string(model_to_urdf(model))
    spec.compiler.fusestatic = False
    named = {b.name for b in model.bodies}
    for b in spec.bodies:
        if b.name not in named and b.name != "world":
            assert b.mass == 0, f"intermediate link {b.name} must be massless"
            b.mass = 1e-12
            b.inertia = [1e-12] * 3
    return spec.compile()


@pytest.mark.parametrize("name", ALL)
def test_urdf_has_the_same_dynamics_as_mjcf(name: str, tmp_path: Path) -> None:
    model = _model(name, tmp_path)
    a, b = load_mjcf(model), _urdf_in_mujoco(model)
    assert mujoco.mj_getTotalmass(b) == pytest.approx(model.total_mass, rel=1e-9)
    da, db = mujoco.MjData(a), mujoco.MjData(b)
    maps_a, maps_b = index_maps(model, a), index_maps(model, b)
    for m in (a, b):
        m.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONTACT
    rng = np.random.default_rng(5)
    for _ in range(10):
        q, v = random_state(model, rng)
        out = []
        for m, d, maps in ((a, da, maps_a), (b, db, maps_b)):
            set_state(m, d, maps, q, v)
            mujoco.mj_forward(m, d)
            full = np.zeros((m.nv, m.nv))
            mujoco.mj_fullM(m, d, full)
            vmap = maps[1]
            out.append((full[np.ix_(vmap, vmap)], d.qfrc_bias[vmap].copy()))
        (ma, ha), (mb, hb) = out
        assert np.linalg.norm(ma - mb) <= 1e-9 * max(1.0, np.linalg.norm(ma))
        assert np.linalg.norm(ha - hb) <= 1e-9 * max(1.0, np.linalg.norm(ha))


@pytest.mark.parametrize("name", ALL)
def test_urdf_structure(name: str, tmp_path: Path) -> None:
    model = _model(name, tmp_path)
    root = ET.fromstring(model_to_urdf(model))
    links = [el.get("name") for el in root.iter("link")]
    assert len(links) == len(set(links))
    joints = {el.get("name"): el for el in root.iter("joint")}
    assert len(joints) == len(root.findall("joint"))
    children = [el.find("child").get("link") for el in joints.values()]
    # A tree: every link but the world has exactly one parent joint.
    assert sorted(children) == sorted(n for n in links if n != "world")
    for d in model.dofs:
        j = joints[d.name]
        assert j.get("type") in (
            ("prismatic",) if d.motion == "slide" else ("revolute", "continuous")
        )
        assert [float(x) for x in j.find("axis").get("xyz").split()] == list(d.axis)
    for j in model.joints:
        if j.is_free_3d:
            assert joints["root"].get("type") == "floating"
        if j.kind == "weld":
            assert joints[j.name].get("type") == "fixed"
    massive = {el.get("name"): el for el in root.iter("link") if el.find("inertial") is not None}
    assert set(massive) == {b.name for b in model.bodies}


@pytest.mark.parametrize("fmt", ["mjcf", "urdf"])
@pytest.mark.parametrize("name", ALL)
def test_export_is_deterministic(name: str, fmt: str, tmp_path: Path) -> None:
    first = export_text(_model(name, tmp_path), fmt)
    second = export_text(_model(name, tmp_path), fmt)
    assert first == second
    assert str(tmp_path) not in first and str(ROOT) not in first  # no absolute paths


@pytest.mark.parametrize("fmt", ["mjcf", "urdf"])
def test_export_is_the_same_under_two_hash_seeds(fmt: str) -> None:
    outs = []
    for seed in ("0", "1"):
        env = {**os.environ, "PYTHONHASHSEED": seed, "PYTHONPATH": str(ROOT / "src")}
        args = [sys.executable, "-m", "legdsl", "export", "creatures/quadruped.leg"]
        outs.append(
            subprocess.run(
                [*args, "--format", fmt, "-o", "-"],
                cwd=ROOT,
                env=env,
                capture_output=True,
                text=True,
                check=True,
            ).stdout
        )
    assert outs[0] == outs[1] and outs[0].startswith("<")


def test_cli_export_writes_files(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "sub" / "kangaroo.xml"
    assert (
        main(["export", str(CREATURES / "kangaroo.leg"), "--format", "mjcf", "-o", str(out)]) == 0
    )
    assert "wrote" in capsys.readouterr().out
    mj = mujoco.MjModel.from_xml_path(str(out))
    assert mj.nv == 10 + 2 * 2  # and each of its two contacts' anchor pad: a level hinge, a slide
    urdf = tmp_path / "k.urdf"
    assert (
        main(["export", str(CREATURES / "kangaroo.leg"), "--format", "urdf", "-o", str(urdf)]) == 0
    )
    assert ET.parse(urdf).getroot().tag == "robot"
    assert sorted(p.name for p in tmp_path.rglob("*")) == ["k.urdf", "kangaroo.xml", "sub"]


def test_cli_export_default_name_and_stdout(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.chdir(tmp_path)
    assert main(["export", str(CREATURES / "biped.leg"), "--format", "urdf"]) == 0
    assert (tmp_path / "biped.urdf").read_text() == model_to_urdf(
        check_model(CREATURES / "biped.leg")
    )
    capsys.readouterr()
    assert main(["export", str(CREATURES / "biped.leg"), "--format", "mjcf", "-o", "-"]) == 0
    said = capsys.readouterr()
    assert said.out == model_to_mjcf(check_model(CREATURES / "biped.leg"))
    assert "wrote standard output (MJCF, creature 'biped', 14 DOF)" in said.err  # as docs say
    bare = ["export", str(CREATURES / "biped.leg"), "--format", "mjcf", "--no-anchor-pads"]
    assert main([*bare, "-o", "-"]) == 0
    out = capsys.readouterr().out
    assert out == model_to_mjcf(check_model(CREATURES / "biped.leg"), pads=False)
    assert "_pad" not in out and "_pad" in model_to_mjcf(check_model(CREATURES / "biped.leg"))
    assert main(["export", str(CREATURES / "biped.leg"), "--format", "urdf",
                 "--no-anchor-pads"]) == 2  # fmt: skip
    assert "MJCF options" in capsys.readouterr().err


def test_cli_export_bad_file_writes_nothing(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    bad = tmp_path / "bad.leg"
    bad.write_text(BRICK.replace("mass 2.5 kg", "mass 2.5 m"))
    out = tmp_path / "bad.xml"
    assert main(["export", str(bad), "--format", "mjcf", "-o", str(out)]) == 2
    assert "bad.leg:" in capsys.readouterr().err
    assert not out.exists() and sorted(p.name for p in tmp_path.iterdir()) == ["bad.leg"]


def test_cli_export_mistake_shows_its_line_and_caret(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A mistake only the export finds (a pad too heavy for its body) is shown like the
    checker's: file:line:col, the line and a caret."""
    text = (CREATURES / "hopper.leg").read_text()
    bad = tmp_path / "heavy.leg"
    bad.write_text(text.replace("tangent spring(k = 2e4 N/m, b = 200 N*s/m)",
                                "tangent spring(k = 2e4 N/m, b = 1000 N*s/m)"))  # fmt: skip
    assert main(["export", str(bad), "--format", "mjcf", "-o", str(tmp_path / "x.xml")]) == 2
    line = next(i for i, t in enumerate(text.split("\n"), 1) if "contact toe" in t)
    err = capsys.readouterr().err.split("\n")
    assert err[0].startswith(f"{bad}:{line}:3: error: the MJCF export's anchor pad")
    assert err[1:3] == ["      contact toe on shank at tip", "      ^~~~~~~~~~~~~~~~~~~~~~~~~~~"]


def test_write_atomic_keeps_the_old_file_on_failure(tmp_path: Path) -> None:
    target = tmp_path / "x.xml"
    target.write_text("old")

    with pytest.raises(TypeError):
        write_atomic(target, 42)  # type: ignore[arg-type]
    assert target.read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["x.xml"]
    write_atomic(target, "new")
    assert target.read_text() == "new"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["x.xml"]
