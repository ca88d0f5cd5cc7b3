"""Export a run as glTF 2.0 (``.glb`` binary, or ``.gltf`` with the buffer embedded).

The scene has one node per link, nested as the link tree, under one top node
named after the creature. That top node turns legdsl's z-up world into
glTF's y-up (a quarter turn about x; x stays forward). Each link node holds a
triangle mesh of its drawing shape (``legdsl.export.formats.formats.shapes``) with a material of
its colour, and the run is one animation, ``run``, with a translation and a
rotation channel per link (LINEAR, time in seconds from the run's start):
the link's pose relative to its parent link, so that the nodes move the
way the joints do.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from legdsl import __version__
from legdsl.export.ending import ending
from legdsl.export.motion import (
    Motion,
    frame_rate,
    free_name,
    ground_area,
    quaternion_to_matrix,
)
from legdsl.export.shapes import Mesh, body_mesh, ground_meshes, hex_rgb, srgb_to_linear
from legdsl.files import write_atomic
from legdsl.lang.errors import UsageError
from legdsl.pipeline.optional import not_installed
from legdsl.signals import import_held

FORMATS = ("glb", "gltf")
Z_UP_TO_Y_UP = [-math.sqrt(0.5), 0.0, 0.0, math.sqrt(0.5)]  # (x, y, z, w): -90 deg about x

ARRAY_BUFFER = 34962
ELEMENT_ARRAY_BUFFER = 34963
FLOAT = 5126
UNSIGNED_SHORT = 5123
UNSIGNED_INT = 5125


def _pygltflib() -> Any:
    try:
        pygltflib = import_held("pygltflib")
    except ImportError as e:
        if not not_installed(e, "pygltflib"):
            raise
        raise UsageError("exporting glTF needs pygltflib: pip install 'legdsl[export]'") from None
    return pygltflib


# ---------------------------------------------------------------- quaternions (x, y, z, w)


def quat_conjugate(q: np.ndarray) -> np.ndarray:
    return q * np.array([-1.0, -1.0, -1.0, 1.0])


def quat_multiply(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    ax, ay, az, aw = np.moveaxis(a, -1, 0)
    bx, by, bz, bw = np.moveaxis(b, -1, 0)
    return np.stack(
        [
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz,
        ],
        axis=-1,
    )


def quat_rotate(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Rotate vectors ``v`` (..., 3) by unit quaternions ``q`` (..., 4)."""
    u, w = q[..., :3], q[..., 3:4]
    t = 2.0 * np.cross(u, v)
    return np.asarray(v + w * t + np.cross(u, t))


def local_poses(motion: Motion) -> tuple[np.ndarray, np.ndarray]:
    """Every link's pose relative to its parent link: translations (F, B, 3), rotations (F, B, 4)."""
    pos, rot = motion.positions, motion.quaternions
    local_t = pos.copy()
    local_r = rot.copy()
    for b, parent in enumerate(motion.parents):
        if parent < 0:
            continue
        inverse = quat_conjugate(rot[:, parent])
        local_t[:, b] = quat_rotate(inverse, pos[:, b] - pos[:, parent])
        local_r[:, b] = quat_multiply(inverse, rot[:, b])
    local_r /= np.linalg.norm(local_r, axis=2, keepdims=True)
    for k in range(1, len(local_r)):  # no sign flips between frames: LINEAR takes the short way
        flip = np.sum(local_r[k] * local_r[k - 1], axis=-1) < 0
        local_r[k][flip] *= -1
    return local_t, local_r


# ---------------------------------------------------------------- building the file


class _Blob:
    """One binary buffer with 4-byte aligned views, and the accessors into it."""

    def __init__(self, gltf: Any, lib: Any):
        self.gltf, self.lib = gltf, lib
        self.data = bytearray()

    def accessor(
        self, array: np.ndarray, kind: str, target: int | None = None, bounds: bool = False
    ) -> int:
        lib = self.lib
        if array.dtype == np.float32:
            component = FLOAT
        elif array.dtype == np.uint16:
            component = UNSIGNED_SHORT
        else:
            component = UNSIGNED_INT
        raw = np.ascontiguousarray(array).tobytes()
        offset = len(self.data)
        self.data += raw
        self.data += b"\0" * (-len(self.data) % 4)
        view = lib.BufferView(buffer=0, byteOffset=offset, byteLength=len(raw), target=target)
        self.gltf.bufferViews.append(view)
        count = int(array.shape[0])  # elements: scalars, or rows of a (count, n) array
        accessor = lib.Accessor(
            bufferView=len(self.gltf.bufferViews) - 1,
            componentType=component,
            count=count,
            type=kind,
        )
        if bounds:
            flat = array.reshape(count, -1)
            accessor.min = [float(x) for x in flat.min(axis=0)]
            accessor.max = [float(x) for x in flat.max(axis=0)]
        self.gltf.accessors.append(accessor)
        return len(self.gltf.accessors) - 1


def build_gltf(motion: Motion, skin: bool = False) -> Any:
    """The scene and animation as a ``pygltflib.GLTF2`` with its binary blob set.

    With ``skin`` the link nodes are the joints of a skin and carry no meshes:
    one mesh ``CREATURE_skin`` (a primitive per link, each vertex bound with
    weight 1 to its link's joint, in the first frame's pose) is deformed by them,
    which DCC tools import as an armature with one bone per link.
    """
    lib = _pygltflib()
    gltf = lib.GLTF2(
        asset=lib.Asset(version="2.0", generator=f"legdsl {__version__}"),
        scene=0,
        scenes=[lib.Scene(name=motion.creature, nodes=[0])],
    )
    blob = _Blob(gltf, lib)
    # the export's own nodes take names no link or contact has (tools key nodes by name and
    # rename duplicates: a link called like the creature would have been the one renamed, and
    # a contact is pinned by its name); a contact steps aside only for a link
    taken = {b.name for b in motion.bodies}
    contact_names = []
    for name in motion.contact_names if motion.contact_points is not None else ():
        taken.add(free := free_name(name, taken))
        contact_names.append(free)

    def own_name(name: str) -> str:
        taken.add(free := free_name(name, taken))
        return free

    gltf.nodes.append(lib.Node(name=own_name(motion.creature), rotation=Z_UP_TO_Y_UP, children=[]))

    materials: dict[str, int] = {}
    lo, hi = ground_area(motion)
    ground = ground_meshes(motion.terrain, lo, hi)
    colors = [(b.color or "#9a9a9a").lower() for b in motion.bodies] + [c for _, _, c in ground]
    for color in colors:
        if color not in materials:
            linear = [srgb_to_linear(c) for c in hex_rgb(color)]
            gltf.materials.append(
                lib.Material(
                    name=color,
                    pbrMetallicRoughness=lib.PbrMetallicRoughness(
                        baseColorFactor=[*linear, 1.0], metallicFactor=0.0, roughnessFactor=0.7
                    ),
                )
            )
            materials[color] = len(gltf.materials) - 1

    def add_mesh(name: str, mesh: Mesh, color: str) -> int:
        indices = mesh.indices.reshape(-1)
        indices = indices.astype(np.uint16 if len(mesh.positions) < 65536 else np.uint32)
        primitive = lib.Primitive(
            attributes=lib.Attributes(
                POSITION=blob.accessor(mesh.positions, "VEC3", ARRAY_BUFFER, bounds=True),
                NORMAL=blob.accessor(mesh.normals, "VEC3", ARRAY_BUFFER),
            ),
            indices=blob.accessor(indices, "SCALAR", ELEMENT_ARRAY_BUFFER),
            material=materials[color],
        )
        gltf.meshes.append(lib.Mesh(name=name, primitives=[primitive]))
        return len(gltf.meshes) - 1

    translations, rotations = local_poses(motion)
    for b, body in enumerate(motion.bodies):
        node = lib.Node(
            name=body.name,
            mesh=None if skin else add_mesh(body.name, body_mesh(body), colors[b]),
            translation=[float(x) for x in translations[0, b]],
            rotation=[float(x) for x in rotations[0, b]],
            children=[],
        )
        gltf.nodes.append(node)
        parent = motion.parents[b]
        gltf.nodes[0 if parent < 0 else parent + 1].children.append(b + 1)
    _contact_nodes(gltf, lib, motion, contact_names)

    if skin:
        _skin(gltf, lib, blob, motion, colors, materials, own_name(f"{motion.creature}_skin"))

    # The ground and terrain: fixed meshes in world coordinates, beside the creature's root.
    ground_node = lib.Node(name=own_name("ground"), children=[])
    gltf.nodes.append(ground_node)
    gltf.nodes[0].children.append(len(gltf.nodes) - 1)
    for name, mesh, color in ground:  # a mesh is named as its node: a link 'floor' has one
        free = own_name(name)
        gltf.nodes.append(lib.Node(name=free, mesh=add_mesh(free, mesh, color)))
        ground_node.children.append(len(gltf.nodes) - 1)

    fps = frame_rate(motion)
    gltf.scenes[0].extras = {
        # Blender's glTF importer keeps these as the scene's custom properties. It turns key
        # times into frames at the scene's frame rate (time 0 at frame 0), so set the scene to
        # `fps` before importing; the keys are then frames frame_start..frame_end.
        "fps": fps,
        "frame_start": 0,
        "frame_end": motion.frames - 1,
        "time_start": 0.0,
        "time_end": motion.duration,
        "up_axis": "y (legdsl z)",
        "units": "metres",
        **ending(motion),  # a run that fell or was cut short: how it ended (export/ending.py)
    }

    times = blob.accessor(motion.times.astype(np.float32), "SCALAR", bounds=True)
    animation = lib.Animation(name="run", samplers=[], channels=[])
    for b in range(len(motion.bodies)):
        for path, values, kind in (
            ("translation", translations[:, b], "VEC3"),
            ("rotation", rotations[:, b], "VEC4"),
        ):
            output = blob.accessor(values.astype(np.float32), kind)
            animation.samplers.append(
                lib.AnimationSampler(input=times, output=output, interpolation="LINEAR")
            )
            animation.channels.append(
                lib.AnimationChannel(
                    sampler=len(animation.samplers) - 1,
                    target=lib.AnimationChannelTarget(node=b + 1, path=path),
                )
            )
    gltf.animations.append(animation)
    for node in gltf.nodes:  # glTF wants no empty arrays
        if not node.children:
            node.children = None
    gltf.buffers.append(lib.Buffer(byteLength=len(blob.data)))
    gltf.set_binary_blob(bytes(blob.data))
    return gltf


def _contact_nodes(gltf: Any, lib: Any, motion: Motion, names: list[str]) -> None:
    """A node per contact point (a sole, a toe), child of its link at the point, with no
    mesh: what an animator pins a foot to. ``extras.legdsl_contact`` marks it; ``names``
    are the nodes' (the contacts', unless a link has one)."""
    if motion.contact_points is None:
        return
    for name, b, point in zip(names, motion.contact_bodies, motion.contact_points, strict=True):
        node = lib.Node(
            name=name,
            translation=[float(x) for x in point],
            extras={"legdsl_contact": True},
        )
        gltf.nodes.append(node)
        gltf.nodes[b + 1].children.append(len(gltf.nodes) - 1)


def _skin(
    gltf: Any,
    lib: Any,
    blob: _Blob,
    motion: Motion,
    colors: list[str],
    materials: dict[str, int],
    node_name: str,
) -> None:
    """A skinned mesh over the link nodes as joints, bound at the first frame (see build_gltf)."""
    top = np.eye(4)
    top[:3, :3] = quaternion_to_matrix(np.array(Z_UP_TO_Y_UP))
    primitives = []
    inverse_bind = []
    for b, body in enumerate(motion.bodies):
        bind = np.eye(4)
        bind[:3, :3] = quaternion_to_matrix(motion.quaternions[0, b])
        bind[:3, 3] = motion.positions[0, b]
        bind = top @ bind  # the joint node's global transform at the first frame
        inverse_bind.append(np.linalg.inv(bind).T.reshape(16))  # column-major
        mesh = body_mesh(body)
        positions = (mesh.positions @ bind[:3, :3].T + bind[:3, 3]).astype(np.float32)
        normals = (mesh.normals @ bind[:3, :3].T).astype(np.float32)
        n = len(positions)
        joints = np.zeros((n, 4), dtype=np.uint16)
        joints[:, 0] = b
        weights = np.zeros((n, 4), dtype=np.float32)
        weights[:, 0] = 1.0
        indices = mesh.indices.reshape(-1).astype(np.uint16 if n < 65536 else np.uint32)
        primitives.append(
            lib.Primitive(
                attributes=lib.Attributes(
                    POSITION=blob.accessor(positions, "VEC3", ARRAY_BUFFER, bounds=True),
                    NORMAL=blob.accessor(normals, "VEC3", ARRAY_BUFFER),
                    JOINTS_0=blob.accessor(joints, "VEC4", ARRAY_BUFFER),
                    WEIGHTS_0=blob.accessor(weights, "VEC4", ARRAY_BUFFER),
                ),
                indices=blob.accessor(indices, "SCALAR", ELEMENT_ARRAY_BUFFER),
                material=materials[colors[b]],
            )
        )
    gltf.meshes.append(lib.Mesh(name=node_name, primitives=primitives))  # as its node
    matrices = blob.accessor(np.array(inverse_bind, dtype=np.float32), "MAT4")
    joints_list = list(range(1, len(motion.bodies) + 1))
    root = next(b for b, parent in enumerate(motion.parents) if parent < 0)
    gltf.skins.append(
        lib.Skin(
            name=f"{motion.creature}_rig",
            joints=joints_list,
            inverseBindMatrices=matrices,
            skeleton=root + 1,
        )
    )
    # A skinned mesh's node is a root of the scene, with no transform of its own (glTF 2.0,
    # 5.29: the joints' transforms place it).
    gltf.nodes.append(lib.Node(name=node_name, mesh=len(gltf.meshes) - 1, skin=0))
    gltf.scenes[0].nodes.append(len(gltf.nodes) - 1)


def write_gltf(motion: Motion, path: Path, fmt: str = "glb", skin: bool = False) -> int:
    """Write ``path`` as .glb (binary) or .gltf (JSON, buffer as a data URI); returns its size."""
    if fmt not in FORMATS:
        raise UsageError(f"--format {fmt}: use one of {', '.join(FORMATS)}")
    gltf = build_gltf(motion, skin)
    if fmt == "glb":
        data = b"".join(gltf.save_to_bytes())
    else:
        gltf.convert_buffers(_pygltflib().BufferFormat.DATAURI)
        data = gltf.gltf_to_json().encode("utf-8")
    write_atomic(path, data)
    return len(data)  # the bytes written: a pipe's size says nothing
