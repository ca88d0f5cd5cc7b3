"""A file that uses every controller construct is accepted; what the checker keeps of it."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from legdsl.check.source import check_model
from legdsl.cli import main
from legdsl.ir.controller import Do
from legdsl.lang.errors import LegError

GOOD = Path(__file__).parents[1] / "good"


def test_hopper_with_every_construct_checks() -> None:
    m = check_model(GOOD / "hopper.leg")
    assert (m.planar, m.nq, m.nv) == (True, 5, 5)
    assert m.q_names == ("x", "z", "pitch", "hip", "slide")
    assert m.body("thigh").length == pytest.approx(0.4)  # 40 cm
    assert m.body("shank").mass == pytest.approx(0.5)  # 500 g
    assert m.ground is not None and m.ground.friction == pytest.approx(0.8)
    (hop,) = m.controllers
    assert hop.start == "FLIGHT"
    assert hop.state_names == ("FLIGHT", "LOADING", "COMPRESSION", "THRUST")
    assert {c.name: c.value for c in hop.inputs} == pytest.approx({"speed": 1.0})
    assert {c.name: c.value for c in hop.params} == pytest.approx({"k_speed": 0.05, "thrust": 0.02})
    assert dict(hop.bindings[0]) == {"active": ("main",), "spare": ("main",)}
    assert hop.record_names == ("t_down",)
    # Actions from the controller and from the file it uses, inlined where they are called.
    called = {s.action for state in hop.states for s in state.body if isinstance(s, Do)}
    assert called == {"lengthen", "place_foot"}
    tilt = next(a for a in m.actuators if a.name == "tilt")
    assert tilt.kind == "force" and tilt.rotary and tilt.max == pytest.approx(20.0)
    assert m.v0[2] == pytest.approx(0.0) and m.v0[0] == pytest.approx(0.5)
    assert m.joint("hip").dofs[0].limits == pytest.approx((-math.pi / 3, math.pi / 3))


def test_cli_check_reports_the_controller(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["check", str(GOOD / "hopper.leg")]) == 0
    assert "controllers: hop" in capsys.readouterr().out


def test_crlf_and_cr_line_ends_read_as_newlines(tmp_path: Path) -> None:
    text = (GOOD / "hopper.leg").read_text(encoding="utf-8")
    (tmp_path / "actions.leg").write_text((GOOD / "actions.leg").read_text(encoding="utf-8"))
    for name, ending in (("crlf.leg", "\r\n"), ("cr.leg", "\r")):
        path = tmp_path / name
        path.write_bytes(text.replace("\n", ending).encode("utf-8"))
        assert check_model(path).nv == 5


def test_byte_order_mark_is_skipped_and_control_characters_are_named(tmp_path: Path) -> None:
    text = "creature a {\n  planar\n  body b free { mass 1 kg  inertia 1 kg*m^2 }\n}\n"
    bom = tmp_path / "bom.leg"
    bom.write_bytes(b"\xef\xbb\xbf" + text.encode("utf-8"))
    assert check_model(bom).nv == 3
    nul = tmp_path / "nul.leg"
    nul.write_bytes(text.replace("planar", "planar\x00").encode("utf-8"))
    with pytest.raises(LegError) as info:
        check_model(nul)
    (d,) = info.value.diagnostics
    assert (d.span.line, d.span.col) == (2, 9)
    assert d.message.startswith("a control character (U+0000) stands here: remove it")


def test_an_axis_of_huge_components_is_normalised(tmp_path: Path) -> None:
    """Its squares overflow: sqrt(inf) divided it into the axis (0, 0, 0), silently."""
    path = tmp_path / "axis.leg"
    path.write_text(
        "creature a {\n  spatial\n  body b free { mass 1 kg  inertia (1, 1, 1) kg*m^2 }\n"
        "  body c on b via revolute j { axis (1e200, 1e200, 0)  mass 1 kg  "
        "inertia (1, 1, 1) kg*m^2 }\n}\n"
    )
    (dof,) = check_model(path).joint("j").dofs
    assert dof.axis == pytest.approx((math.sqrt(0.5), math.sqrt(0.5), 0.0))


@pytest.mark.parametrize(
    ("axis", "expected"),
    [("(1e-300, 0, 0)", (1.0, 0.0, 0.0)), ("(3e-320, 0, -3e-320)", (0.5**0.5, 0.0, -(0.5**0.5)))],
)
def test_an_axis_of_tiny_components_is_a_direction(
    tmp_path: Path, axis: str, expected: tuple[float, float, float]
) -> None:
    """A direction has no length to be too short: '(1e-300, 0, 0)' was refused as of zero
    length (its norm under 1e-12); scaled by its largest component it is x."""
    path = tmp_path / "axis.leg"
    path.write_text(
        "creature a {\n  spatial\n  body b free { mass 1 kg  inertia (1, 1, 1) kg*m^2 }\n"
        f"  body c on b via revolute j {{ axis {axis}  mass 1 kg  "
        "inertia (1, 1, 1) kg*m^2 }\n}\n"
    )
    (dof,) = check_model(path).joint("j").dofs
    assert dof.axis == pytest.approx(expected)


def test_a_file_that_is_not_utf8_is_reported_at_the_bad_byte(tmp_path: Path) -> None:
    path = tmp_path / "latin1.leg"
    path.write_bytes(b"creature a {\n  planar # caf\xe9\n}\n")
    with pytest.raises(LegError) as info:
        check_model(path)
    (d,) = info.value.diagnostics
    assert (d.span.line, d.span.col) == (2, 15)
    assert d.message.startswith("the file is not UTF-8 text")


def test_unreadable_paths_are_user_errors(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["check", str(tmp_path), str(tmp_path / "missing.leg")]) == 2
    err = capsys.readouterr().err
    assert f"{tmp_path}: error: cannot read {tmp_path}: " in err  # a directory
    assert f"{tmp_path / 'missing.leg'}: error: no such file" in err
    assert "internal error" not in err
