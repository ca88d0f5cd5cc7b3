"""The disk refuses a write (full, a quota, an I/O error): legdsl says which file and what to
free, exits 2, and leaves no half-written file nor temporary one; an older file stays whole.

The refusal is simulated (``os.fsync`` or a tool's output raising it), so no test needs a
small file system mounted."""

from __future__ import annotations

import errno
import os
import stat
from pathlib import Path

import pytest

from legdsl.cli import main
from legdsl.files import atomic_path, is_leftover, write_atomic

ROOT = Path(__file__).resolve().parents[2]
HOPPER = str(ROOT / "creatures" / "hopper.leg")
REFUSALS = {
    errno.ENOSPC: "the disk is full",
    errno.EDQUOT: "quota is used up",
    errno.EIO: "input/output error",
}


def _refuse(monkeypatch: pytest.MonkeyPatch, number: int = errno.ENOSPC) -> None:
    """Every file legdsl writes whole (``write_atomic``) is refused at its fsync."""

    def full(fd: int) -> None:
        raise OSError(number, os.strerror(number))

    monkeypatch.setattr(os, "fsync", full)


def _run(capsys: pytest.CaptureFixture[str], argv: list[str]) -> tuple[int, str]:
    code = main(argv)
    err = capsys.readouterr().err
    assert "internal error" not in err and "Traceback" not in err, err
    return code, err


def _only(folder: Path, *names: str) -> None:
    """``folder`` holds ``names`` and nothing else (no temporary file)."""
    left = sorted(p.name for p in folder.iterdir())
    assert left == sorted(names), left
    assert not any(is_leftover(p) for p in folder.iterdir())


@pytest.mark.parametrize("number", list(REFUSALS), ids=["ENOSPC", "EDQUOT", "EIO"])
def test_a_refused_write_names_the_target_and_keeps_the_old_file(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, number: int
) -> None:
    target = tmp_path / "out.json"
    target.write_text("old")
    _refuse(monkeypatch, number)
    with pytest.raises(OSError) as caught:
        write_atomic(target, "new")
    assert caught.value.errno == number and caught.value.filename == str(target)
    assert REFUSALS[number] in caught.value.strerror.lower()
    assert target.read_text() == "old"
    _only(tmp_path, "out.json")


def test_a_write_that_fills_the_disk_inside_a_block_names_the_target(tmp_path: Path) -> None:
    target = tmp_path / "video.gif"
    with pytest.raises(OSError) as caught, atomic_path(target) as tmp:
        tmp.write_bytes(b"GIF8")
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))  # a library's write, unnamed
    assert caught.value.filename == str(target) and "disk is full" in caught.value.strerror
    _only(tmp_path)


def test_an_input_that_cannot_be_read_is_not_called_a_full_disk(tmp_path: Path) -> None:
    with pytest.raises(OSError) as caught, atomic_path(tmp_path / "out.bin"):
        raise OSError(errno.EIO, os.strerror(errno.EIO), "/some/input.npz")
    assert caught.value.filename == "/some/input.npz"


@pytest.fixture(scope="module")
def a_run(tmp_path_factory: pytest.TempPathFactory, generated: Path) -> Path:
    out = tmp_path_factory.mktemp("run") / "hopper"
    assert main(["run", HOPPER, "--time", "0.3", "--generated", str(generated),
                 "--out", str(out)]) == 0  # fmt: skip
    return out


@pytest.mark.parametrize(
    ("command", "name"),
    [
        (["export", HOPPER, "--format", "mjcf"], "hopper.xml"),
        (["export", HOPPER, "--format", "urdf"], "hopper.urdf"),
        (["export-motion", "RUN"], "motion.glb"),
        (["export-motion", "RUN"], "motion.gltf"),
        (["export-motion", "RUN"], "motion.bvh"),
        (["animate", "RUN"], "player.html"),
        (["scale", "--by", "2", HOPPER], "hopper_x2.leg"),
    ],
)
def test_an_export_on_a_full_disk_says_so_and_keeps_the_old_file(
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
    tmp_path: Path,
    a_run: Path,
    command: list[str],
    name: str,
) -> None:
    target = tmp_path / "out" / name
    target.parent.mkdir()
    target.write_text("old")
    _refuse(monkeypatch)
    argv = [str(a_run) if a == "RUN" else a for a in command] + ["-o", str(target)]
    code, err = _run(capsys, argv)
    assert code == 2, err
    assert str(target) in err and "disk is full" in err, err
    assert target.read_text() == "old"
    _only(target.parent, name)


def test_a_run_directory_on_a_full_disk_says_so(
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
    tmp_path: Path,
    generated: Path,
) -> None:
    out = tmp_path / "run"
    _refuse(monkeypatch, errno.EDQUOT)
    argv = ["run", HOPPER, "--time", "0.1", "--generated", str(generated), "--out", str(out)]
    code, err = _run(capsys, argv)
    assert code == 2 and str(out) in err and "quota is used up" in err, err
    assert not any(is_leftover(p) for p in out.iterdir())


def test_compile_on_a_full_disk_keeps_the_old_modules(
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
    tmp_path: Path,
    generated: Path,
) -> None:
    import shutil

    out = tmp_path / "gen"
    shutil.copytree(generated / "hopper", out / "hopper")
    before = {p.name: p.read_bytes() for p in (out / "hopper").iterdir()}
    _refuse(monkeypatch)
    code, err = _run(capsys, ["compile", HOPPER, "--out", str(out)])
    assert code == 2 and "disk is full" in err, err
    assert {p.name: p.read_bytes() for p in (out / "hopper").iterdir()} == before
    _only(out, "hopper")


# ffmpeg on a full disk: "Error writing trailer ...: No space left on device", and exit 0
FAKE_FFMPEG = """#!/bin/sh
for last; do :; done
cat > /dev/null
printf 'half' > "$last"
echo "Error writing trailer of $last: No space left on device" >&2
exit 0
"""


def test_an_mp4_that_ffmpeg_could_not_finish_is_not_kept(
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
    tmp_path: Path,
    a_run: Path,
) -> None:
    import legdsl.export.video as video

    fake = tmp_path / "ffmpeg"
    fake.write_text(FAKE_FFMPEG)
    fake.chmod(fake.stat().st_mode | stat.S_IXUSR)
    monkeypatch.setattr(video, "ffmpeg_exe", lambda: str(fake))
    target = tmp_path / "out" / "run.mp4"
    target.parent.mkdir()
    target.write_text("old")
    code, err = _run(capsys, ["animate", str(a_run), "--video", str(target), "--fps", "10"])
    assert code == 2 and str(target) in err and "disk is full" in err, err
    assert target.read_text() == "old"
    _only(target.parent, "run.mp4")


@pytest.mark.parametrize("fmt", ["usd", "usda"])
def test_a_usd_file_the_full_disk_refused_is_a_user_error(
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
    tmp_path: Path,
    a_run: Path,
    fmt: str,
) -> None:
    pytest.importorskip("pxr")
    from pxr import Tf

    import legdsl.export.usd as usd

    def refused(*args: object) -> None:
        Tf.RaiseCodingError("Failed to write bytes")  # USD's error, without an errno

    monkeypatch.setattr(usd, "build_stage", refused)
    monkeypatch.setattr(usd, "_NEARLY_FULL", 1 << 62)  # any disk is "nearly full"
    target = tmp_path / f"run.{fmt}"
    code, err = _run(capsys, ["export-motion", str(a_run), "-o", str(target)])
    assert code == 2 and str(target) in err and "disk is full" in err, err
    _only(tmp_path)


def test_a_c_cache_on_a_full_disk_falls_back_or_says_what_to_free(
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
    tmp_path: Path,
    generated: Path,
) -> None:
    import legdsl.sim.c_library as c_library
    from legdsl.codegen.c.build import BuildFailed
    from legdsl.sim.c_library import available

    if available() is not None:
        pytest.skip(f"no C backend here: {available()}")

    def full(name: str, files: dict[str, str], **told: object) -> None:
        raise BuildFailed(
            f"cc failed on the C of {name}:\nFatal error: can't write 132 bytes to section "
            ".text of dynamics.c.o: 'No space left on device'"
        )

    monkeypatch.setattr(c_library, "build", full)
    monkeypatch.setattr(c_library, "_BY_STAT", {})
    monkeypatch.setattr(c_library, "_TRUSTED", {})
    monkeypatch.setenv("LEGDSL_CACHE", str(tmp_path / "cache"))
    argv = ["run", HOPPER, "--time", "0.05", "--generated", str(generated)]
    code, err = _run(capsys, [*argv, "--backend", "c", "--out", str(tmp_path / "c")])
    assert code == 2 and "No space left on device" in err and "free space there" in err, err
    code, err = _run(capsys, [*argv, "--backend", "auto", "--out", str(tmp_path / "auto")])
    assert code == 0 and "running on the Python backend" in err, err


def _half_pictures(monkeypatch: pytest.MonkeyPatch) -> None:
    """matplotlib writes its PNG in place, and the disk fills after the first bytes."""
    from matplotlib.figure import Figure

    def half(self: Figure, fname: str | Path, **kwargs: object) -> None:
        Path(fname).write_bytes(b"\x89PNG")
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(Figure, "savefig", half)


def test_a_plot_on_a_full_disk_keeps_the_old_picture(
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
    tmp_path: Path,
    a_run: Path,
) -> None:
    _half_pictures(monkeypatch)
    target = tmp_path / "out" / "figure.png"
    target.parent.mkdir()
    target.write_text("old")
    code, err = _run(capsys, ["plot", str(a_run), "-o", str(target)])
    assert code == 2 and str(target) in err and "disk is full" in err, err
    assert target.read_text() == "old"
    _only(target.parent, "figure.png")


@pytest.mark.parametrize("command", ["sweep", "tune"])
def test_the_picture_of_a_sweep_or_tune_on_a_full_disk_is_not_left_half(
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
    tmp_path: Path,
    generated: Path,
    command: str,
) -> None:
    out = tmp_path / command
    out.mkdir()
    picture = out / f"{command}.png"
    picture.write_text("old")
    _half_pictures(monkeypatch)
    short = ["--controller", "hop", "--time", "0.3s", "--from", "0.1", "--out", str(out)]
    given = {
        "sweep": ["--grid", "k_speed=0.04:0.08:2", "--generated", str(generated)],
        "tune": ["--param", "k_speed=0.04:0.08", "--speeds", "0.5", "--generations", "1",
                 "--popsize", "2", "--generated", str(generated)],
    }[command]  # fmt: skip
    code, err = _run(capsys, [command, HOPPER, *short, *given])
    assert code == 2 and str(picture) in err and "disk is full" in err, err
    assert picture.read_text() == "old"
    assert not any(is_leftover(p) for p in out.iterdir())


def test_an_export_to_a_pipe_writes_into_it_and_leaves_it_a_pipe(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """A device or a pipe (-o /dev/null, /dev/full, a FIFO) is written in place: a file renamed
    over it replaced the device itself (as root, /dev/null became a regular file), and a
    full device's refusal went unseen."""
    import threading

    pipe = tmp_path / "pipe"
    os.mkfifo(pipe)
    got: list[bytes] = []
    reader = threading.Thread(target=lambda: got.append(pipe.read_bytes()))
    reader.start()
    code, err = _run(capsys, ["export", HOPPER, "--format", "urdf", "-o", str(pipe)])
    if code != 0:  # unblock the reader before failing
        with open(pipe, "wb"):
            pass
    reader.join(timeout=30)
    assert code == 0, err
    assert stat.S_ISFIFO(os.stat(pipe).st_mode)
    assert got and got[0].startswith(b"<robot")
    _only(tmp_path, "pipe")


def test_a_sweep_row_the_full_disk_refused_is_not_left_half_in_the_table(
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
    tmp_path: Path,
    generated: Path,
) -> None:
    out = tmp_path / "sweep"
    table = out / "sweep.csv"
    real_fsync = os.fsync

    def table_full(fd: int) -> None:  # the row reached the file, then the disk filled
        if table.exists() and os.path.samestat(os.fstat(fd), os.stat(table)):
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        real_fsync(fd)

    monkeypatch.setattr(os, "fsync", table_full)
    argv = ["sweep", HOPPER, "--controller", "hop", "--grid", "k_speed=0.04:0.08:2",
            "--time", "0.3s", "--from", "0.1", "--out", str(out), "--generated", str(generated)]  # fmt: skip
    code, err = _run(capsys, argv)
    assert code == 2 and str(table) in err and "disk is full" in err, err
    assert not table.exists()  # no half row (nor a header alone) for a resume to trip on
    monkeypatch.setattr(os, "fsync", real_fsync)  # room again: the same command resumes
    code, err = _run(capsys, argv)
    assert code == 0, err
    assert len(table.read_text().splitlines()) == 3


def test_a_stale_module_that_a_full_disk_cannot_rewrite_says_free_space_not_permissions(
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
    tmp_path: Path,
    generated: Path,
) -> None:
    import shutil

    source = tmp_path / "hopper.leg"
    source.write_text(Path(HOPPER).read_text().replace("mass 10 kg", "mass 11 kg"))
    out = tmp_path / "gen"
    shutil.copytree(generated / "hopper", out / "hopper")
    before = {p.name: p.read_bytes() for p in (out / "hopper").iterdir()}
    _refuse(monkeypatch)
    argv = [
        "run",
        str(source),
        "--time",
        "0.1",
        "--generated",
        str(out),
        "--out",
        str(tmp_path / "r"),
    ]
    code, err = _run(capsys, argv)
    assert code == 2 and "free some space there" in err and "writable" not in err, err
    assert {p.name: p.read_bytes() for p in (out / "hopper").iterdir()} == before
    _only(out, "hopper")


def test_any_refusal_of_the_temporary_file_names_the_target(tmp_path: Path) -> None:
    target = tmp_path / "out.bin"
    with pytest.raises(PermissionError) as caught, atomic_path(target) as tmp:
        raise PermissionError(errno.EACCES, os.strerror(errno.EACCES), str(tmp))
    assert caught.value.filename == str(target)  # not the hidden temporary name


def test_a_full_temporary_folder_of_the_compiler_is_named_not_the_cache(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    import tempfile

    import legdsl.sim.c_library as c_library
    from legdsl.codegen.c.build import BuildFailed

    def full(name: str, files: dict[str, str], **told: object) -> None:
        raise BuildFailed(f"{tempfile.gettempdir()}/cc1.s: Fatal error: No space left on device")

    monkeypatch.setattr(c_library, "build", full)
    monkeypatch.setattr(c_library, "_room", lambda f: f != Path(tempfile.gettempdir()))
    with pytest.raises(OSError) as caught:
        c_library._build("hopper", {})
    assert caught.value.errno == errno.ENOSPC
    assert f"in {tempfile.gettempdir()}, where the compiler" in caught.value.strerror


def test_a_run_whose_recording_the_disk_may_not_hold_is_told_before_it_runs(
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
    tmp_path: Path,
    generated: Path,
) -> None:
    """A full disk refused the recording only after the whole run (a 10 s quadruped: six
    seconds of simulation, then exit 2 and nothing kept). A note before it, not a refusal:
    a long run may be meant to be stopped early."""
    import shutil

    usage = shutil.disk_usage(tmp_path)
    monkeypatch.setattr(shutil, "disk_usage", lambda p: usage._replace(free=20_000))
    argv = ["run", HOPPER, "--time", "1", "--generated", str(generated),
            "--out", str(tmp_path / "run")]  # fmt: skip
    code, err = _run(capsys, argv)
    assert code == 0, err
    assert "note: --out" in err and "the disk there has 0.02 MB free, and this run's" in err
    assert "recording may take about" in err and "--record-rate" in err
    monkeypatch.setattr(shutil, "disk_usage", lambda p: usage._replace(free=10**9))
    code, err = _run(capsys, argv)
    assert code == 0 and "note" not in err, err
    # a disk with nine tenths of what the files take free is told so too (their size was
    # reckoned as the recording's in memory, and told at under half of that: a 10 min run
    # needing 61 MB on 21 MB free was not)
    written = sum(f.stat().st_size for f in (tmp_path / "run").iterdir())
    monkeypatch.setattr(shutil, "disk_usage", lambda p: usage._replace(free=int(0.9 * written)))
    code, err = _run(capsys, argv)
    assert code == 0 and "recording may take about" in err, err
    told = float(err.split("may take about ")[1].split(" MB")[0]) * 1e6
    assert written <= told <= 2.5 * written  # at least what the files take, and not far off


def test_a_full_disk_names_the_file_of_the_run_directory() -> None:
    """docs/runtime.md: a full disk names the file; it said only the run directory."""
    import errno

    from legdsl.pipeline.options import os_error

    full = OSError(
        errno.ENOSPC, "No space left on device", "/x/r/.trajectory.npz.tmp-12-0a1b2c3d.npz"
    )
    said = str(os_error("the run directory", Path("/x/r"), full))
    assert said.startswith("cannot write the run directory /x/r (trajectory.npz): No space"), said
    elsewhere = OSError(errno.ENOSPC, "No space left on device", "/y/z")
    assert "(" not in str(os_error("the run directory", Path("/x/r"), elsewhere)).split(":")[0]
