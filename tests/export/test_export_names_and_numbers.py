"""An outside user's findings on the export commands' outputs: USD's binary suffix .usdc,
a folder made for -o (said), `export`'s format taken from -o's name, no digit separators in
numbers on the command line, and no advice to open /dev/null in a browser."""

from __future__ import annotations

from pathlib import Path

import pytest
from anim_runs import creature_run, generated_dir
from conftest import CREATURES

from legdsl.cli import main

GEN = ["--generated", str(generated_dir())]


@pytest.fixture(scope="module")
def hopper(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return creature_run("hopper", tmp_path_factory.mktemp("hop") / "run")


def test_usdc_is_written_as_binary_usd_and_usdz_is_refused_with_usd_names(
    hopper: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    pytest.importorskip("pxr")
    out = tmp_path / "x.usdc"
    assert main(["export-motion", str(hopper), "-o", str(out), *GEN]) == 0
    assert out.read_bytes()[:8] == b"PXR-USDC"
    assert main(["export-motion", str(hopper), "--format", "usd", "-o", str(out), *GEN]) == 0
    capsys.readouterr()
    assert main(["export-motion", str(hopper), "-o", str(tmp_path / "x.usdz"), *GEN]) == 2
    err = capsys.readouterr().err
    assert "a .usdz package is not written" in err and f"{tmp_path / 'x.usd'}" in err
    assert "GLB" not in err and not (tmp_path / "x.usdz").exists()


def test_a_missing_folder_of_an_output_is_made_and_said(
    hopper: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    capsys.readouterr()
    out = tmp_path / "new" / "a" / "x.glb"
    assert main(["export-motion", str(hopper), "-o", str(out), *GEN]) == 0
    said = capsys.readouterr().out
    assert f"legdsl: made directories {tmp_path / 'new'}/ to {tmp_path / 'new' / 'a'}/" in said
    assert out.is_file()
    urdf = tmp_path / "b" / "k.urdf"
    assert main(["export", str(CREATURES / "hopper.leg"), "-o", str(urdf)]) == 0
    assert f"made directory {tmp_path / 'b'}/" in capsys.readouterr().out
    assert main(["animate", str(hopper), "-o", str(tmp_path / "c" / "p.html"), *GEN]) == 0
    assert f"legdsl: made directory {tmp_path / 'c'}/" in capsys.readouterr().out
    assert main(["export-motion", str(hopper), "-o", str(tmp_path / "y.glb"), *GEN]) == 0
    assert "made" not in capsys.readouterr().out  # its folder was there


@pytest.mark.parametrize(
    ("name", "root"),
    [("k.urdf", "<robot"), ("k.xml", "<mujoco"), ("k.mjcf", "<mujoco"), ("k.URDF", "<robot")],
)
def test_export_takes_its_format_from_the_name(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], name: str, root: str
) -> None:
    out = tmp_path / name
    assert main(["export", str(CREATURES / "hopper.leg"), "-o", str(out)]) == 0
    assert root in out.read_text()


@pytest.mark.parametrize(
    ("argv", "said"),
    [
        (["-o", "k.sdf"], "-o k.sdf: the suffix .sdf says no format; name it .xml or .mjcf"),
        (["-o", "k"], "-o k: a name without a suffix says no format"),
        (["-o", "-"], "-o -: say the format: --format mjcf or --format urdf"),
        ([], "without -o, say the format: --format mjcf (NAME.xml) or --format urdf"),
    ],
)
def test_export_without_a_format_the_name_says_is_refused(
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
    argv: list[str],
    said: str,
) -> None:
    monkeypatch.chdir(tmp_path)
    assert main(["export", str(CREATURES / "hopper.leg"), *argv]) == 2
    assert said in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    ("command", "flag", "value"),
    [
        ("export-motion", "--fps", "6_0"),
        ("animate", "--fps", "6_0Hz"),
        ("animate", "--slow-motion", "1_0"),
        ("run", "--time", "1_0"),
        ("run", "--set", "speed=1_000.5m/s"),
        ("run", "--set", "speed=1m/s@0.1_5"),
    ],
)
def test_numbers_with_digit_separators_are_refused(
    hopper: Path,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    command: str,
    flag: str,
    value: str,
) -> None:
    # Python's float() reads '6_0' as 60: --fps 60_0 made 600 keyframes a second
    where = str(CREATURES / "hopper.leg") if command == "run" else str(hopper)
    argv = [command, where, flag, value, *GEN]
    if command == "run":
        argv += ["--controller", "hop", "--out", str(tmp_path / "r")]
    elif command == "animate" and flag == "--slow-motion":
        argv += ["--video", str(tmp_path / "v.mp4")]
    else:
        argv += ["-o", str(tmp_path / ("x.glb" if command == "export-motion" else "x.html"))]
    capsys.readouterr()
    try:
        status = main(argv)
    except SystemExit as e:  # argparse's own options (type=float) end the process
        status = e.code
    assert status == 2
    err = capsys.readouterr().err
    number = value.rpartition("@")[2] if "@" in value else value.partition("=")[2] or value
    number = number.removesuffix("Hz").removesuffix("m/s")
    assert f"'{number}' is not a number: write it with the digits 0-9, without '_'" in err
    assert "^" in err  # with a caret under it
    assert list(tmp_path.iterdir()) == []


def test_other_digits_than_0_to_9_are_refused(
    hopper: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    capsys.readouterr()
    argv = ["export-motion", str(hopper), "--fps", "\u0666\u0660", "-o", str(tmp_path / "x.glb")]
    assert main([*argv, *GEN]) == 2
    assert "is not a number" in capsys.readouterr().err


def test_a_player_written_to_a_device_is_not_to_be_opened_in_a_browser(
    hopper: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    capsys.readouterr()
    assert main(["animate", str(hopper), "-o", "/dev/null", *GEN]) == 0
    said = capsys.readouterr().out
    assert "legdsl: wrote /dev/null" in said and "browser" not in said


def test_replay_and_scale_say_the_folder_they_make(
    hopper: Path,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """`legdsl replay RUN --mujoco -o r2/sub/h1.mp4` and `legdsl scale FILE --by 2 -o
    sc/new/h2.leg` made their missing folders without a word, where plot, animate and the
    exports say `made directory DIR/`: they say it too."""
    from legdsl.export import mjreplay

    def render(run: Path, out: Path, *rest: object) -> int:  # MuJoCo's renderer stood in for
        out.parent.mkdir(parents=True, exist_ok=True)
        out.write_bytes(b"mp4")
        return 1

    monkeypatch.setattr(mjreplay, "render_mp4", render)
    capsys.readouterr()
    video = tmp_path / "r2" / "sub" / "h1.mp4"
    assert main(["replay", str(hopper), "--mujoco", "-o", str(video), "--fps", "10"]) == 0
    said = capsys.readouterr().out
    assert f"legdsl: made directories {tmp_path / 'r2'}/ to {video.parent}/" in said
    scaled = tmp_path / "sc" / "new" / "h2.leg"
    assert main(["scale", str(CREATURES / "hopper.leg"), "--by", "2", "-o", str(scaled)]) == 0
    said = capsys.readouterr().out
    assert said.index(f"made directories {tmp_path / 'sc'}/ to {scaled.parent}/") < said.index(
        f"wrote {scaled}"
    )
    assert main(["scale", str(CREATURES / "hopper.leg"), "--by", "3", "-o", str(scaled)]) == 0
    assert "made" not in capsys.readouterr().out  # its folder was there
