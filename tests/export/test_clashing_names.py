"""Links named like the nodes and prims an export adds (``ground``, ``shape``, ``floor``, the
creature's name) keep them apart."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from standin import ModelKinematics
from test_gltf import read_glb

from legdsl.check.source import check_model
from legdsl.export.gltf import write_gltf
from legdsl.export.motion import motion_from
from legdsl.export.usd import link_paths, write_usd
from legdsl.sim.trajectory import empty

pytest.importorskip("pxr", reason="needs usd-core: pip install 'legdsl[export]'")
from pxr import Usd, UsdGeom  # noqa: E402

CLASHING = """
creature clash {
  planar
  body ground free {
    mass 2 kg  inertia 0.1 kg*m^2
    shape box(0.4 m, 0.1 m)
    initial x = 0 m, z = 0.6 m, pitch = 0 deg
  }
  body shape on ground via revolute hip at (0.1 m, 0 m) {
    length 0.5 m  com 0.25 m  mass 0.5 kg  inertia 0.01 kg*m^2
    shape cylinder(0.02 m)
  }
}
"""


def clashing_motion(tmp_path: Path, text: str = CLASHING):
    source = tmp_path / "clash.leg"
    source.write_text(text)
    model = check_model(source)
    times = np.linspace(0.0, 1.0, 11)
    tr = empty(
        len(times), 4, 4, 0, 0, q_names=model.q_names, v_names=model.v_names,
        contact_names=(), state_names=(), total_mass=model.total_mass,
    )  # fmt: skip
    tr.t[:] = times
    tr.q[:] = np.column_stack([0.5 * times, 0.6 + 0.4 * times, 0.3 * times, 0.5 * times])
    return motion_from(model, tr, ModelKinematics(model), fps=10)


def test_a_link_called_ground_does_not_carry_the_floor(tmp_path: Path) -> None:
    motion = clashing_motion(tmp_path)
    path = tmp_path / "clash.usda"
    write_usd(motion, path, "usda")
    stage = Usd.Stage.Open(str(path))
    last = Usd.TimeCode(motion.frames - 1)
    cache = UsdGeom.XformCache(last)
    floors = [p for p in stage.Traverse() if p.GetName() == "floor"]
    assert len(floors) == 1
    # the floor is fixed in the world, not a child of the link 'ground' that rose 0.4 m
    assert cache.GetLocalToWorldTransform(floors[0]).ExtractTranslation()[2] == 0.0
    ancestor = floors[0].GetParent()
    while ancestor.GetPath() != ancestor.GetPath().absoluteRootPath:
        assert not UsdGeom.Xformable(ancestor).GetTimeSamples(), ancestor.GetPath()
        ancestor = ancestor.GetParent()
    # each link is an Xform with a mesh of its own, the link 'shape' beside its parent's mesh
    for b, link in enumerate(link_paths(motion)):
        prim = stage.GetPrimAtPath(link)
        assert prim.GetTypeName() == "Xform", link
        meshes = [c for c in prim.GetChildren() if c.IsA(UsdGeom.Mesh)]
        assert len(meshes) == 1, link
        world = cache.GetLocalToWorldTransform(prim).ExtractTranslation()
        assert np.allclose(world, motion.positions[-1, b], atol=1e-9), link


def test_gltf_link_nodes_keep_their_names(tmp_path: Path) -> None:
    # links called as the creature, the ground node and the floor: every node's name is unique
    # (tools rename duplicates, Blender the later node), and the links have theirs
    text = CLASHING.replace("body ground", "body clash").replace("on ground", "on clash")
    motion = clashing_motion(tmp_path, text.replace("body shape", "body floor"))
    for skin in (False, True):
        path = tmp_path / f"clash{int(skin)}.glb"
        write_gltf(motion, path, skin=skin)
        names = [n.get("name") for n in read_glb(path)[0]["nodes"]]
        assert len(names) == len(set(names)), names
        assert {"clash", "floor"} <= set(names)
        # and every mesh's: two meshes were named floor (the link's and the ground's)
        meshes = [m.get("name") for m in read_glb(path)[0]["meshes"]]
        assert len(meshes) == len(set(meshes)), meshes
        assert names.index("clash") == 1 + [b.name for b in motion.bodies].index("clash")


CONTACTS = """
creature clash {
  planar
  body clash free {
    mass 2 kg  inertia 0.1 kg*m^2
    shape box(0.4 m, 0.1 m)
    initial x = 0 m, z = 0.6 m, pitch = 0 deg
  }
  body leg1 on clash via revolute h1 at (0.1 m, 0 m) {
    length 0.5 m  com 0.25 m  mass 0.5 kg  inertia 0.01 kg*m^2
  }
  body leg2 on clash via revolute h2 at (-0.1 m, 0 m) {
    length 0.5 m  com 0.25 m  mass 0.5 kg  inertia 0.01 kg*m^2
  }
  body leg3 on clash via revolute h3 at (0 m, 0 m) {
    length 0.5 m  com 0.25 m  mass 0.5 kg  inertia 0.01 kg*m^2
  }
  contact shape on leg1 at tip
  contact clash_1 on leg2 at tip
  contact ground on leg3 at tip
}
"""


def test_contacts_keep_their_names_and_the_exports_own_nodes_step_aside(tmp_path: Path) -> None:
    """A contact named as the export's top node would be (clash_1) was renamed clash_1_1, the
    top node taking its name, and the USD mesh 'shape' took a contact 'shape''s name: an
    animator pinning a foot by its contact's name got the whole creature, or nothing."""
    source = tmp_path / "clash.leg"
    source.write_text(CONTACTS)
    model = check_model(source)
    times = np.linspace(0.0, 1.0, 11)
    tr = empty(
        len(times), 6, 6, 3, 0, q_names=model.q_names, v_names=model.v_names,
        contact_names=("shape", "clash_1", "ground"), state_names=(),
        total_mass=model.total_mass,
    )  # fmt: skip
    tr.t[:] = times
    tr.q[:, 1] = 0.6
    motion = motion_from(model, tr, ModelKinematics(model), fps=10)
    path = tmp_path / "clash.glb"
    write_gltf(motion, path)
    nodes = read_glb(path)[0]["nodes"]
    names = [n.get("name") for n in nodes]
    contacts = {n["name"] for n in nodes if (n.get("extras") or {}).get("legdsl_contact")}
    assert contacts == {"shape", "clash_1", "ground"}, names
    assert len(names) == len(set(names)) and names[0] not in contacts | {"clash"}, names
    write_usd(motion, tmp_path / "clash.usda", "usda")
    stage = Usd.Stage.Open(str(tmp_path / "clash.usda"))
    for b, link in enumerate(link_paths(motion)):
        prim = stage.GetPrimAtPath(link)
        touching = {c.GetName() for c in prim.GetChildren() if c.HasAttribute("legdsl:touching")}
        mine = {
            c for c, on in zip(motion.contact_names, motion.contact_bodies, strict=True) if on == b
        }
        assert touching == mine, link
