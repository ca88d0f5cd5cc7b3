"""Commands under a memory limit (``ulimit -v``) too low for what they load: ``legdsl plot``
at 220 MB spun for ever (Python short of memory while importing matplotlib, deaf to
SIGTERM), ``export-motion --format usda`` below about 1.2 GB died of a segmentation fault with
nothing said, a library that could not be mapped was "not installed", and a trajectory.npz
that could not be read for memory was "damaged: run the creature again". Each is now one line
that says to raise the limit; the failures are simulated, the limit is not set."""

from __future__ import annotations

import importlib.abc
import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import CREATURES

import legdsl.sim.recorder as recorder
from legdsl.cli import main


@pytest.fixture(scope="module")
def run(generated: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("limits") / "run"
    argv = ["run", str(CREATURES / "hopper.leg"), "--time", "0.2", "--generated", str(generated)]
    assert main([*argv, "--out", str(out)]) == 0
    return out


def _left(monkeypatch: pytest.MonkeyPatch, megabytes: int) -> None:
    monkeypatch.setattr(recorder, "address_space_left", lambda: megabytes * 2**20)


def test_plot_refuses_to_draw_without_room_for_matplotlib(
    run: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    _left(monkeypatch, 28)
    assert main(["plot", str(run), "-o", str(tmp_path / "f.png")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("legdsl: out of memory to draw the run: the memory limit (ulimit -v)")
    assert "raise it" in err and list(tmp_path.iterdir()) == []


def test_usd_export_refuses_without_room_for_usd_core(
    run: Path,
    tmp_path: Path,
    generated: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:
    _left(monkeypatch, 850)
    monkeypatch.delitem(sys.modules, "pxr", raising=False)  # as in a new process
    out = tmp_path / "m.usda"
    argv = ["export-motion", str(run), "--format", "usda", "-o", str(out)]
    assert main([*argv, "--generated", str(generated)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("legdsl: out of memory to export USD (usd-core)"), err
    assert not out.exists()


class _Unmappable(importlib.abc.MetaPathFinder):
    """pygltflib installed but not loadable, as under ulimit -v."""

    def find_spec(self, name: str, *_: object) -> None:
        if name == "pygltflib":
            raise ImportError("failed to map segment from shared object", name=name)


def test_a_library_that_cannot_be_loaded_is_not_said_to_be_missing(
    run: Path,
    tmp_path: Path,
    generated: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:
    monkeypatch.delitem(sys.modules, "pygltflib", raising=False)
    monkeypatch.setattr(sys, "meta_path", [_Unmappable(), *sys.meta_path])
    argv = ["export-motion", str(run), "--format", "glb", "-o", str(tmp_path / "m.glb")]
    assert main([*argv, "--generated", str(generated)]) == 2
    err = capsys.readouterr().err
    assert "pip install 'legdsl[export]'" not in err
    assert "cannot load pygltflib (failed to map segment" in err and "ulimit -v" in err


def test_a_missing_library_is_still_said_to_be_missing(
    run: Path,
    tmp_path: Path,
    generated: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:
    monkeypatch.setitem(sys.modules, "pygltflib", None)  # import raises ModuleNotFoundError
    argv = ["export-motion", str(run), "--format", "glb", "-o", str(tmp_path / "m.glb")]
    assert main([*argv, "--generated", str(generated)]) == 2
    assert "needs pygltflib: pip install 'legdsl[export]'" in capsys.readouterr().err


def test_a_trajectory_read_short_of_memory_is_not_called_damaged(
    run: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    def refused(*_: object, **__: object) -> object:
        raise MemoryError("Unable to allocate output buffer.")

    monkeypatch.setattr(np, "load", refused)
    assert main(["metrics", str(run)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("legdsl: out of memory"), err
    assert "run the creature again" not in err


def test_a_sweep_whose_heat_map_cannot_be_drawn_says_its_table_is_whole(
    tmp_path: Path,
    generated: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:
    import legdsl.api.sweep_cli as sweep_cli

    def unmappable(*_: object) -> None:
        raise ImportError("ft2font.so: failed to map segment from shared object", name="ft2font")

    monkeypatch.setattr(sweep_cli, "plot_sweep", unmappable)
    out = tmp_path / "sweep"
    argv = ["sweep", str(CREATURES / "hopper.leg"), "--controller", "hop", "--grid",
            "speed=0.5:1:2", "--time", "0.2", "--from", "0.1", "--jobs", "1"]  # fmt: skip
    assert main([*argv, "--generated", str(generated), "--out", str(out)]) == 2
    said = capsys.readouterr()
    assert said.out.startswith("2 runs (") and "sweep.png" not in said.out
    assert "its table is whole, its heat map not drawn: cannot load ft2font" in said.err
    assert "Traceback" not in said.err and len(said.err.splitlines()) == 1
    assert len((out / "sweep.csv").read_text().splitlines()) == 3
    assert not (out / "sweep.png").exists()


def test_a_tune_whose_plot_cannot_be_drawn_keeps_and_names_its_files(
    tmp_path: Path,
    generated: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:
    import legdsl.api.tune_cli as tune_cli

    def short(*_: object, **__: object) -> None:
        raise MemoryError

    monkeypatch.setattr(tune_cli, "plot_history", short)
    out = tmp_path / "tune"
    argv = ["tune", str(CREATURES / "hopper.leg"), "--controller", "hop", "--param",
            "k_speed=0.02:0.2", "--speeds", "1", "--time", "0.3", "--from", "0.1",
            "--generations", "1", "--popsize", "2", "--jobs", "1"]  # fmt: skip
    assert main([*argv, "--generated", str(generated), "--out", str(out)]) == 2
    said = capsys.readouterr()
    assert "tune.json" in said.out and "tune.png" not in said.out.splitlines()[-1]
    assert said.err.splitlines()[-1] == (
        "legdsl: tune: tune.png not drawn: out of memory to draw the convergence plot: "
        "raise the memory limit (ulimit -v) and run again"
    )
    assert (out / "tune.json").is_file() and (out / "hopper.leg").is_file()


def test_ffmpeg_short_of_memory_is_not_an_internal_error(
    run: Path,
    tmp_path: Path,
    generated: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:
    """ffmpeg inherits ulimit -v: x264 could not allocate, "internal error (RuntimeError...)"."""
    import legdsl.export.video as video

    ffmpeg = tmp_path / "ffmpeg"
    ffmpeg.write_text(
        "#!/bin/sh\ncat > /dev/null\necho 'x264 [error]: malloc of size 2029952 failed' >&2\n"
        "echo 'Error encoding a frame: Generic error in an external library' >&2\nexit 187\n"
    )
    ffmpeg.chmod(0o755)
    monkeypatch.setattr(video, "ffmpeg_exe", lambda: str(ffmpeg))
    out = tmp_path / "v.mp4"
    assert main(["animate", str(run), "--video", str(out), "--generated", str(generated)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(
        "legdsl: ffmpeg ran out of memory encoding the video (it said: x264 [error]: malloc of"
    ), err
    assert "ulimit -v" in err and "internal error" not in err
    assert {p.name for p in tmp_path.iterdir()} == {"ffmpeg"}


def test_mujoco_short_of_memory_is_not_an_internal_error(
    run: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """``replay --mujoco -o`` at 280 MB: "internal error (FatalError: Could not allocate
    memory)"; at 320 MB OpenGL failed for want of room, and only EGL was blamed."""
    mujoco = pytest.importorskip("mujoco")

    def no_arena(*_: object) -> None:
        raise mujoco.FatalError("Could not allocate memory")

    monkeypatch.setattr(mujoco, "MjData", no_arena)
    assert main(["replay", str(run), "--mujoco", "-o", str(tmp_path / "r.mp4")]) == 2
    assert capsys.readouterr().err.startswith("legdsl: out of memory: raise the memory limit")
    monkeypatch.undo()

    def no_context(*_: object) -> None:
        raise RuntimeError("Cannot initialize a EGL device display")

    _left(monkeypatch, 40)
    monkeypatch.setattr(mujoco, "Renderer", no_context)
    assert main(["replay", str(run), "--mujoco", "-o", str(tmp_path / "r.mp4")]) == 2
    err = capsys.readouterr().err
    assert "could not start" in err and err.rstrip().endswith(
        "or raise the memory limit (ulimit -v), which OpenGL shares"
    )
    assert list(tmp_path.iterdir()) == []


def test_too_little_memory_to_start_does_not_ask_for_a_shorter_time(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """``legdsl check`` at 180 MB said "or ask for less (a shorter --time, ...)"."""
    import legdsl.cli as cli

    def short() -> None:
        raise MemoryError

    monkeypatch.setattr(cli, "_parser", short)
    assert main(["check", str(CREATURES / "hopper.leg")]) == 2
    assert capsys.readouterr().err == (
        "legdsl: out of memory to load legdsl and its libraries (numpy, sympy): raise the memory "
        "limit (ulimit -v) and run again\n"
    )


def test_plot_short_of_memory_asks_for_a_shorter_window(
    run: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """A long run plotted at 300 MB: "ask for less (a shorter --time, ...)", options plot has
    not; its own are --from and --to."""
    import legdsl.analysis.plot as plot

    def short(*_: object) -> None:
        raise MemoryError

    monkeypatch.setattr(plot, "plot_run", short)
    assert main(["plot", str(run), "-o", str(tmp_path / "f.png")]) == 2
    assert capsys.readouterr().err == (
        "legdsl: out of memory: raise the memory limit (ulimit -v) or ask for less (a shorter "
        "window: --from T, --to T)\n"
    )
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    ("command", "advice"),
    [
        (
            "animate",
            "or ask for less (fewer frames: a lower --fps, e.g. --fps 10, or a video's lower "
            "--slow-motion)\n",
        ),
        ("export-motion", "or ask for less (fewer keyframes: a lower --fps, e.g. --fps 10)\n"),
    ],
)
def test_a_player_short_of_memory_asks_for_fewer_frames(
    run: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str], command: str, advice: str,
) -> None:  # fmt: skip
    """``animate`` of a 300 s run at 800 MB was told "(a shorter --time, a lower
    --record-rate)", legdsl run's options; its own --fps is what stores fewer frames."""
    import legdsl.export.motion as motion

    def short(*_: object, **__: object) -> None:
        raise MemoryError

    monkeypatch.setattr(motion, "load_motion", short)
    out = tmp_path / ("p.html" if command == "animate" else "m.glb")
    assert main([command, str(run), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err == f"legdsl: out of memory: raise the memory limit (ulimit -v) {advice}"
    assert "--time" not in err and list(tmp_path.iterdir()) == []


def test_a_command_without_options_to_ask_less_is_told_the_limit_alone(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """``legdsl compile`` has no --time nor --record-rate to lower."""
    import legdsl.cli as cli

    def short(*_: object) -> int:
        raise MemoryError

    monkeypatch.setattr(cli, "_cmd_compile", short)
    assert main(["compile", str(CREATURES / "hopper.leg"), "-o", str(tmp_path)]) == 2
    assert capsys.readouterr().err == (
        "legdsl: out of memory: raise the memory limit (ulimit -v) and run again\n"
    )


def test_a_tune_short_of_memory_is_told_its_population_too() -> None:
    """A tune holds a generation's runs at once: `--popsize 100000000` ran out of memory and was
    told only 'a shorter --time, fewer --jobs'."""
    from legdsl.cli.process import out_of_memory

    assert "a smaller --popsize" in out_of_memory("tune")
    assert "--popsize" not in out_of_memory("sweep")
