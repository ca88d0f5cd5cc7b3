"""The grammar (and the package's other data files) must ship inside the wheel: a plain install
finds them with no source tree."""

from __future__ import annotations

import os
import subprocess
import sys
import zipfile
from pathlib import Path

from conftest import ROOT


def test_wheel_carries_grammar_and_parses_outside_the_tree(tmp_path: Path) -> None:
    wheel_dir = tmp_path / "wheel"
    subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation",
         "-q", "-w", str(wheel_dir), str(ROOT)],
        check=True,
    )  # fmt: skip
    (wheel,) = wheel_dir.glob("legdsl-*.whl")
    names = zipfile.ZipFile(wheel).namelist()
    assert "legdsl/grammar/legdsl.lark" in names
    assert "legdsl/grammar/friendly_errors.toml" in names
    assert (
        "legdsl/codegen/python/templates/dynamics.py.j2" in names
    )  # the generated-module skeleton
    assert "legdsl/analysis/table2.toml" in names  # the paper's Table 2, read as data

    target = tmp_path / "site"
    subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "install",
            "--no-deps",
            "-q",
            "--target",
            str(target),
            str(wheel),
        ],
        check=True,
    )
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    code = (
        "import legdsl.lang.parser as p, sys; "
        "p.parse('creature a { planar body b free { mass 1 kg inertia 1 kg*m^2 } }'); "
        "print(p.grammar_dir()); "
        "from legdsl.analysis.table2 import TABLE2; assert len(TABLE2) == 4, TABLE2"
    )
    env = {**os.environ, "PYTHONPATH": str(target)}
    out = subprocess.run(
        [sys.executable, "-c", code],
        cwd=elsewhere,
        env=env,
        check=True,
        capture_output=True,
        text=True,
    )
    assert Path(out.stdout.strip()).is_relative_to(target)
