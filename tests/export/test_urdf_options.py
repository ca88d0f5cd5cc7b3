"""URDF export options: a floating base as ROS tools and Pinocchio expect, no massless links."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import mujoco
import numpy as np
import pytest
from conftest import CREATURES

from legdsl.check.source import check_model
from legdsl.cli import main
from legdsl.export.urdf import model_to_urdf


def test_a_free_base_is_the_root_link() -> None:
    model = check_model(CREATURES / "quadruped.leg")
    robot = ET.fromstring(model_to_urdf(model, base="free"))
    links = [link.get("name") for link in robot.iter("link")]
    joints = robot.findall("joint")
    assert "world" not in links
    assert not [j for j in joints if j.get("type") == "floating"]
    children = {j.find("child").get("link") for j in joints}
    roots = [name for name in links if name not in children]
    assert roots == [model.bodies[0].name]  # one tree, rooted at the trunk
    # every coordinate but the free root's is still a joint of the same name
    names = {j.get("name") for j in joints}
    assert {d.name for j in model.joints[1:] for d in j.dofs} <= names
    # the default is unchanged: a floating joint from a world link
    default = ET.fromstring(model_to_urdf(model))
    assert [j.get("name") for j in default.findall("joint") if j.get("type") == "floating"] == [
        "root"
    ]


@pytest.mark.parametrize("name", ["kangaroo", "quadruped"])
def test_with_link_mass_mujoco_loads_the_urdf_as_it_is(name: str) -> None:
    model = check_model(CREATURES / f"{name}.leg")
    with pytest.raises(ValueError, match="mass"):  # MuJoCo refuses the massless chain links
        mujoco.MjModel.from_xml_string(model_to_urdf(model))
    text = model_to_urdf(model, link_mass=1e-6)
    mj = mujoco.MjModel.from_xml_string(text)
    extra = sum(1 for link in ET.fromstring(text).iter("link") if "__" in link.get("name"))
    assert extra > 0
    total = mujoco.mj_getTotalmass(mj)
    assert total == pytest.approx(model.total_mass + 1e-6 * extra, rel=1e-9)
    assert np.all(mj.body_mass[1:] > 0)


def test_mujoco_welds_a_free_base_urdf_s_root_as_docs_export_says() -> None:
    # docs/export.md said MuJoCo loads the --link-mass URDF "as it is" with an example that
    # added --base free, which MuJoCo loads with the trunk welded to the world (nq 12, 10 kg)
    model = check_model(CREATURES / "quadruped.leg")
    world = mujoco.MjModel.from_xml_string(model_to_urdf(model, link_mass=1e-6))
    free = mujoco.MjModel.from_xml_string(model_to_urdf(model, "free", link_mass=1e-6))
    assert (world.nq, free.nq) == (19, 12)
    assert mujoco.mj_getTotalmass(world) == pytest.approx(20.000004)
    assert mujoco.mj_getTotalmass(free) == pytest.approx(10.000004)
    text = (Path(__file__).parents[2] / "docs" / "export.md").read_text()
    assert "--format urdf --base free --link-mass" not in text
    assert "`nq` 19, `nv` 18, 20.000004 kg" in text and "`nq` 12 and 10.000004 kg" in text


def test_cli_urdf_options(tmp_path: Path) -> None:
    out = tmp_path / "q.urdf"
    args = ["export", str(CREATURES / "quadruped.leg"), "--format", "urdf", "-o", str(out)]
    assert main([*args, "--base", "free", "--link-mass", "1e-6"]) == 0
    assert "floating" not in out.read_text()
    assert main(["export", str(CREATURES / "quadruped.leg"), "--format", "mjcf",
                 "-o", str(tmp_path / "q.xml"), "--base", "free"]) == 2  # fmt: skip
    assert main([*args, "--link-mass", "-1"]) == 2
    in_kg = out.read_text()  # the 1e-6 (kg) export above; -1 was refused
    assert main([*args, "--base", "free", "--link-mass", "0.001g"]) == 0  # a mass with its unit
    assert out.read_text() == in_kg and '<mass value="1e-06" />' in in_kg


def test_the_link_mass_is_a_mass(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """--link-mass took a bare float only ("0.001g" was "invalid float value")."""
    args = [
        "export",
        str(CREATURES / "quadruped.leg"),
        "--format",
        "urdf",
        "-o",
        str(tmp_path / "q.urdf"),
    ]
    assert main([*args, "--link-mass", "1mm"]) == 2
    assert "--link-mass is a mass" in capsys.readouterr().err
