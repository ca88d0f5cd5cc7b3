"""Write a copy of a .leg file with some controller parameters multiplied, to start a tuning
from gains that do not work (docs/api.md, "Tuning from detuned gains"):

    python docs/scripts/detune.py creatures/kangaroo.leg --controller hop \\
        --times k_speed=3 --times kp=1/3 --times kv=1/3 -o detuned/kangaroo.leg

Only those values change, each kept in the unit it is written in (the tuner's own writer).
A mistake in the options (a name the controller has not, a factor that is no number) is said
in a sentence, with exit status 2; a file that does not compile, with its diagnostics and 1.
"""

from __future__ import annotations

import argparse
import sys
from fractions import Fraction
from pathlib import Path

from legdsl.api.tuned_file import write_tuned
from legdsl.check.source import check_model
from legdsl.lang.errors import LegError


def write_times(file: Path, controller_name: str, factors: dict[str, float], out: Path) -> None:
    """``out``: ``file`` with each named parameter of the controller multiplied by its factor,
    changed where it is declared and kept in its unit (also docs/scripts/tune_variants.py)."""
    controller = check_model(file).controller(controller_name)
    values = {p.name: p.value for p in controller.params}
    changed = {name: values[name] * factor for name, factor in factors.items()}
    out.parent.mkdir(parents=True, exist_ok=True)
    write_tuned(file, controller, changed, out)


def _factor(text: str) -> tuple[str, float, str]:
    """``NAME=FACTOR`` of ``--times``: FACTOR a number or a fraction (1/3), finite."""
    name, eq, factor = text.partition("=")
    if not eq or not name.strip():
        raise argparse.ArgumentTypeError(f"{text!r}: write NAME=FACTOR (kp=1/3)")
    try:
        value = float(Fraction(factor.strip()))
    except (ValueError, ZeroDivisionError, OverflowError):
        raise argparse.ArgumentTypeError(
            f"{text!r}: the factor {factor.strip() or 'nothing'!r} is not a number; give a "
            "finite number or a fraction (kp=3, kp=0.5, kp=1/3)"
        ) from None
    return name.strip(), value, factor.strip()


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("file", type=Path)
    parser.add_argument("--controller", required=True)
    parser.add_argument("--times", action="append", default=[], metavar="NAME=FACTOR",
                        type=_factor)  # fmt: skip
    parser.add_argument("-o", "--output", type=Path, required=True)
    args = parser.parse_args()
    factors: dict[str, float] = {}
    for name, value, _ in args.times:
        if name in factors:
            parser.error(f"--times {name}: given twice; give each parameter's factor once")
        factors[name] = value
    try:
        model = check_model(args.file)
    except LegError as e:
        print(e, file=sys.stderr)
        return 1
    controllers = {c.name: c for c in model.controllers}
    if args.controller not in controllers:
        parser.error(f"--controller {args.controller}: {args.file} has no such controller "
                     f"(it has {', '.join(controllers) or 'none'})")  # fmt: skip
    params = [p.name for p in controllers[args.controller].params]
    for name in factors:
        if name not in params:
            parser.error(f"--times {name}: not a parameter of controller '{args.controller}' "
                         f"(it has {', '.join(params) or 'none'})")  # fmt: skip
    try:
        write_times(args.file, args.controller, factors, args.output)
    except OSError as e:
        print(f"detune.py: cannot write {args.output}: {e.strerror or e}", file=sys.stderr)
        return 1
    print(f"wrote {args.output}: " + ", ".join(f"{n} x {f}" for n, _, f in args.times))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
