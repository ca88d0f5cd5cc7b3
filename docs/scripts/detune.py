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


def write_times(file: Path, controller_name: str, factors: dict[str, float], out: Path) -> None:
    """``out``: ``file`` with each named parameter of the controller multiplied by its factor,
    changed where it is declared and kept in its unit (also docs/scripts/tune_variants.py)."""
    controller = check_model(file).controller(controller_name)
    values = {p.name: p.value for p in controller.params}
    changed = {name: values[name] * factor for name, factor in factors.items()}
    out.parent.mkdir(parents=True, exist_ok=True)
    write_tuned(file, controller, changed, out)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("file", type=Path)
    parser.add_argument("--controller", required=True)
    parser.add_argument("--times", action="append", default=[], metavar="NAME=FACTOR")
    parser.add_argument("-o", "--output", type=Path, required=True)
    args = parser.parse_args()
    write_times(args.file, args.controller, {n: float(Fraction(f)) for n, f in
                                            (t.split("=") for t in args.times)}, args.output)  # fmt: skip
    print(f"wrote {args.output}: " + ", ".join(f"{n} x {f}" for n, f in
                                               (t.split("=") for t in args.times)))  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
