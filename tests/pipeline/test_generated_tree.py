"""``legdsl run`` against a generated tree it must recompile but cannot write (a read-only
checkout, a shared install) or that is a file, and with a wrong ``LEGDSL_BACKEND``: one line
that names what is wrong and the fix."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from conftest import CREATURES, GENERATED

from legdsl.cli import main
from legdsl.pipeline import generated as generated_module


@pytest.mark.parametrize(
    ("backend", "stale"), [("python", "dynamics.py"), ("c", "dynamics.c"), ("auto", "dynamics.h")]
)
def test_a_stale_tree_that_cannot_be_written_says_to_give_another(
    backend: str,
    stale: str,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:
    if backend == "c":
        from legdsl.sim.c_library import available

        if available() is not None:
            pytest.skip(f"needs a C compiler: {available()}")
    tree = tmp_path / "generated"
    shutil.copytree(GENERATED / "hopper", tree / "hopper")
    with open(tree / "hopper" / stale, "a") as f:
        f.write("\n")  # edited by hand: its digest no longer matches SHA256SUMS

    def read_only(*args: object) -> Path:
        raise OSError(30, "Read-only file system", str(tree / ".hopper.new-1-2"))

    monkeypatch.setattr(generated_module, "write_module_dir", read_only)
    argv = ["run", str(CREATURES / "hopper.leg"), "--controller", "hop", "--time", "0.05",
            "--generated", str(tree), "--out", str(tmp_path / "run"),
            "--backend", backend]  # fmt: skip
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1] == (
        f"legdsl: the generated modules of hopper in {tree} are out of date and cannot be "
        "written there (Read-only file system); make it writable, or give --generated a "
        "directory you can write"
    ), err


@pytest.mark.parametrize("tree_is", ["fresh", "without dynamics.py"])
def test_modules_that_are_missing_are_not_said_to_be_out_of_date(
    tree_is: str,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:
    """A fresh --generated under ``ulimit -f 30``: the modules "are out of date and cannot be
    written there", though there were none, and "free some space there" for a file-size limit."""
    import errno
    import os

    tree = tmp_path / "generated"
    if tree_is != "fresh":
        shutil.copytree(GENERATED / "hopper", tree / "hopper")
        (tree / "hopper" / "dynamics.py").unlink()

    def too_large(*args: object) -> Path:
        raise OSError(errno.EFBIG, os.strerror(errno.EFBIG), str(tree / "hopper"))

    monkeypatch.setattr(generated_module, "write_module_dir", too_large)
    argv = ["run", str(CREATURES / "hopper.leg"), "--time", "0.05", "--backend", "python",
            "--generated", str(tree), "--out", str(tmp_path / "run")]  # fmt: skip
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    state = "missing" if tree_is == "fresh" else "incomplete"
    assert err[-1].startswith(
        f"legdsl: the generated modules of hopper in {tree} are {state} and cannot be written "
        "there (File too large"
    ), err
    assert err[-1].endswith("; raise that limit, or give --generated a directory you can write")


def test_a_generated_path_that_is_a_file_says_to_give_a_directory(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "generated").write_text("not a directory")
    argv = ["run", str(CREATURES / "hopper.leg"), "--time", "0.05", "--backend", "python",
            "--generated", str(tmp_path / "generated"), "--out", str(tmp_path / "run")]  # fmt: skip
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1] == (
        f"legdsl: cannot write generated modules into {tmp_path / 'generated'}: it is a file; "
        "give --generated a directory you can write"
    ), err


def test_a_wrong_legdsl_backend_is_named_as_the_variable(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """No --backend was given: the message names what was set, LEGDSL_BACKEND."""
    monkeypatch.setenv("LEGDSL_BACKEND", "gcc")
    argv = ["run", str(CREATURES / "hopper.leg"), "--time", "0.05",
            "--generated", str(GENERATED), "--out", str(tmp_path / "run")]  # fmt: skip
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1] == "legdsl: LEGDSL_BACKEND=gcc: use one of python, c, auto", err
