"""Ctrl-C caught in a notebook while ``tune`` imports cma (and with it matplotlib): the next
import works. Half-imported, matplotlib's submodules kept the half-made package and every
later import of cma failed (``module 'matplotlib' has no attribute 'get_data_path'``)
until the kernel restarted (random API interrupts, draws 39 and 55)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

SCRIPT = """
import sys
from legdsl.api.tune import tune

class CutShort:  # Ctrl-C landing as matplotlib imports its rcsetup, cbook already in
    def find_spec(self, name, path=None, target=None):
        if name == "matplotlib.rcsetup":
            raise KeyboardInterrupt
        return None

sys.meta_path.insert(0, CutShort())
try:
    tune(None, [], None, 1, 2, 0, 1)
except KeyboardInterrupt:
    pass
sys.meta_path.pop(0)
import cma, matplotlib
print(matplotlib.get_data_path() != "")
"""


def test_an_interrupted_import_of_cma_leaves_it_importable() -> None:
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"))
    done = subprocess.run([sys.executable, "-c", SCRIPT], env=env, capture_output=True,
                          text=True, timeout=120)  # fmt: skip
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.strip() == "True"
