"""USD export: validated by usd-core's own validators, read back by usd-core, poses compared with the run."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from anim_runs import creature_motion, creature_run, exported_into_a_pipe, generated_dir

from legdsl.cli import main
from legdsl.export.motion import Motion, frame_rate, quaternion_to_matrix
from legdsl.export.usd import link_paths, write_usd

pxr = pytest.importorskip("pxr", reason="usd-core is in the test extra: pip install '.[test]'")
from pxr import Usd, UsdGeom, UsdValidation  # noqa: E402


@pytest.fixture(scope="module", params=["kangaroo", "quadruped"])
def exported(request, tmp_path_factory) -> tuple[Motion, dict[str, Path]]:
    motion = creature_motion(request.param, tmp_path_factory.mktemp(request.param) / "run")
    out = tmp_path_factory.mktemp("usd")
    paths = {fmt: out / f"{request.param}.{fmt}" for fmt in ("usd", "usda")}
    for fmt, path in paths.items():
        assert write_usd(motion, path, fmt) == path.stat().st_size > 0
    return motion, paths


def validation_errors(stage) -> list[str]:
    """Every validator usd-core registers (what usdchecker runs), on ``stage``.

    usd-core 26 replaced ``UsdUtils.ComplianceChecker`` with the UsdValidation
    framework; where the old checker is still there it is run too.
    """
    registry = UsdValidation.ValidationRegistry()
    context = UsdValidation.ValidationContext(registry.GetOrLoadAllValidators())
    errors = [f"{e.GetName()}: {e.GetMessage()}" for e in context.Validate(stage)]
    from pxr import UsdUtils

    if hasattr(UsdUtils, "ComplianceChecker"):
        checker = UsdUtils.ComplianceChecker()
        checker.CheckCompliance(stage.GetRootLayer().realPath)
        errors += checker.GetErrors() + checker.GetFailedChecks()
    return errors


@pytest.mark.parametrize("fmt", ["usd", "usda"])
def test_usd_validators_find_nothing(exported, fmt: str) -> None:
    _, paths = exported
    stage = Usd.Stage.Open(str(paths[fmt]))
    assert validation_errors(stage) == []
    crate = paths[fmt].read_bytes()[:8]
    assert crate.startswith(b"PXR-USDC") if fmt == "usd" else crate.startswith(b"#usda")


def test_the_validators_are_not_vacuous(exported) -> None:
    _, paths = exported
    stage = Usd.Stage.Open(str(paths["usda"]))
    stage.GetRootLayer().ClearDefaultPrim()
    stage.GetRootLayer().pseudoRoot.ClearInfo("upAxis")
    assert validation_errors(stage)


def test_timeline_and_axes(exported) -> None:
    motion, paths = exported
    stage = Usd.Stage.Open(str(paths["usd"]))
    assert stage.GetTimeCodesPerSecond() == pytest.approx(frame_rate(motion))
    assert stage.GetFramesPerSecond() == pytest.approx(frame_rate(motion))
    assert stage.GetStartTimeCode() == 0 and stage.GetEndTimeCode() == motion.frames - 1
    assert UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.z
    assert UsdGeom.GetStageMetersPerUnit(stage) == 1.0
    assert stage.GetDefaultPrim().GetName() == motion.creature


def test_hierarchy_meshes_and_ground(exported) -> None:
    motion, paths = exported
    stage = Usd.Stage.Open(str(paths["usda"]))
    links = link_paths(motion)
    for b, body in enumerate(motion.bodies):
        prim = stage.GetPrimAtPath(links[b])
        assert prim.IsA(UsdGeom.Xform) and prim.GetName() == body.name
        parent = motion.parents[b]
        expected = f"/{motion.creature}" if parent < 0 else links[parent]
        assert str(prim.GetParent().GetPath()) == expected
        mesh = UsdGeom.Mesh(stage.GetPrimAtPath(f"{links[b]}/shape"))
        assert len(mesh.GetPointsAttr().Get()) > 0 and mesh.GetExtentAttr().Get()
        ops = UsdGeom.Xformable(prim).GetOrderedXformOps()
        assert [op.GetOpName() for op in ops] == ["xformOp:translate", "xformOp:orient"]
        assert all(op.GetNumTimeSamples() == motion.frames for op in ops)
    ground = stage.GetPrimAtPath(f"/{motion.creature}/ground")
    assert [c.GetName() for c in ground.GetChildren()][0] == "floor"


def test_display_colours_are_linear_as_the_gltfs(exported) -> None:
    """USD takes a displayColor with no colour space authored as linear Rec.709; the export
    wrote the .leg's sRGB numbers, shown lighter and greyer than the .leg's colour and the
    glTF's (linear) baseColorFactor."""
    from legdsl.export.gltf import build_gltf
    from legdsl.export.shapes import hex_rgb

    motion, paths = exported
    stage = Usd.Stage.Open(str(paths["usda"]))
    gltf = build_gltf(motion)
    nodes = {n.name: n for n in gltf.nodes}
    for body, link in zip(motion.bodies, link_paths(motion), strict=True):
        shown = UsdGeom.Mesh(stage.GetPrimAtPath(f"{link}/shape")).GetDisplayColorAttr().Get()[0]
        primitive = gltf.meshes[nodes[body.name].mesh].primitives[0]
        linear = gltf.materials[primitive.material].pbrMetallicRoughness.baseColorFactor[:3]
        assert np.allclose(list(shown), linear, atol=1e-6), body.name
        srgb = hex_rgb((body.color or "#9a9a9a").lower())
        assert not np.allclose(list(shown), srgb, atol=1e-3), body.name  # not the sRGB numbers


def test_time_samples_replay_the_run(exported) -> None:
    motion, paths = exported
    stage = Usd.Stage.Open(str(paths["usd"]))
    links = link_paths(motion)
    for f in range(0, motion.frames, 4):
        cache = UsdGeom.XformCache(Usd.TimeCode(f))
        for b in range(len(motion.bodies)):
            m = np.array(cache.GetLocalToWorldTransform(stage.GetPrimAtPath(links[b])))
            # Gf matrices act on row vectors: the translation is the last row
            assert np.allclose(m[3, :3], motion.positions[f, b], atol=1e-6)
            rot = quaternion_to_matrix(motion.quaternions[f, b])
            assert np.allclose(m[:3, :3].T, rot, atol=1e-6)


def test_cli_writes_usda(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    run = creature_run("kangaroo", tmp_path / "run")
    out = tmp_path / "k.usda"
    args = ["export-motion", str(run), "--format", "usda", "-o", str(out)]
    assert main([*args, "--generated", str(generated_dir())]) == 0
    assert out.read_text().startswith("#usda 1.0")
    assert "wrote" in capsys.readouterr().out
    bad = ["export-motion", str(run), "--format", "usd", "-o", str(tmp_path / "k2.usda")]
    assert main(bad) == 2


@pytest.mark.parametrize(("fmt", "head"), [("usda", b"#usda 1.0"), ("usd", b"PXR-USDC")])
def test_usd_into_a_pipe(tmp_path: Path, fmt: str, head: bytes) -> None:
    """USD takes a layer's format from its file's name: ``-o /dev/stdout`` failed in USD's
    SdfLayer ("fileFormat ''") and was told as a disk to check. Now it is written under its
    own name first, then copied into the pipe."""
    run = creature_run("kangaroo", tmp_path / "run")
    code, got = exported_into_a_pipe(run, fmt, tmp_path / "pipe")
    assert code == 0 and got.startswith(head)
    copy = tmp_path / f"copy.{fmt}"
    copy.write_bytes(got)
    stage = Usd.Stage.Open(str(copy))
    assert stage.GetEndTimeCode() > 0 and stage.GetPrimAtPath("/kangaroo").IsValid()


@pytest.mark.parametrize("fmt", ["usd", "usda"])
def test_the_size_said_is_what_went_into_a_pipe_or_dev_null(
    tmp_path: Path, fmt: str, capsys: pytest.CaptureFixture[str]
) -> None:
    """``-o /dev/stdout`` (or a pipe, or /dev/null) said "wrote /dev/stdout (0 B: ...)" for
    USD, the size read back from the path after the save, though the whole file was written."""
    from legdsl.export.animate import human_size

    run = creature_run("kangaroo", tmp_path / "run")
    capsys.readouterr()
    code, got = exported_into_a_pipe(run, fmt, tmp_path / "pipe")
    assert code == 0 and len(got) > 1024
    said = capsys.readouterr()
    assert f"wrote {tmp_path / 'pipe'} ({human_size(len(got))}: " in said.out + said.err
    args = ["export-motion", str(run), "--format", fmt, "-o", "/dev/null"]
    assert main([*args, "--generated", str(generated_dir())]) == 0
    said = capsys.readouterr()
    assert f"wrote /dev/null ({human_size(len(got))}: " in said.out + said.err
