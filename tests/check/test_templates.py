"""Templates and their mirrors (docs/language.md, "Templates"): an instance checks to the
model its template written out by hand gives, and a mirror is the reflection of the part."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

from legdsl.check.source import check_model
from legdsl.cli import main
from legdsl.codegen.fingerprints import _clean
from legdsl.ir.model import Model
from legdsl.pipeline.compile import compile_model
from tests.conftest import load_module

ROOT = Path(__file__).resolve().parents[2]
GOOD = ROOT / "tests" / "good"


def plain(model: Model) -> dict[str, Any]:
    """The model without spans, its file's name, its controllers and its scenes (runs)."""
    out = _clean(model)
    del out["source"], out["controllers"], out["scenes"]
    return out


@pytest.mark.parametrize("name", ["quadruped", "biped"])
def test_shipped_templates_give_the_hand_written_models(name: str) -> None:
    shipped = check_model(ROOT / "creatures" / f"{name}.leg")
    assert plain(shipped) == plain(check_model(GOOD / f"{name}_by_hand.leg"))


def creature_lines(path: Path) -> int:
    lines = path.read_text(encoding="utf-8").split("\n")
    start = next(i for i, line in enumerate(lines) if line.startswith("creature "))
    end = next(i for i, line in enumerate(lines) if i > start and line == "}")
    return end - start + 1


def test_the_shipped_creatures_are_shorter() -> None:
    quadruped = creature_lines(ROOT / "creatures" / "quadruped.leg")  # its controllers aside
    assert quadruped <= 2 / 3 * creature_lines(GOOD / "quadruped_by_hand.leg")
    biped = creature_lines(ROOT / "creatures" / "biped.leg")
    assert biped < creature_lines(GOOD / "biped_by_hand.leg")


def test_a_mirrored_template_is_the_hand_written_mirror() -> None:
    template = check_model(GOOD / "mirror_template.leg")
    assert plain(template) == plain(check_model(GOOD / "mirror_by_hand.leg"))
    right = template.joint("shoulder_r").dofs[0]
    assert right.axis[0] < 0 and right.axis[1] > 0  # -M a for the hinge about (1, 2, 0.5)
    assert template.joint("elbow_r").dofs[0].limits == pytest.approx(
        (-np.radians(40), np.radians(10))
    )


def test_a_mirror_reflects_the_dynamics(tmp_path: Path) -> None:
    """Same mass matrix as the hand-written mirror at random states; and the mirrored arm
    at the reflected state has the mass matrix and bias forces of the arm not mirrored:
    M'(D q) = D M(q) D and h'(D q, D v) = D h(q, v), D flipping the coordinates whose sign
    the mirror negates (the gimbal's hinges about x and z)."""
    text = (GOOD / "mirror_template.leg").read_text(encoding="utf-8")
    assert " mirror sagittal" in text
    unmirrored = tmp_path / "unmirrored.leg"
    unmirrored.write_text(text.replace(" mirror sagittal", ""), encoding="utf-8")
    mods = []
    for path in (GOOD / "mirror_template.leg", GOOD / "mirror_by_hand.leg", unmirrored):
        compiled = compile_model(path)
        mods.append((compiled.model, load_module(compiled.text("dynamics.py"), compiled.name)))
    (model, mirrored), (_, by_hand), (_, plain_dyn) = mods
    flip = np.array([-1.0 if n in ("elbow_r_x", "elbow_r_z") else 1.0 for n in model.q_names])
    assert model.nq == model.nv == len(flip) == 8
    rng = np.random.default_rng(19)
    for _ in range(5):
        q, v = rng.uniform(-1, 1, model.nq), rng.uniform(-2, 2, model.nv)
        m = np.array(mirrored.mass_matrix(list(q)))
        np.testing.assert_allclose(m, np.array(by_hand.mass_matrix(list(q))), rtol=1e-12)
        reflected = np.array(mirrored.mass_matrix(list(flip * q)))
        expected = np.diag(flip) @ np.array(plain_dyn.mass_matrix(list(q))) @ np.diag(flip)
        np.testing.assert_allclose(reflected, expected, rtol=1e-10, atol=1e-12)
        h = np.array(mirrored.bias_forces(list(flip * q), list(flip * v)))
        h0 = np.array(plain_dyn.bias_forces(list(q), list(v)))
        np.testing.assert_allclose(h, flip * h0, rtol=1e-10, atol=1e-12)


PLANAR = """
creature hop {
  planar
  body trunk free { mass 5 kg  inertia 0.2 kg*m^2 }
  %s
}
"""
LEG = (
    "body thigh_%s on trunk via revolute hip_%s at %s {"
    " length 0.3 m  com (%s m, -0.1 m)  mass 1 kg  inertia 0.01 kg*m^2"
    " limits %s deg to %s deg  initial %s deg }\n"
    "actuator hip_%s_servo on hip_%s servo(kp = 10 N*m/rad, kv = 1 N*m*s/rad, setpoint = %s deg)"
)


def test_a_frontal_mirror_in_a_planar_creature(tmp_path: Path) -> None:
    """x -> -x: a hinge about y keeps its axis and its angle changes sign."""
    template = tmp_path / "template.leg"
    template.write_text(
        PLANAR
        % (
            "template leg(S, X) {\n"
            + LEG % ("S", "S", "X", "0.02", "-10", "40", "5", "S", "S", "7")
            + "\n}\ninstance front = leg(S = f, X = (0.2 m, 0 m))\n"
            "instance back = leg(S = b, X = (0.2 m, 0 m)) mirror frontal"
        ),
        encoding="utf-8",
    )
    by_hand = tmp_path / "by_hand.leg"
    by_hand.write_text(
        PLANAR
        % (
            LEG % ("f", "f", "(0.2 m, 0 m)", "0.02", "-10", "40", "5", "f", "f", "7")
            + "\n"
            + LEG % ("b", "b", "(-0.2 m, 0 m)", "-0.02", "-40", "10", "-5", "b", "b", "-7")
        ),
        encoding="utf-8",
    )
    assert plain(check_model(template)) == plain(check_model(by_hand))


def test_parameters_replace_whole_parts_of_names_only(tmp_path: Path) -> None:
    path = tmp_path / "names.leg"
    path.write_text(
        PLANAR
        % (
            "template leg(S) {\n"
            "  body thigh_S on trunk via revolute S_hip_SS at (0 m, 0 m) {"
            " mass 1 kg  inertia 0.01 kg*m^2 }\n"
            "}\ninstance a = leg(S = front)"
        ),
        encoding="utf-8",
    )
    model = check_model(path)
    assert [b.name for b in model.bodies] == ["trunk", "thigh_front"]
    assert model.joints[1].name == "front_hip_SS"


def test_show_prints_the_expanded_tree(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["show", str(ROOT / "creatures" / "quadruped.leg")]) == 0
    out = capsys.readouterr().out
    for leg in ("fl", "fr", "rl", "rr"):
        assert f"thigh_{leg}  via gimbal hip_{leg}" in out
        assert f"shank_{leg}  via prismatic leg_{leg}" in out


def test_a_part_outside_the_instance_at_the_tip_of_a_mirrored_body(tmp_path: Path) -> None:
    """A contact or body hung 'at tip' of a mirrored body is at the mirrored tip."""
    text = (GOOD / "mirror_template.leg").read_text(encoding="utf-8")
    extra = (
        "  contact knuckle on lower_r at tip\n"
        "  body finger on upper_r via revolute knuckle_joint at tip {"
        " mass 0.1 kg  inertia (0.001, 0.001, 0.001) kg*m^2 }\n}\n"
    )
    path = tmp_path / "outside.leg"
    path.write_text(text.removesuffix("}\n") + extra, encoding="utf-8")
    model = check_model(path)
    assert model.joint("knuckle_joint").origin == model.body("upper_r").tip
    knuckle = next(c for c in model.contacts if c.name == "knuckle")
    assert knuckle.point == model.body("lower_r").tip
    assert model.body("upper_r").tip[1] < 0  # the left arm's leans to +y


def test_a_mirrored_instance_at_the_tip_of_a_body_of_another(tmp_path: Path) -> None:
    """A mirrored hand on the mirrored arm's tip is at that tip (it was reflected twice, back
    to where the unmirrored arm's tip is), and one on an unmirrored body's tip stays there."""
    text = (GOOD / "mirror_template.leg").read_text(encoding="utf-8")
    extra = (
        "  template palm(S, ON) {\n"
        "    body palm_S on ON via revolute wrist_S at tip {"
        " axis (0, 1, 0)  length 0.1 m  direction (0.2, 0.5, -1)  com 0.05 m"
        "  mass 0.1 kg  inertia (0.001, 0.001, 0.001) kg*m^2 }\n"
        "    contact pad_S on ON at tip\n"
        "  }\n"
        "  instance pl = palm(S = l, ON = upper_l)\n"
        "  instance pr = palm(S = r, ON = upper_r) mirror sagittal\n"
        "  instance pb = palm(S = b, ON = lower_l) mirror sagittal\n}\n"
    )
    path = tmp_path / "hands.leg"
    path.write_text(text.removesuffix("}\n") + extra, encoding="utf-8")
    model = check_model(path)
    pads = {c.name: c.point for c in model.contacts}
    for side in "lr":
        assert model.joint(f"wrist_{side}").origin == model.body(f"upper_{side}").tip
        assert pads[f"pad_{side}"] == model.body(f"upper_{side}").tip
    assert model.joint("wrist_b").origin == pads["pad_b"] == model.body("lower_l").tip
    left, right = model.body("palm_l").direction, model.body("palm_r").direction
    assert right == (left[0], -left[1], left[2])  # the palm itself is mirrored


def test_an_instance_refused_for_its_arguments_is_the_only_error(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The quadruped's rear right leg without its HIP: the instance is the mistake, and the
    gaits' roles on leg 'rr' it would have declared are no news (each was an 'unknown leg
    'rr'' before it, two of them in a used file when the gaits came through 'use')."""
    text = (ROOT / "creatures" / "quadruped.leg").read_text(encoding="utf-8")
    rr = "instance rr = leg(S = rr, HIP = (-0.39 m, 0.12 m, 0 m)) mirror sagittal"
    assert rr in text
    leg = tmp_path / "quadruped.leg"
    leg.write_text(text.replace(rr, "instance rr = leg(S = rr) mirror sagittal"), "utf-8")
    assert main(["check", str(leg)]) == 2
    err = capsys.readouterr().err
    assert err.count("error:") == 1, err
    assert "instance 'rr' of template 'leg' does not give 'HIP'" in err


def test_parameters_named_like_words_of_the_language_leave_the_words(tmp_path: Path) -> None:
    """Parameters 'spring', 'mass', 'revolute' and 'k' are put in names and values only: the
    actuator's kind, the joint's kind, the property keys and the spring's argument names
    stay words (the kind 'spring' had become 'front_spring', and 'mass 0.5 kg' a mistake)."""
    path = tmp_path / "words.leg"
    path.write_text(
        PLANAR
        % (
            "template leg(S, spring, mass, revolute, k) {\n"
            "  body thigh_S on trunk via revolute hip_S at (0 m, 0 m) {"
            " length 0.3 m  mass mass  inertia 0.01 kg*m^2"
            "  limits -30 deg to 30 deg  stop k = 100 N*m/rad }\n"
            "  body shank_S on thigh_S via prismatic slide_S at tip {"
            " mass 0.5 kg  inertia 0.005 kg*m^2 }\n"
            "  actuator spring on slide_S spring(k = k, b = 5 N*s/m)\n"
            "}\n"
            "instance a = leg(S = a, spring = spring_a, mass = 2 kg, revolute = prismatic,"
            " k = 3000 N/m)\n"
            "instance b = leg(S = b, spring = spring_b, mass = 3 kg, revolute = prismatic,"
            " k = 4000 N/m)"
        ),
        encoding="utf-8",
    )
    model = check_model(path)
    assert [(b.name, b.mass) for b in model.bodies if b.name.startswith("thigh")] == [
        ("thigh_a", 2.0),
        ("thigh_b", 3.0),
    ]
    assert model.body("shank_a").mass == 0.5
    assert [(a.name, a.kind, dict(a.params)["k"]) for a in model.actuators] == [
        ("spring_a", "spring", 3000.0),
        ("spring_b", "spring", 4000.0),
    ]
    assert model.joint("hip_a").kind == "revolute"
    assert model.stops[0].k == 100.0


def test_a_whole_number_stands_in_a_name_after_its_first_part(tmp_path: Path) -> None:
    """`instance a1 = arm(S = 1)` with `body a_S` was refused 18 times ("given a value, not a
    name") though `a_1` is a name, and the controller's `s_1` was then told unknown with
    "did you mean 's_S'", the template's own text. A whole number after a name's first part
    makes the name as written by hand; a number that cannot is refused, with the fix."""
    text = """creature arms {
  planar
  gravity 0 m/s^2
  body base fixed at (0 m, 2 m) { mass 1 kg  inertia 0.1 kg*m^2 }
  template arm(S) {
    body a_S on base via revolute j_S { length 0.5 m  com 0.25 m  mass 1 kg  inertia 0.02 kg*m^2 }
    actuator s_S on j_S servo(kp = 2000 N*m/rad, kv = 60 N*m*s/rad)
  }
  instance a1 = arm(S = 1)
  instance a2 = arm(S = 2)
}
controller c { table { state A on time >= 0 s: s_1.setpoint = 30 deg; s_2.setpoint = 0 deg } }
"""
    path = tmp_path / "arms.leg"
    path.write_text(text)
    model = check_model(path)
    assert [b.name for b in model.bodies] == ["base", "a_1", "a_2"]
    assert [j.name for j in model.joints][-2:] == ["j_1", "j_2"]
    path.write_text(text.replace("S = 2", "S = 2.5"))
    with pytest.raises(Exception, match=r"cannot stand in the name 'a_S': give it a name"):
        check_model(path)
