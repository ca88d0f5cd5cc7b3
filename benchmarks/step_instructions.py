"""Instructions per step of a C-backend run, counted by callgrind (repeatable, unlike seconds).

    python benchmarks/step_instructions.py quadruped trot 2     # creature, controller, m/s
    python benchmarks/step_instructions.py biped run 1.5

Runs a 2 s controlled run of ``creatures/CREATURE.leg`` under ``valgrind --tool=callgrind``
(the library is built first, outside valgrind) and prints the inclusive instruction count
of the C runtime's ``step`` (dynamics, actuators, ground) and of ``leg_control_tick`` (the
state machine, its sensors and solves), each divided by the run's steps. Needs valgrind
(Debian's package); takes a few minutes, most of it Python starting under valgrind. The
library is built without ``-march=native`` (through a wrapper given as ``LEGDSL_CC``, into a
cache of its own): on a processor with AVX-512 the native build holds instructions valgrind
3.19 cannot decode, and the run under it dies of SIGILL.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DURATION = 2.0
FUNCTIONS = ("step", "leg_control_tick")

RUN = f"""
import sys
from pathlib import Path
from legdsl.pipeline.options import RunOptions
from legdsl.pipeline.session import RunSession
name, controller, speed = sys.argv[1:4]
session = RunSession.from_file(Path("creatures") / f"{{name}}.leg", generated=Path("generated"))
run = session.run(controller, [f"speed={{speed}}m/s"], options=RunOptions(duration={DURATION}),
                  backend="c")
print(run.result.steps)
"""


def portable_build(folder: Path) -> dict[str, str]:
    """The environment of a run whose library is built by the system's ``cc`` without
    ``-march=native``, cached in ``folder``."""
    wrapper = folder / "cc-portable"
    wrapper.write_text(
        "#!/bin/sh\n"
        'for a in "$@"; do shift; [ "$a" = -march=native ] || set -- "$@" "$a"; done\n'
        'exec cc "$@"\n'
    )
    wrapper.chmod(0o755)
    return {**os.environ, "LEGDSL_CC": str(wrapper), "LEGDSL_CACHE": str(folder / "cache")}


def main() -> None:
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    args = sys.argv[1:4]
    run = [sys.executable, "-c", RUN, *args]
    with tempfile.TemporaryDirectory() as tmp:
        env = portable_build(Path(tmp))
        subprocess.run(run, cwd=ROOT, check=True, capture_output=True, env=env)  # the library
        out = Path(tmp) / "callgrind.out"
        done = subprocess.run(
            ["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", *run],
            cwd=ROOT, check=True, capture_output=True, text=True, env=env,
        )  # fmt: skip
        steps = int(done.stdout.split()[-1])
        table = subprocess.run(
            ["callgrind_annotate", "--inclusive=yes", "--threshold=100", str(out)],
            check=True, capture_output=True, text=True,
        ).stdout  # fmt: skip
    print(f"{' '.join(args)}: {steps} steps")
    for name in FUNCTIONS:
        found = re.search(rf"^\s*([\d,]+) .*\?\?\?:{name} \[", table, re.MULTILINE)
        count = int(found.group(1).replace(",", "")) if found else 0
        print(f"  {name}: {count / steps:,.0f} instructions a step")


if __name__ == "__main__":
    main()
