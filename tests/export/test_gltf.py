"""glTF export: valid for the Khronos validator, and read back the same by independent readers."""

from __future__ import annotations

import json
import struct
from pathlib import Path

import numpy as np
import pytest
from anim_runs import creature_motion
from external_tools import validate_gltf

from legdsl.export.gltf import write_gltf
from legdsl.export.motion import Motion, ground_area, quaternion_to_matrix
from legdsl.export.shapes import body_mesh, ground_meshes

Z_UP_TO_Y_UP = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])
NUMPY_TYPES = {5126: np.float32, 5123: np.uint16, 5125: np.uint32}
WIDTH = {"SCALAR": 1, "VEC3": 3, "VEC4": 4, "MAT4": 16}


def _ground(motion: Motion) -> list:
    return ground_meshes(motion.terrain, *ground_area(motion))


def read_glb(path: Path) -> tuple[dict, bytes]:
    """The JSON and binary chunks of a GLB file, read by hand from the spec's layout."""
    data = path.read_bytes()
    magic, version, length = struct.unpack_from("<4sII", data, 0)
    assert (magic, version, length) == (b"glTF", 2, len(data))
    json_length, json_type = struct.unpack_from("<I4s", data, 12)
    assert json_type == b"JSON"
    doc = json.loads(data[20 : 20 + json_length])
    bin_length, bin_type = struct.unpack_from("<I4s", data, 20 + json_length)
    assert bin_type == b"BIN\0"
    start = 28 + json_length
    return doc, data[start : start + bin_length]


def accessor(doc: dict, blob: bytes, index: int) -> np.ndarray:
    acc = doc["accessors"][index]
    view = doc["bufferViews"][acc["bufferView"]]
    dtype = NUMPY_TYPES[acc["componentType"]]
    count, width = acc["count"], WIDTH[acc["type"]]
    offset = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    values = np.frombuffer(blob, dtype=dtype, count=count * width, offset=offset)
    return values.reshape(count, width) if width > 1 else values


@pytest.fixture(scope="module", params=["kangaroo", "quadruped"])
def exported(request, tmp_path_factory) -> tuple[Motion, Path]:
    motion = creature_motion(request.param, tmp_path_factory.mktemp(request.param) / "run")
    path = tmp_path_factory.mktemp("glb") / f"{request.param}.glb"
    size = write_gltf(motion, path)
    assert size == path.stat().st_size > 0
    return motion, path


def test_the_khronos_validator_finds_no_issue(exported) -> None:
    motion, path = exported
    report = validate_gltf(path)
    issues = report["issues"]
    assert issues["numErrors"] == 0 and issues["numWarnings"] == 0, issues["messages"]
    info = report["info"]
    assert info["animationCount"] == 1
    assert info["drawCallCount"] == len(motion.bodies) + len(_ground(motion))


def test_trimesh_reads_the_link_tree_at_its_first_pose(exported) -> None:
    trimesh = pytest.importorskip("trimesh")
    motion, path = exported
    scene = trimesh.load(path, force="scene")
    assert len(scene.geometry) == len(motion.bodies) + len(_ground(motion))
    names = {b.name for b in motion.bodies}
    assert names <= set(scene.graph.nodes)
    for b, body in enumerate(motion.bodies):
        matrix, _ = scene.graph.get(body.name)
        assert np.allclose(matrix[:3, 3], Z_UP_TO_Y_UP @ motion.positions[0, b], atol=1e-5)
        rot = Z_UP_TO_Y_UP @ quaternion_to_matrix(motion.quaternions[0, b])
        assert np.allclose(matrix[:3, :3], rot, atol=1e-5)


def test_the_animation_replays_the_run(exported) -> None:
    motion, path = exported
    doc, blob = read_glb(path)
    (animation,) = doc["animations"]
    nodes = doc["nodes"]
    # the links, the creature's top node, a "ground" node over the ground's meshes, the contacts
    assert len(nodes) == len(motion.bodies) + 2 + len(_ground(motion)) + len(motion.contact_names)
    inputs = {s["input"] for s in animation["samplers"]}
    assert len(inputs) == 1
    times = accessor(doc, blob, inputs.pop())
    assert times[0] == 0.0
    assert float(times[-1]) == pytest.approx(motion.duration, abs=1e-6)
    assert len(times) == motion.frames
    assert all(s["interpolation"] == "LINEAR" for s in animation["samplers"])

    # Each link node is a child of its parent link's node (the root's: the creature's top node).
    index = {n.get("name"): i for i, n in enumerate(nodes)}
    parent_of = {c: i for i, n in enumerate(nodes) for c in n.get("children", [])}
    for body in motion.bodies:
        expected = motion.creature if body.parent is None else body.parent
        assert parent_of[index[body.name]] == index[expected]

    # Compose every node's animated local transform down the tree, at every keyframe.
    channels = {}
    for channel in animation["channels"]:
        values = accessor(doc, blob, animation["samplers"][channel["sampler"]]["output"])
        channels[(channel["target"]["node"], channel["target"]["path"])] = values
    top = np.eye(4)
    top[:3, :3] = quaternion_to_matrix(np.array(nodes[0]["rotation"]))
    for k in range(motion.frames):
        local = {i: np.eye(4) for i in range(len(nodes))}
        for (node, path), values in channels.items():
            if path == "translation":
                local[node][:3, 3] = values[k]
            else:
                local[node][:3, :3] = quaternion_to_matrix(values[k].astype(float))
        world = {0: top}
        for i, node in enumerate(nodes):  # parents come before children
            for child in node.get("children", []):
                world[child] = world[i] @ local[child]
        for b, body in enumerate(motion.bodies):
            w = world[index[body.name]]
            assert np.allclose(w[:3, 3], Z_UP_TO_Y_UP @ motion.positions[k, b], atol=1e-5)
            rot = Z_UP_TO_Y_UP @ quaternion_to_matrix(motion.quaternions[k, b])
            assert np.allclose(w[:3, :3], rot, atol=1e-5)


def test_the_scene_carries_its_frame_range_and_the_ground(exported) -> None:
    motion, path = exported
    doc, _ = read_glb(path)
    extras = doc["scenes"][0]["extras"]
    assert extras["frame_start"] == 0 and extras["frame_end"] == motion.frames - 1
    assert extras["fps"] == pytest.approx((motion.frames - 1) / motion.duration)
    assert extras["time_end"] == pytest.approx(motion.duration)
    nodes = doc["nodes"]
    (ground,) = [n for n in nodes if n.get("name") == "ground"]
    names = [nodes[c]["name"] for c in ground["children"]]
    assert names == [name for name, _, _ in _ground(motion)]
    assert "animation" not in ground


def test_gltf_json_with_embedded_buffer(exported, tmp_path: Path) -> None:
    trimesh = pytest.importorskip("trimesh")
    motion, _ = exported
    path = tmp_path / "run.gltf"
    write_gltf(motion, path, "gltf")
    doc = json.loads(path.read_text())
    assert doc["buffers"][0]["uri"].startswith("data:application/octet-stream;base64,")
    assert len(trimesh.load(path, force="scene").geometry) == len(motion.bodies) + len(
        _ground(motion)
    )
    assert validate_gltf(path)["issues"]["numErrors"] == 0


@pytest.fixture(scope="module")
def skinned(exported, tmp_path_factory) -> tuple[Motion, Path]:
    motion, _ = exported
    path = tmp_path_factory.mktemp("skin") / f"{motion.creature}-skin.glb"
    write_gltf(motion, path, skin=True)
    return motion, path


def test_the_skinned_rig_validates(skinned) -> None:
    motion, path = skinned
    report = validate_gltf(path)
    issues = report["issues"]
    assert issues["numErrors"] == 0 and issues["numWarnings"] == 0, issues["messages"]
    doc, _ = read_glb(path)
    (skin,) = doc["skins"]
    names = [doc["nodes"][j]["name"] for j in skin["joints"]]
    assert names == [b.name for b in motion.bodies]
    assert all("mesh" not in doc["nodes"][j] for j in skin["joints"])
    (skin_node,) = [i for i, n in enumerate(doc["nodes"]) if "skin" in n]
    assert skin_node in doc["scenes"][0]["nodes"]  # a root node, as glTF wants


def test_the_skin_deforms_into_the_runs_poses(skinned) -> None:
    """Linear blend skinning (weights 1) at a keyframe puts each link's mesh at its world pose."""
    motion, path = skinned
    doc, blob = read_glb(path)
    (animation,) = doc["animations"]
    nodes = doc["nodes"]
    k = motion.frames // 2
    local = {i: np.eye(4) for i in range(len(nodes))}
    for i, n in enumerate(nodes):
        if "rotation" in n:
            local[i][:3, :3] = quaternion_to_matrix(np.array(n["rotation"]))
    for channel in animation["channels"]:
        values = accessor(doc, blob, animation["samplers"][channel["sampler"]]["output"])[k]
        node = channel["target"]["node"]
        if channel["target"]["path"] == "translation":
            local[node][:3, 3] = values
        else:
            local[node][:3, :3] = quaternion_to_matrix(values.astype(float))
    world = {i: local[i] for i in doc["scenes"][0]["nodes"]}
    for i, node in enumerate(nodes):
        for child in node.get("children", []):
            world[child] = world[i] @ local[child]
    (skin,) = doc["skins"]
    ibm = accessor(doc, blob, skin["inverseBindMatrices"]).reshape(-1, 4, 4).transpose(0, 2, 1)
    (mesh,) = [m for m in doc["meshes"] if m["name"].endswith("_skin")]
    for b, primitive in enumerate(mesh["primitives"]):
        attrs = primitive["attributes"]
        assert set(accessor(doc, blob, attrs["JOINTS_0"])[:, 0]) == {b}
        v = accessor(doc, blob, attrs["POSITION"]).astype(float)
        joint = world[skin["joints"][b]] @ ibm[b]
        skinned_v = v @ joint[:3, :3].T + joint[:3, 3]
        local_v = body_mesh(motion.bodies[b]).positions.astype(float)
        rot = Z_UP_TO_Y_UP @ quaternion_to_matrix(motion.quaternions[k, b])
        expected = local_v @ rot.T + Z_UP_TO_Y_UP @ motion.positions[k, b]
        assert np.allclose(skinned_v, expected, atol=2e-5)
