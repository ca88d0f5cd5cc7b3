"""SHA-256 of the run files of every shipped creature and controller, to show that a change
to the compiler or the runtime leaves every run byte-identical.

    python docs/scripts/run_fingerprints.py -o /tmp/before.json     # on the old commit
    python docs/scripts/run_fingerprints.py -o /tmp/after.json      # on the new one
    diff /tmp/before.json /tmp/after.json && echo byte-identical

Each run goes through the command line (``legdsl run``), so the script does not depend on
the package's internals and works on either side of a reorganisation. The runs are short
(``--time``, 2 s by default) but cover every controller, a schedule, a path, a change of
controller and a passive drop.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import subprocess
import sys
import tempfile
from pathlib import Path

RUNS: dict[str, list[str]] = {
    "hopper-hop": ["creatures/hopper.leg", "--controller", "hop", "--set", "speed=1m/s"],
    "kangaroo-hop": ["creatures/kangaroo.leg", "--controller", "hop", "--set", "speed=3m/s"],
    "kangaroo-schedule": [
        "creatures/kangaroo.leg", "--controller", "hop", "--set", "speed=2m/s",
        "--set", "speed=4m/s@1s",
    ],
    "biped-run": ["creatures/biped.leg", "--controller", "run", "--set", "speed=1.5m/s"],
    "biped-run-circle": [
        "creatures/biped.leg", "--controller", "run", "--set", "speed=1.5m/s",
        "--path", "circle(center = (0, 5) m, radius = 5 m, turn = left)",
    ],
    "biped-gallop": ["creatures/biped.leg", "--controller", "gallop", "--set", "speed=1.5m/s"],
    "biped-gallop_human": [
        "creatures/biped.leg", "--controller", "gallop_human", "--set", "speed=1.5m/s",
    ],
    "kangaroo-jump": ["creatures/kangaroo.leg", "--controller", "jump", "--set", "speed=4m/s"],
    "quadruped-drop": ["creatures/quadruped.leg", "--drop", "0.3"],
    "quadruped-trot": ["creatures/quadruped.leg", "--controller", "trot", "--set", "speed=2m/s"],
    "quadruped-pace": ["creatures/quadruped.leg", "--controller", "pace", "--set", "speed=1m/s"],
    "quadruped-bound": ["creatures/quadruped.leg", "--controller", "bound", "--set", "speed=1m/s"],
    "quadruped-gallop": ["creatures/quadruped.leg", "--controller", "gallop", "--set", "speed=2m/s"],
    "biped-switch": [
        "creatures/biped.leg", "--controller", "run", "--set", "speed=1.5m/s",
        "--switch", "1s=gallop",
    ],
}  # fmt: skip
FILES = ("trajectory.npz", "trajectory.csv", "run.json")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", required=True, help="where to write the JSON")
    parser.add_argument("--time", default="2", help="simulated seconds per run (default 2)")
    args = parser.parse_args()
    hashes: dict[str, dict[str, str | int]] = {}
    with tempfile.TemporaryDirectory() as tmp:
        for label, argv in RUNS.items():
            out = Path(tmp) / label
            cmd = ["legdsl", "run", *argv, "--time", args.time, "--out", str(out)]
            done = subprocess.run(cmd, capture_output=True, text=True)
            entry: dict[str, str | int] = {"exit": done.returncode}
            for name in FILES:
                path = out / name
                if path.is_file():
                    entry[name] = hashlib.sha256(path.read_bytes()).hexdigest()
            hashes[label] = entry
            print(f"{label}: exit {done.returncode}", file=sys.stderr)
    Path(args.output).write_text(json.dumps(hashes, indent=2, sort_keys=True) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
