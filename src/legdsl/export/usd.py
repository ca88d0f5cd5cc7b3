"""Export a run as USD (``.usda`` text or ``.usd`` binary crate) through Pixar's ``usd-core``.

The stage is z-up in metres, as legdsl is, so no axis turn is needed. Its
default prim ``/CREATURE`` is an ``Xform`` holding the link tree as nested
``Xform`` prims (each link a child of its parent link), each with
time-sampled ``xformOp:translate`` and ``xformOp:orient`` ops: the link's pose
relative to its parent, one sample per frame, so that the prims move the way
the joints do. Each link prim has a ``Mesh`` child ``shape`` (its drawing
shape, with normals, ``displayColor`` in linear RGB and an extent). The ground and terrain
are meshes under ``/CREATURE/ground``. Time codes are frame numbers from 0:
``timeCodesPerSecond`` and ``framesPerSecond`` are the frame rate, and
``startTimeCode``/``endTimeCode`` the run's first and last frames.
"""

from __future__ import annotations

import errno
import os
import re
import sys
from pathlib import Path
from typing import Any

import numpy as np

from legdsl import __version__
from legdsl.export.ending import ending, ending_text
from legdsl.export.gltf import local_poses
from legdsl.export.motion import Motion, frame_rate, free_name, ground_area
from legdsl.export.shapes import Mesh, body_mesh, ground_meshes, hex_rgb, srgb_to_linear
from legdsl.files import atomic_path, free_bytes, refused_in
from legdsl.lang.errors import UsageError
from legdsl.pipeline.optional import not_installed
from legdsl.pipeline.outputs import ROOM_FOR_USD, room_for

FORMATS = ("usd", "usda", "usdc")  # usdc: binary, as usd


def _pxr() -> Any:
    if "pxr" not in sys.modules:  # loaded once; what it took is no longer left
        room_for("export USD (usd-core)", ROOM_FOR_USD)
    try:
        from pxr import Gf, Sdf, Usd, UsdGeom, Vt
    except ImportError as e:
        if not not_installed(e, "pxr"):
            raise
        raise UsageError("exporting USD needs usd-core: pip install 'legdsl[export]'") from None
    return Gf, Sdf, Usd, UsdGeom, Vt


def prim_name(name: str) -> str:
    """A valid USD prim name for a legdsl name (they are identifiers already, but be safe)."""
    text = re.sub(r"[^A-Za-z0-9_]", "_", name)
    return text if text and not text[0].isdigit() else f"_{text}"


def _mesh(stage: Any, path: str, mesh: Mesh, color: str) -> None:
    Gf, _, _, UsdGeom, Vt = _pxr()
    prim = UsdGeom.Mesh.Define(stage, path)
    points = Vt.Vec3fArray.FromNumpy(np.ascontiguousarray(mesh.positions, dtype=np.float32))
    prim.CreatePointsAttr(points)
    prim.CreateFaceVertexCountsAttr(Vt.IntArray([3] * len(mesh.indices)))
    prim.CreateFaceVertexIndicesAttr(Vt.IntArray([int(i) for i in mesh.indices.reshape(-1)]))
    normals = Vt.Vec3fArray.FromNumpy(np.ascontiguousarray(mesh.normals, dtype=np.float32))
    prim.CreateNormalsAttr(normals)
    prim.SetNormalsInterpolation(UsdGeom.Tokens.vertex)
    prim.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    # linear Rec.709, USD's colour space where none is authored (as the glTF's baseColorFactor):
    # the .leg's sRGB numbers as they are were shown lighter and greyer (#d09863 for #a05020)
    linear = (srgb_to_linear(c) for c in hex_rgb(color))
    prim.CreateDisplayColorAttr(Vt.Vec3fArray([Gf.Vec3f(*linear)]))
    lo, hi = mesh.bounds
    prim.CreateExtentAttr(Vt.Vec3fArray([Gf.Vec3f(*map(float, lo)), Gf.Vec3f(*map(float, hi))]))


def build_stage(motion: Motion, path: Path) -> Any:
    """A new ``Usd.Stage`` at ``path`` holding the scene and its animation (not yet saved)."""
    Gf, Sdf, Usd, UsdGeom, _ = _pxr()
    layer = Sdf.Layer.CreateNew(
        str(path), args={"format": "usda"} if path.suffix == ".usda" else {}
    )
    stage = Usd.Stage.Open(layer)
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    fps = frame_rate(motion)
    stage.SetTimeCodesPerSecond(fps)
    stage.SetFramesPerSecond(fps)
    stage.SetStartTimeCode(0)
    stage.SetEndTimeCode(motion.frames - 1)
    layer.documentation = f"legdsl {__version__}: run of creature '{motion.creature}'"
    if told := ending(motion):  # a run that fell or was cut short says how it ended
        layer.documentation += f", which did not end ok: {ending_text(motion)}"
        layer.customLayerData = {f"legdsl:{key}": value for key, value in told.items()}

    top = f"/{prim_name(motion.creature)}"
    root = UsdGeom.Xform.Define(stage, top)
    Usd.ModelAPI(root.GetPrim()).SetKind("component")
    stage.SetDefaultPrim(root.GetPrim())

    translations, rotations = local_poses(motion)
    paths = link_paths(motion)
    for b, (body, path_b) in enumerate(zip(motion.bodies, paths, strict=True)):
        xform = UsdGeom.Xform.Define(stage, path_b)
        translate = xform.AddTranslateOp(UsdGeom.XformOp.PrecisionDouble)
        orient = xform.AddOrientOp(UsdGeom.XformOp.PrecisionDouble)
        for f in range(motion.frames):
            x, y, z, w = (float(v) for v in rotations[f, b])
            translate.Set(Gf.Vec3d(*(float(v) for v in translations[f, b])), Usd.TimeCode(f))
            orient.Set(Gf.Quatd(w, x, y, z), Usd.TimeCode(f))
        # the mesh steps aside for a child link and for a contact on the link (pinned by name)
        contacts = {
            prim_name(name)
            for name, on in zip(motion.contact_names, motion.contact_bodies, strict=True)
            if on == b and motion.contact_points is not None and motion.touching is not None
        }
        shape = f"{path_b}/{free_name('shape', children_of(path_b, paths) | contacts)}"
        _mesh(stage, shape, body_mesh(body), (body.color or "#9a9a9a").lower())
    _contact_prims(stage, motion, paths)

    ground = f"{top}/{free_name('ground', children_of(top, paths))}"
    UsdGeom.Xform.Define(stage, ground)
    for name, mesh, color in ground_meshes(motion.terrain, *ground_area(motion)):
        _mesh(stage, f"{ground}/{prim_name(name)}", mesh, color)
    return stage


def _contact_prims(stage: Any, motion: Motion, paths: list[str]) -> None:
    """An ``Xform`` per contact point under its link, at the point, with a time-sampled
    ``legdsl:touching`` (whether it touches the ground at each frame): a foot's soles, for
    pinning a foot while it stands."""
    Gf, Sdf, Usd, UsdGeom, _ = _pxr()
    if motion.contact_points is None or motion.touching is None:
        return
    for c, (name, b) in enumerate(zip(motion.contact_names, motion.contact_bodies, strict=True)):
        parent = paths[b]
        taken = {p.GetName() for p in stage.GetPrimAtPath(parent).GetChildren()}
        xform = UsdGeom.Xform.Define(stage, f"{parent}/{free_name(prim_name(name), taken)}")
        translate = xform.AddTranslateOp(UsdGeom.XformOp.PrecisionDouble)
        translate.Set(Gf.Vec3d(*(float(v) for v in motion.contact_points[c])))
        touching = xform.GetPrim().CreateAttribute(
            "legdsl:touching", Sdf.ValueTypeNames.Bool, custom=True
        )
        for f in range(motion.frames):
            touching.Set(bool(motion.touching[f, c]), Usd.TimeCode(f))


def children_of(parent: str, paths: list[str]) -> set[str]:
    """The names of the link prims right under ``parent``."""
    return {p.rsplit("/", 1)[1] for p in paths if p.rsplit("/", 1)[0] == parent}


def link_paths(motion: Motion) -> list[str]:
    """The prim path of each link, in ``motion.bodies`` order."""
    top = f"/{prim_name(motion.creature)}"
    paths: list[str] = []
    for b, body in enumerate(motion.bodies):
        parent = motion.parents[b]
        paths.append(f"{top if parent < 0 else paths[parent]}/{prim_name(body.name)}")
    return paths


def write_usd(motion: Motion, path: Path, fmt: str = "usd") -> int:
    """Write ``path`` as .usd (binary crate) or .usda (text); returns its size (the bytes
    written, as saved: a pipe's or /dev/null's own size says nothing)."""
    if fmt not in FORMATS:
        raise UsageError(f"--format {fmt}: use one of {', '.join(FORMATS)}")
    # The layer's format follows its extension: write under the right one, then rename.
    _pxr()  # usd-core missing, or too little memory to load it: said before anything is written
    from pxr import Tf

    with atomic_path(path, suffix=f".{fmt}") as tmp:
        try:  # USD creates the file at once, and writes it whole at the save
            stage = build_stage(motion, tmp)
            stage.GetRootLayer().Save()
        except Tf.ErrorException as e:  # the file system refused it (USD gives no errno)
            raise _unwritten(tmp, path, str(e)) from None
        del stage
        size = tmp.stat().st_size
    return size


# free space below which a refused save is taken for a full disk (USD gives no errno)
_NEARLY_FULL = 1 << 20


def _unwritten(tmp: Path, path: Path, said: str) -> Exception:
    """Why USD could not save ``tmp`` (``path`` to the user): a full disk as an ``OSError``
    (``legdsl.files`` says what to free), else what USD said."""
    disk = refused_in(said)
    if disk is None:
        free = free_bytes(tmp.parent)
        disk = errno.ENOSPC if free is not None and free < _NEARLY_FULL else None
    if disk is not None:
        return OSError(disk, os.strerror(disk), str(tmp))
    lines = [line.strip() for line in said.splitlines() if line.strip()]
    first = lines[0][-200:] if lines else "no reason given"
    return UsageError(
        f"cannot write {path}: the USD library failed to save it ({first}); "
        "check that disk, or write elsewhere"
    )
