"""Where a command runs: a current directory deleted under it, a Python without legdsl's
dependencies, and names with spaces, accents and a newline. Each in a subprocess."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
HOPPER = str(ROOT / "creatures" / "hopper.leg")
ENV = dict(os.environ, PYTHONPATH=str(ROOT / "src"))


def test_a_deleted_current_directory_is_said_once(tmp_path: Path) -> None:
    """``cd d; rm -rf ../d; legdsl scale ...``: "No such file or directory; check the path and
    its permissions", of no path (plot, export, compile: "cannot write in .")."""
    gone = tmp_path / "gone"
    gone.mkdir()
    script = (
        "import os, shutil, subprocess, sys; os.chdir(sys.argv[1]); shutil.rmtree(sys.argv[1]); "
        "sys.exit(subprocess.run([sys.executable, '-m', 'legdsl', *sys.argv[2:]]).returncode)"
    )
    for args in (["scale", HOPPER, "--by", "2", "-o", "s.leg"],
                 ["export", HOPPER, "--format", "urdf", "-o", "h.urdf"]):  # fmt: skip
        gone.mkdir(exist_ok=True)
        proc = subprocess.run([sys.executable, "-c", script, str(gone), *args], env=ENV,
                              capture_output=True, text=True, timeout=60)  # fmt: skip
        assert proc.returncode == 2, proc.stderr
        assert proc.stderr == (
            "legdsl: the current directory was deleted while you were in it: "
            "cd to one that exists and run again\n"
        )


def test_a_python_without_numpy_says_so_in_a_line(tmp_path: Path) -> None:
    """``python -S -m legdsl`` (no site-packages, as another Python would be): a traceback
    ending in ModuleNotFoundError."""
    proc = subprocess.run([sys.executable, "-S", "-m", "legdsl", "show", HOPPER], cwd=tmp_path,
                          env=ENV, capture_output=True, text=True, timeout=60)  # fmt: skip
    assert proc.returncode == 2 and "Traceback" not in proc.stderr, proc.stderr
    assert proc.stderr.startswith("legdsl: cannot load ") and "pip install" in proc.stderr


def test_odd_names_make_whole_run_directories(generated: Path, tmp_path: Path) -> None:
    """Spaces, accents, Japanese and a newline in the folder names, under LC_ALL=C."""
    out = tmp_path / "a b" / "é 日本" / "new\nline" / "run"
    env = dict(ENV, LC_ALL="C", LANG="C")
    proc = subprocess.run([sys.executable, "-m", "legdsl", "run", HOPPER, "--time", "0.1",
                           "--generated", str(generated), "--out", str(out)], cwd=tmp_path,
                          env=env, capture_output=True, text=True, timeout=60)  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert json.loads((out / "run.json").read_text())["status"] == "ok"
    shutil.rmtree(tmp_path / "a b")


def test_a_name_missing_from_legdsls_own_module_is_not_told_as_a_missing_dependency() -> None:
    """An outside user ran legdsl while its files were being changed: 'cannot import name
    overwritten_notes from legdsl.pipeline.settings' was told to install the dependencies or
    raise the memory limit, neither of which helps."""
    from legdsl.cli.process import cannot_import

    own = ImportError("cannot import name 'x' from 'legdsl.pipeline.settings'",
                      name="legdsl.pipeline.settings")  # fmt: skip
    said = cannot_import(own)
    assert "legdsl's own files do not match one another" in said and "ulimit" not in said
    assert "install legdsl's dependencies" in cannot_import(ImportError("no", name="numpy"))
