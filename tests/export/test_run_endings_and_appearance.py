"""An outside user's findings on the animation exports: a run that fell is exported saying so
(on standard error, in the glTF scene's extras and the USD layer's metadata), and a creature
changed only in its colours or drawing shapes is still drawn (as it is now), while any other
change refuses the run with the command that ran it, its --generated included."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from anim_runs import generated_dir
from conftest import CREATURES

from legdsl.cli import main


@pytest.fixture(scope="module")
def fell(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A hopper run that fell at 0.176 s (--fall-height 0.8), made from its own copy of
    hopper.leg with its modules in gen/ beside it."""
    home = tmp_path_factory.mktemp("fell")
    shutil.copy(CREATURES / "hopper.leg", home / "hopper.leg")
    shutil.copytree(generated_dir() / "hopper", home / "gen" / "hopper")
    argv = ["run", str(home / "hopper.leg"), "--controller", "hop", "--set", "speed=1m/s",
            "--time", "3", "--fall-height", "0.8", "--out", str(home / "runs" / "hfall"),
            "--generated", str(home / "gen")]  # fmt: skip
    assert main(argv) == 4  # it fell
    return home / "runs" / "hfall"


def test_an_export_of_a_run_that_fell_says_so(
    fell: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    pytest.importorskip("pygltflib")
    pytest.importorskip("pxr")
    import pygltflib
    from pxr import Sdf

    gen = ["--generated", str(fell.parent.parent / "gen")]
    capsys.readouterr()
    for name in ("h.glb", "h.usda", "h.bvh"):
        assert main(["export-motion", str(fell), "-o", str(tmp_path / name), *gen]) == 0
        err = capsys.readouterr().err
        assert f"the run in {fell} did not end ok (fell at t = 0.176 s: the root fell to" in err
        assert f"{tmp_path / name} shows its motion up to then" in err
    extras = pygltflib.GLTF2().load(str(tmp_path / "h.glb")).scenes[0].extras
    assert extras["status"] == "fell" and extras["ended_at"] == pytest.approx(0.176)
    assert extras["cause"].startswith("the root fell to")
    layer = Sdf.Layer.FindOrOpen(str(tmp_path / "h.usda"))
    assert layer.customLayerData["legdsl:status"] == "fell"
    assert layer.customLayerData["legdsl:ended_at"] == pytest.approx(0.176)
    assert "did not end ok: fell at t = 0.176 s" in layer.documentation


def test_an_interrupted_run_is_told_with_its_cause(
    fell: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    run = tmp_path / "int"
    shutil.copytree(fell, run)
    info = json.loads((run / "run.json").read_text())
    info.update(status="interrupted", cause="SIGINT (Ctrl-C)", ended_at=0.176,
                message="interrupted by SIGINT (Ctrl-C) at t = 0.176 s of 3 s; what was "
                "recorded up to then is kept")  # fmt: skip
    (run / "run.json").write_text(json.dumps(info))
    gen = ["--generated", str(fell.parent.parent / "gen")]
    capsys.readouterr()
    assert main(["animate", str(run), "-o", str(tmp_path / "a.html"), *gen]) == 0
    err = capsys.readouterr().err
    assert "did not end ok (interrupted at t = 0.176 s: SIGINT (Ctrl-C))" in err


def test_an_ok_run_says_nothing_of_its_ending(
    fell: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    pytest.importorskip("pygltflib")
    import pygltflib

    run = tmp_path / "ok"
    shutil.copytree(fell, run)
    info = json.loads((run / "run.json").read_text())
    info["status"] = "ok"
    (run / "run.json").write_text(json.dumps(info))
    gen = ["--generated", str(fell.parent.parent / "gen")]
    assert main(["export-motion", str(run), "-o", str(tmp_path / "ok.glb"), *gen]) == 0
    assert "did not end ok" not in capsys.readouterr().err
    assert "status" not in pygltflib.GLTF2().load(str(tmp_path / "ok.glb")).scenes[0].extras


def _changed(fell: Path, tmp_path: Path, old: str, new: str) -> tuple[Path, list[str]]:
    """A copy of the run and its hopper.leg (``old`` replaced by ``new``), and --generated."""
    home = tmp_path / "home"
    shutil.copytree(fell.parent.parent, home)
    leg = home / "hopper.leg"
    assert old in leg.read_text()
    leg.write_text(leg.read_text().replace(old, new))
    run = home / "runs" / "hfall"
    info = json.loads((run / "run.json").read_text())
    info["source"] = str(leg)
    info["generated"] = {"from_run": "../../gen", "absolute": str(home / "gen")}
    (run / "run.json").write_text(json.dumps(info))
    return run, ["--generated", str(home / "gen")]


def test_a_recoloured_or_reshaped_creature_is_drawn_as_it_is_now(
    fell: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    pytest.importorskip("pygltflib")
    import pygltflib

    run, gen = _changed(fell, tmp_path, '"#506880"', '"#ff0000"')
    leg = run.parent.parent / "hopper.leg"
    leg.write_text(leg.read_text().replace("shape cylinder(0.04 m)", "shape cylinder(0.06 m)"))
    out = tmp_path / "c.glb"
    assert main(["export-motion", str(run), "-o", str(out), *gen]) == 0, capsys.readouterr().err
    materials = [m.name for m in pygltflib.GLTF2().load(str(out)).materials]
    assert "#ff0000" in materials and "#506880" not in materials
    assert main(["animate", str(run), "-o", str(tmp_path / "c.html"), *gen]) == 0


@pytest.mark.parametrize(
    ("old", "new"),
    [
        ("mass 10 kg", "mass 11 kg"),  # dynamics
        ("contact toe", "contact sole"),  # a name
    ],
)
def test_any_other_change_is_refused_with_the_whole_command(
    fell: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], old: str, new: str
) -> None:
    run, gen = _changed(fell, tmp_path, old, new)
    if "sole" in new:  # the leg names its foot
        leg = run.parent.parent / "hopper.leg"
        leg.write_text(leg.read_text().replace("foot toe", "foot sole"))
    capsys.readouterr()
    assert main(["export-motion", str(run), "-o", str(tmp_path / "x.glb"), *gen]) == 2
    err = capsys.readouterr().err
    assert "has changed since the run" in err and "colours and drawing shapes" in err
    assert f"--generated {run.parent.parent / 'gen'} --out {run}" in err
    assert not (tmp_path / "x.glb").exists()
