"""Write a copy of a .leg file with some controller parameters multiplied, to start a tuning
from gains that do not work (docs/api.md, "Tuning from detuned gains"):

    python docs/scripts/detune.py creatures/kangaroo.leg --controller hop \\
        --times k_speed=3 --times kp=1/3 --times kv=1/3 -o detuned/kangaroo.leg

Only those values change, each kept in the unit it is written in (the tuner's own writer).
"""

from __future__ import annotations

import argparse
from fractions import Fraction
from pathlib import Path

from legdsl.api.tuned_file import write_tuned
from legdsl.check.source import check_model


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("file", type=Path)
    parser.add_argument("--controller", required=True)
    parser.add_argument("--times", action="append", default=[], metavar="NAME=FACTOR")
    parser.add_argument("-o", "--output", type=Path, required=True)
    args = parser.parse_args()
    controller = check_model(args.file).controller(args.controller)
    values = {p.name: p.value for p in controller.params}
    changed = {}
    for text in args.times:
        name, _, factor = text.partition("=")
        changed[name] = values[name] * float(Fraction(factor))
    args.output.parent.mkdir(parents=True, exist_ok=True)
    write_tuned(args.file, controller, changed, args.output)
    print(f"wrote {args.output}: " + ", ".join(f"{n} x {f}" for n, f in
                                               (t.split("=") for t in args.times)))  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
