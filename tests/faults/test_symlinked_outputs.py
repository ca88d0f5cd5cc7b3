"""An output path that is a symbolic link: ``-o /dev/stdout`` with stdout sent to a file
renamed a temporary file over the link (as root, over /dev/stdout itself), and a link to a
file became a file of its own. Now a link to a file has that file written (the link stays),
and a link to one of the process's descriptors is written through it, in place."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from legdsl.files import atomic_path, atomic_same_name, process_fd, write_atomic

ROOT = Path(__file__).resolve().parents[2]


def _linked(tmp_path: Path, target: str = "real.txt") -> Path:
    (tmp_path / "real.txt").write_text("old\n")
    link = tmp_path / "link.txt"
    link.symlink_to(target)
    return link


def _write_through_atomic_path(path: Path, text: str) -> None:
    with atomic_path(path) as tmp:
        tmp.write_text(text)


def _write_through_same_name(path: Path, text: str) -> None:
    with atomic_same_name(path) as tmp:
        tmp.write_text(text)


@pytest.mark.parametrize("write", [write_atomic, _write_through_atomic_path,
                                   _write_through_same_name])  # fmt: skip
def test_a_link_to_a_file_has_the_file_written_and_stays_a_link(tmp_path: Path, write) -> None:  # type: ignore[no-untyped-def]
    link = _linked(tmp_path)
    write(link, "new\n")
    assert link.is_symlink() and os.readlink(link) == "real.txt"
    assert (tmp_path / "real.txt").read_text() == "new\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link.txt", "real.txt"]


def test_a_dangling_link_has_its_target_made(tmp_path: Path) -> None:
    link = tmp_path / "link.txt"
    link.symlink_to("sub/made.txt")
    (tmp_path / "sub").mkdir()
    write_atomic(link, "new\n")
    assert link.is_symlink() and (tmp_path / "sub" / "made.txt").read_text() == "new\n"


@pytest.mark.parametrize("write", [write_atomic, _write_through_atomic_path])
def test_a_link_to_an_open_descriptor_is_written_through_it(tmp_path: Path, write) -> None:  # type: ignore[no-untyped-def]
    out = tmp_path / "redirected"
    fd = os.open(out, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
    try:
        link = tmp_path / "stdout"
        link.symlink_to(f"/proc/self/fd/{fd}")
        assert process_fd(link) == fd and process_fd(Path(f"/dev/fd/{fd}")) == fd
        os.write(fd, b"before\n")
        if write is write_atomic:  # through the descriptor: after what it printed
            write(link, "content\n")
        else:  # a writer that opens the name: the descriptor is moved past it
            write(link, "before\ncontent\n")
        os.write(fd, b"after\n")
    finally:
        os.close(fd)
    assert link.is_symlink()
    assert out.read_text() == "before\ncontent\nafter\n"


def test_export_to_dev_stdout_sent_to_a_file(tmp_path: Path) -> None:
    """``legdsl export ... -o LINK`` with LINK -> /proc/self/fd/1 (as /dev/stdout is) and
    stdout sent to a file: the file has the export alone (the line that says it was written
    goes to standard error)."""
    link = tmp_path / "stdout.xml"
    link.symlink_to("/proc/self/fd/1")
    out = tmp_path / "redirected"
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    with out.open("wb") as f:
        subprocess.run([sys.executable, "-m", "legdsl", "export", str(ROOT / "creatures" / "hopper.leg"),
                        "--format", "mjcf", "-o", str(link)], stdout=f, env=env, check=True)  # fmt: skip
    assert link.is_symlink() and os.readlink(link) == "/proc/self/fd/1"
    text = out.read_text()
    assert text.startswith('<mujoco model="hopper">') and text.endswith("</mujoco>\n")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["redirected", "stdout.xml"]


@pytest.mark.parametrize("name", ["dangling", "loop/run"])
def test_an_out_through_a_dangling_or_looping_link_is_refused_before_the_run(
    tmp_path: Path, name: str, capsys: pytest.CaptureFixture[str]
) -> None:
    """It was refused after the run ("cannot write the run directory dangling: File exists"),
    the run lost; docs/runtime.md: an --out that cannot be written is refused first."""
    from legdsl.cli import main

    (tmp_path / "dangling").symlink_to(tmp_path / "nowhere")
    (tmp_path / "loop").symlink_to(tmp_path / "loop")
    hopper = Path(__file__).resolve().parents[2] / "creatures" / "hopper.leg"
    generated = tmp_path / "generated"
    argv = ["run", str(hopper), "--time", "0.1", "--generated", str(generated)]
    assert main([*argv, "--out", str(tmp_path / name)]) == 2
    assert "is a symbolic link to " in capsys.readouterr().err
    assert not generated.exists()  # refused before anything was compiled


def test_a_killed_writers_temporary_file_goes_at_the_next_write(tmp_path: Path) -> None:
    """A video killed with kill -9 left .v.mp4.tmp-PID-... beside v.mp4, for good: the next
    write of v.mp4 removes it (a writer that is still running keeps its own)."""
    import secrets

    dead = 2**22 + 12345  # above the default pid_max: no process has it
    left = tmp_path / f".v.mp4.tmp-{dead}-{secrets.token_hex(4)}.mp4"
    left.write_bytes(b"half a video")
    running = tmp_path / f".v.mp4.tmp-{os.getpid()}-{secrets.token_hex(4)}.mp4"
    running.write_bytes(b"ours")
    write_atomic(tmp_path / "v.mp4", b"a video")
    assert not left.exists() and running.exists()
    assert (tmp_path / "v.mp4").read_bytes() == b"a video"
