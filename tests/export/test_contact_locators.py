"""The animation files carry the contact points (a foot's soles) as locators under their links.

An animator pins a foot where it stands; without the soles in the file the contacts, which
are not the links' tips (a flat foot's heel and toe), had to be guessed. Each contact is a
node (glTF) or an ``Xform`` (USD) under its link at the contact point, and USD says at each
frame whether it touches the ground (``legdsl:touching``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from anim_runs import creature_motion
from test_gltf import accessor, read_glb

from legdsl.export.bvh import Z_UP_TO_Y_UP
from legdsl.export.gltf import write_gltf
from legdsl.export.motion import Motion, quaternion_to_matrix
from legdsl.export.usd import link_paths, write_usd

pytest.importorskip("pygltflib", reason="needs pygltflib: pip install 'legdsl[export]'")
pytest.importorskip("pxr", reason="needs usd-core: pip install 'legdsl[export]'")
from pxr import Usd, UsdGeom  # noqa: E402


@pytest.fixture(scope="module", params=["biped", "quadruped"])
def motion(request, tmp_path_factory) -> Motion:
    return creature_motion(request.param, tmp_path_factory.mktemp(request.param) / "run")


def test_the_run_lands_and_lifts(motion: Motion) -> None:
    # the comparison below is not vacuous: some contact touches, and some frame has one off
    assert motion.touching is not None
    assert motion.touching.any() and not motion.touching.all()


def test_usd_contacts_sit_where_the_run_had_them_and_say_when_they_touch(
    motion: Motion, tmp_path: Path
) -> None:
    path = tmp_path / "run.usda"
    write_usd(motion, path, "usda")
    stage = Usd.Stage.Open(str(path))
    links = link_paths(motion)
    assert motion.touching is not None
    for c, (name, b) in enumerate(zip(motion.contact_names, motion.contact_bodies, strict=True)):
        prim = stage.GetPrimAtPath(f"{links[b]}/{name}")
        assert prim.IsValid() and prim.IsA(UsdGeom.Xform), name
        touching = prim.GetAttribute("legdsl:touching")
        for f in range(0, motion.frames, 3):
            m = np.array(UsdGeom.XformCache(Usd.TimeCode(f)).GetLocalToWorldTransform(prim))
            assert np.allclose(m[3, :3], motion.contact_positions[f, c], atol=1e-9), (name, f)
            assert touching.Get(Usd.TimeCode(f)) == bool(motion.touching[f, c]), (name, f)


@pytest.mark.parametrize("skin", [False, True])
def test_gltf_contacts_are_nodes_under_their_links(
    motion: Motion, tmp_path: Path, skin: bool
) -> None:
    path = tmp_path / "run.glb"
    write_gltf(motion, path, "glb", skin=skin)
    doc, blob = read_glb(path)
    nodes = doc["nodes"]
    index = {n.get("name"): i for i, n in enumerate(nodes)}
    parent_of = {c: i for i, n in enumerate(nodes) for c in n.get("children", [])}
    (animation,) = doc["animations"]
    channels = {
        (ch["target"]["node"], ch["target"]["path"]): accessor(
            doc, blob, animation["samplers"][ch["sampler"]]["output"]
        )
        for ch in animation["channels"]
    }
    top = np.eye(4)
    top[:3, :3] = quaternion_to_matrix(np.array(nodes[0]["rotation"]))
    for c, (name, b) in enumerate(zip(motion.contact_names, motion.contact_bodies, strict=True)):
        node = index[name]
        assert nodes[node]["extras"] == {"legdsl_contact": True}
        assert nodes[parent_of[node]]["name"] == motion.bodies[b].name
        chain = [node]
        while chain[-1] != 0:
            chain.append(parent_of[chain[-1]])
        for f in range(0, motion.frames, 5):
            world = top
            for n in reversed(chain[:-1]):
                local = np.eye(4)
                if (n, "translation") in channels:
                    local[:3, 3] = channels[(n, "translation")][f]
                    rotation = channels[(n, "rotation")][f].astype(float)
                    local[:3, :3] = quaternion_to_matrix(rotation)
                else:  # the contact's own node: fixed on its link
                    local[:3, 3] = nodes[n]["translation"]
                world = world @ local
            expected = Z_UP_TO_Y_UP @ motion.contact_positions[f, c]
            assert np.allclose(world[:3, 3], expected, atol=2e-6), (name, f)  # float32 keys
