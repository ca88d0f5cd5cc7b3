"""Outputs named by a standard stream (``-o /dev/stdout``): into a pipe a picture is whole,
and with the stream closed at start (``>&-``) nothing is written anywhere. Closed, the first
file the command opened took the stream's number, and ``legdsl plot -o /dev/stdout`` wrote
its PNG over one of matplotlib's fonts. Each is really done to a ``legdsl`` subprocess."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
ENV = dict(os.environ, PYTHONPATH=str(ROOT / "src"))


def _legdsl(*args: str, cwd: Path, **kw: object) -> subprocess.CompletedProcess[bytes]:
    return subprocess.run([sys.executable, "-m", "legdsl", *args], cwd=cwd, env=ENV,
                          timeout=120, **kw)  # type: ignore[call-overload]  # fmt: skip


@pytest.fixture(scope="module")
def run(generated: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("closed") / "run"
    proc = _legdsl("run", str(ROOT / "creatures" / "hopper.leg"), "--time", "0.2",
                   "--generated", str(generated), "--out", str(out), cwd=out.parent,
                   capture_output=True)  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    return out


def test_a_closed_descriptor_gets_dev_null_so_no_file_takes_its_number(tmp_path: Path) -> None:
    code = ("import os, sys; from legdsl.cli.process import streams_that_cannot_fail; "
            "streams_that_cannot_fail(); print(os.readlink('/proc/self/fd/1'), file=sys.stderr)")  # fmt: skip
    proc = subprocess.run([sys.executable, "-c", code], env=ENV, capture_output=False,
                          stderr=subprocess.PIPE, text=True, timeout=60, cwd=tmp_path,
                          preexec_fn=lambda: os.close(1))  # fmt: skip
    assert proc.returncode == 0 and proc.stderr.strip() == "/dev/null", proc.stderr


@pytest.mark.parametrize(
    "words",
    [("plot", "-o", "/dev/stdout"), ("export-motion", "--format", "bvh", "-o", "/dev/stdout")],
)
def test_an_output_to_a_closed_standard_output_is_refused(
    run: Path, tmp_path: Path, words: tuple[str, ...]
) -> None:
    before = {p: p.read_bytes() for p in run.iterdir()}
    proc = _legdsl(words[0], str(run), *words[1:], cwd=tmp_path, stderr=subprocess.PIPE,
                   text=True, preexec_fn=lambda: os.close(1))  # fmt: skip
    assert proc.returncode == 2, proc.stderr
    assert "started with standard output closed (>&-)" in proc.stderr
    assert "Traceback" not in proc.stderr
    assert {p: p.read_bytes() for p in run.iterdir()} == before


def test_a_picture_into_a_pipe_is_whole(run: Path, tmp_path: Path) -> None:
    """``legdsl plot RUN -o /dev/stdout | cat``: "[Errno None] None" (the PNG writer seeks)."""
    proc = _legdsl("plot", str(run), "-o", "/dev/stdout", cwd=tmp_path, capture_output=True)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.startswith(b"\x89PNG\r\n\x1a\n") and proc.stdout.endswith(b"IEND\xaeB`\x82")


def test_an_output_to_a_stream_open_only_to_read_says_so(run: Path, tmp_path: Path) -> None:
    """``-o /dev/stdin < file``: "Bad file descriptor (/dev/stdin); check the path"."""
    (tmp_path / "notes.txt").write_text("mine\n")
    with open(tmp_path / "notes.txt", "rb") as read_only:
        proc = _legdsl("export-motion", str(run), "--format", "bvh", "-o", "/dev/stdin",
                       cwd=tmp_path, stdin=read_only, capture_output=True, text=True)  # fmt: skip
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.strip() == (
        "legdsl: cannot write /dev/stdin: the stream it names is not open for writing; give a file"
    )
    assert (tmp_path / "notes.txt").read_text() == "mine\n"


def test_an_export_to_dash_with_standard_output_closed_is_refused(tmp_path: Path) -> None:
    """``legdsl export FILE -o - >&-`` was an internal error (sys.stdout is None)."""
    proc = _legdsl("export", str(ROOT / "creatures" / "hopper.leg"), "--format", "mjcf", "-o",
                   "-", cwd=tmp_path, stderr=subprocess.PIPE, text=True,
                   preexec_fn=lambda: os.close(1))  # fmt: skip
    assert proc.returncode == 2, proc.stderr
    assert "-o -: this command was started with standard output closed (>&-)" in proc.stderr


def test_a_compile_whose_messages_cannot_be_read_still_compiles(tmp_path: Path) -> None:
    """``legdsl compile FILE 2>&1 | head -1``: the second message met a closed pipe and the
    compile stopped there, exit 1, nothing written. A message lost does not stop the work."""
    import shutil

    shutil.copy(ROOT / "creatures" / "hopper.leg", tmp_path / "hopper.leg")
    proc = subprocess.Popen([sys.executable, "-m", "legdsl", "compile", "hopper.leg"],
                            cwd=tmp_path, env=ENV, stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE)  # fmt: skip
    assert proc.stderr is not None
    proc.stderr.readline()  # the first line, then the reader leaves
    proc.stderr.close()
    assert proc.wait(timeout=120) == 0
    assert (tmp_path / "generated" / "hopper" / "dynamics.py").is_file()


def test_show_with_standard_output_closed_says_so(tmp_path: Path) -> None:
    """``legdsl show FILE >&-`` exited 0 having shown nothing."""
    proc = _legdsl("show", str(ROOT / "creatures" / "hopper.leg"), cwd=tmp_path,
                   stderr=subprocess.PIPE, text=True, preexec_fn=lambda: os.close(1))  # fmt: skip
    assert proc.returncode == 2, proc.stderr
    assert "standard output is closed (>&-)" in proc.stderr
