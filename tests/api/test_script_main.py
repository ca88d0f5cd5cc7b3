"""A user's script is run once: legdsl's worker processes never import it again."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

from conftest import CREATURES

SCRIPT = """\
import os, threading, time
with open("marker.log", "a") as f:
    f.write(f"{os.getpid()} {__name__}\\n")
threading.Thread(target=time.sleep, args=(30,), daemon=True).start()  # any thread of its own
import legdsl
print(legdsl.load("hopper.leg").run(controller="hop", time=0.2).status)
"""


def test_a_script_without_a_main_guard_runs_once(tmp_path: Path) -> None:
    """With a thread of its own alive, the script made the compiler spawn its processes (a
    threaded process is not forked), and each imported the script again as __mp_main__: an
    unguarded script, as docs/api.md's examples are written, ran twice whole."""
    shutil.copy(CREATURES / "hopper.leg", tmp_path / "hopper.leg")
    (tmp_path / "script.py").write_text(SCRIPT)
    env = {
        **os.environ,
        "LEGDSL_CACHE": str(tmp_path / "cache"),
        "PYTHONPATH": os.pathsep.join(sys.path),
    }
    done = subprocess.run(
        [sys.executable, "script.py"],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "ok"
    assert (tmp_path / "generated" / "hopper").is_dir()  # it compiled: the processes were spawned
    ran = (tmp_path / "marker.log").read_text().splitlines()
    assert len(ran) == 1 and ran[0].endswith(" __main__"), ran
