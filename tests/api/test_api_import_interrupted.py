"""Ctrl-C during the public API's first import (``legdsl.load`` first used: lark and numpy,
some 0.6 s; sympy was among them until a run of fresh modules no longer needed it). Landing mid-import it left those packages half-initialised, and the next
call in the same process (a notebook's next cell) failed: sympy's RecursionError in
``sympify``, or a syntax tree whose table rows were lark Trees ("'Tree' object has no
attribute 'actions'", random API interrupt seed 13100). Now it comes once the import is whole.

The same for the libraries imported when first needed: sympy and jinja2 by the first compile,
matplotlib by the first picture. A Ctrl-C in ``legdsl.load``'s compile left sympy half-made and
every later compile in the process failed ("module 'sympy' has no attribute 'core'", random API
interrupt seed 15700)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from conftest import CREATURES

# In a fresh interpreter: an import hook sends the process SIGINT as lark's lexer starts to
# import, in the middle of the API's import; then the call is made again.
PROBE = r"""
import os, signal, sys

class Kick:
    fired = False

    def find_spec(self, name, path=None, target=None):
        if name == "lark.lexer" and not Kick.fired:
            Kick.fired = True
            os.kill(os.getpid(), signal.SIGINT)
        return None

sys.meta_path.insert(0, Kick())
import legdsl

try:
    legdsl.load
    print("not interrupted")
except KeyboardInterrupt:
    print("interrupted, the API whole:", "legdsl.api" in sys.modules)
print(legdsl.load(sys.argv[1]))
"""


def test_ctrl_c_in_the_first_import_comes_once_the_api_is_whole(tmp_path: Path) -> None:
    done = subprocess.run(
        [sys.executable, "-c", PROBE, str(CREATURES / "hopper.leg")],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        timeout=120,
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines() == [
        "interrupted, the API whole: True",
        "<legdsl creature 'hopper': 5 DOF, controllers ['hop']>",
    ], done.stdout + done.stderr
    assert "Traceback" not in done.stderr, done.stderr


# The same kick at a chosen module, in a call that first imports it; then the call again.
PROBE_LATER = r"""
import os, signal, sys

class Kick:
    fired = False

    def find_spec(self, name, path=None, target=None):
        if name == sys.argv[2] and not Kick.fired:
            Kick.fired = True
            os.kill(os.getpid(), signal.SIGINT)
        return None

import legdsl

def call():
    run = legdsl.load(sys.argv[1]).run(controller="hop", time=0.2)
    return run.plot("figure6.png").name if sys.argv[3] == "plot" else run

legdsl.load
sys.meta_path.insert(0, Kick())
try:
    call()
    print("not interrupted")
except KeyboardInterrupt:
    print("interrupted")
print(call())
"""


@pytest.mark.parametrize(
    ("kicked", "call", "result"),
    [
        ("sympy.printing", "load", "<legdsl run of 'hopper': ok, 39 samples to 0.198 s>"),
        ("sympy.core.numbers", "load", "<legdsl run of 'hopper': ok, 39 samples to 0.198 s>"),
        ("matplotlib.colors", "plot", "figure6.png"),
    ],
)
def test_ctrl_c_in_a_library_imported_when_first_needed_comes_once_it_is_whole(
    tmp_path: Path, kicked: str, call: str, result: str
) -> None:
    source = tmp_path / "hopper.leg"  # beside no generated/: the first load compiles
    source.write_text((CREATURES / "hopper.leg").read_text(encoding="utf-8"), encoding="utf-8")
    done = subprocess.run(
        [sys.executable, "-c", PROBE_LATER, str(source), kicked, call],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines() == ["interrupted", result], done.stdout + done.stderr
    assert "Traceback" not in done.stderr, done.stderr
