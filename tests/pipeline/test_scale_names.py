"""``legdsl scale``'s names and the file it leaves: the scaled creature's name fits the 64
characters a name may have (a valid 64-character name became NAME_x2, 67, and the file was
written, then refused by the tool's own check and left on disk), ``--name`` chooses it, and a
scaled file that would not pass ``legdsl check`` is never written (docs/scaling.md)."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from conftest import CREATURES, ROOT

from legdsl.check.source import check_file
from legdsl.check.values import MAX_NAME
from legdsl.cli import main
from legdsl.lang import scaling

LONG = "a" * MAX_NAME
TRUNK = "body trunk free { mass 10 kg inertia 0.4 kg*m^2 }"


def _creature(name: str) -> str:
    return (
        f"creature {name} {{ planar {TRUNK}\n"
        "  body thigh on trunk via revolute hip { length 0.3 m mass 1 kg inertia 0.01 kg*m^2 }\n"
        "  actuator hip_motor on hip torque(max = 10 N*m) }\n"
        f"controller c_{name[-3:]} for {name} {{\n"
        "  table { state A on time > 0.1 s: hip_motor.force = 1 N*m }\n}\n"
    )


def test_names_are_cut_where_the_checker_has_them_end() -> None:
    assert scaling.NAME_MOST == MAX_NAME
    assert scaling.scale_name("kangaroo", 2) == "kangaroo_x2"
    assert scaling.scale_name(LONG, 2) == "a" * 61 + "_x2"
    assert len(scaling.scale_name(LONG, 0.123456789)) == MAX_NAME


@pytest.mark.parametrize(("by", "suffix"), [("2", "_x2"), ("0.123456789", "_x0_123456789")])
def test_a_creature_of_the_longest_name_scales_into_a_file_that_checks(
    by: str, suffix: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    source = tmp_path / "long.leg"
    source.write_text(f"creature {LONG} {{ planar {TRUNK} }}\n")
    out = tmp_path / "long_scaled.leg"
    assert main(["scale", str(source), "--by", by, "-o", str(out)]) == 0
    (model,) = check_file(out)
    assert model.name == LONG[: MAX_NAME - len(suffix)] + suffix
    err = capsys.readouterr().err
    assert f"{LONG}{suffix} would pass 64 characters; choose its name with --name NEW" in err
    assert main(["scale", str(source), "--by", by, "-o", str(out), "--name", "big"]) == 0
    assert [m.name for m in check_file(out)] == ["big"]
    assert "would pass" not in capsys.readouterr().err


def test_name_chooses_the_scaled_creatures_name(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "big.leg"
    hopper = str(CREATURES / "hopper.leg")
    assert main(["scale", hopper, "--by", "2", "-o", str(out), "--name", "hopper_big"]) == 0
    (model,) = check_file(out)
    assert model.name == "hopper_big"
    assert [c.name for c in model.controllers] == [
        c.name for c in check_file(hopper)[0].controllers
    ]
    out.unlink()
    for name, words in [
        ("2big", "a creature's name is a letter or _ followed by letters, digits and _"),
        ("b" * 65, "this name is 65 characters long; a creature's name has at most 64"),
        ("big-one", "a creature's name is a letter or _"),
        ("other=big", "has no creature 'other' (its creatures: hopper)"),
        ("hopper=", "a creature's name is a letter or _"),
    ]:
        assert main(["scale", hopper, "--by", "2", "-o", str(out), "--name", name]) == 2
        assert f"legdsl: --name {name}: " in (err := capsys.readouterr().err) and words in err
        assert not out.exists()
    args = ["scale", hopper, "--by", "2", "-o", str(out), "--name", "a", "--name", "hopper=b"]
    assert main(args) == 2
    assert "creature hopper is named twice (also a)" in capsys.readouterr().err
    lib = tmp_path / "actions.leg"
    shutil.copy(ROOT / "tests" / "good" / "actions.leg", lib)
    assert main(["scale", str(lib), "--by", "2", "-o", str(out), "--name", "x"]) == 2
    assert "has no creature to name" in capsys.readouterr().err


def test_several_creatures_each_get_a_name_that_fits_and_their_controllers_follow(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    one, two = "b" * 62 + "_1", "b" * 62 + "_2"  # cut to fit, both are b*61 + "_x2"
    source = tmp_path / "two.leg"
    source.write_text(_creature(one) + _creature(two) + _creature("short"))
    assert [m.name for m in check_file(source)] == [one, two, "short"]
    out = tmp_path / "two_x2.leg"
    scale = ["scale", str(source), "--by", "2", "-o", str(out)]
    assert main(scale) == 2
    err = capsys.readouterr().err
    cut = "b" * 61 + "_x2"
    assert f"creatures {one} and {two} of {source} would both be named {cut} once scaled" in err
    assert f"name them with --name {one}=NEW --name {two}=NEW" in err
    assert not out.exists()
    assert main([*scale, "--name", "big"]) == 2
    assert f"has 3 creatures ({one}, {two}, short); say which with --name OLD=NEW" in (
        capsys.readouterr().err
    )
    assert main([*scale, "--name", f"{one}=big"]) == 0
    models = {m.name: m for m in check_file(out)}
    assert list(models) == ["big", cut, "short_x2"]
    assert [c.name for c in models["big"].controllers] == ["c_b_1"]
    assert [c.name for c in models[cut].controllers] == ["c_b_2"]
    assert [c.name for c in models["short_x2"].controllers] == ["c_ort"]
    assert f"note: creature {two} scaled is named {cut}" in capsys.readouterr().err


def test_a_name_given_that_another_creature_has_is_told_so_not_as_a_cut(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--name hopper=pogo_x2, the name creature pogo gets scaled, was told as two names cut to
    fit 64 characters, and to rename pogo: nothing was cut, and the name given is the one."""
    source = tmp_path / "two.leg"
    source.write_text(_creature("hopper") + _creature("pogo"))
    scale = ["scale", str(source), "--by", "2", "-o", str(tmp_path / "out.leg")]
    for names, other, how in [(["hopper=pogo_x2"], "pogo", "its name scaled"),
                              (["pogo=hopper_x2"], "hopper", "its name scaled"),
                              (["hopper=z", "pogo=z"], "pogo", "given with --name too")]:  # fmt: skip
        assert main([*scale, *(a for n in names for a in ("--name", n))]) == 2
        err = capsys.readouterr().err
        taken = names[0].partition("=")[2]
        assert f"--name {names[0]}: {taken} is also creature {other}'s name ({how})" in err
        assert "64 characters" not in err and f"give {names[0].partition('=')[0]} another" in err


def test_a_name_given_that_a_creature_of_the_file_has_unscaled_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--name pogo=hopper gave the scaled pogo the unscaled hopper's name (and --name myhop
    a lone creature its own), so its generated/hopper/ and runs were the unscaled one's."""
    two = tmp_path / "two.leg"
    two.write_text(_creature("hopper") + _creature("pogo"))
    one = tmp_path / "myhop.leg"
    one.write_text(_creature("myhop"))
    out = tmp_path / "out.leg"
    for source, name, taken in [(two, "pogo=hopper", "hopper"), (two, "pogo=pogo", "pogo"),
                                (one, "myhop", "myhop")]:  # fmt: skip
        assert main(["scale", str(source), "--by", "2", "-o", str(out), "--name", name]) == 2
        err = capsys.readouterr().err
        assert f"--name {name}: {taken} is the name of {source}'s creature {taken}, unscaled" in err
        assert "Traceback" not in err and not out.exists()
    assert main(["scale", str(two), "--by", "2", "-o", str(out), "--name", "pogo=hopper2"]) == 0
    assert [m.name for m in check_file(out)] == ["hopper_x2", "hopper2"]


def test_a_creature_that_uses_a_file_is_named_and_checked_from_its_new_folder(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    dachs = ROOT / "tests" / "good" / "outside" / "dachs.leg"
    out = tmp_path / "deep" / "dachs_small.leg"
    out.parent.mkdir()
    assert main(["scale", str(dachs), "--by", "0.5", "-o", str(out), "--name", "dachs_s"]) == 0
    assert [m.name for m in check_file(out)] == ["dachs_s"]
    assert "quadruped.leg, which it uses, is not scaled" in capsys.readouterr().err


def test_a_scaled_file_that_would_fail_its_check_is_never_written(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """Checked before it is written (an OUT already there is left as it was)."""
    from legdsl.pipeline import scale_cli

    real = scale_cli.scale_source

    def broken(*args: object, **kwargs: object) -> str:
        text = real(*args, **kwargs)  # type: ignore[arg-type]
        return text.replace("mass 640 kg", "mass 640 s")

    monkeypatch.setattr(scale_cli, "scale_source", broken)
    source = tmp_path / "one.leg"
    source.write_text(f"creature one {{ planar {TRUNK} }}\n")
    out = tmp_path / "one_x4.leg"
    assert main(["scale", str(source), "--by", "4", "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert f"{out}:3:" in err and "mass 640 s" in err
    assert f"legdsl: -o {out}: not written: the scaled file would not pass legdsl check" in err
    assert not out.exists()
    out.write_text("kept\n")
    assert main(["scale", str(source), "--by", "4", "-o", str(out)]) == 2
    assert out.read_text() == "kept\n"
