"""Write a quadruped of other proportions than the paper's, with the shipped quadruped's
controllers, to show them carried to a new creature (docs/quadruped.md, "A quadruped of
other proportions"):

    python docs/scripts/stocky_quadruped.py -o stocky/stocky.leg           # the shipped gains
    python docs/scripts/stocky_quadruped.py -o stocky/stocky.leg --tuned   # and the tuned ones

`stocky` is `creatures/quadruped.leg` with a trunk 30% heavier, hips 12 cm closer together
fore and aft and 2 cm further apart sideways, and thighs 5 cm shorter and lighter; its
controllers are the shipped ones with the two values that are lengths of the creature
(`full`, the leg's length at which thrust ends, and `height`, the apex asked for) moved with
the legs. ``--tuned`` also writes the trot's, the bound's and the pace's values the searches
found for it (``TUNED``; the commands are in docs/quadruped.md), each in the unit the file
writes it in (the tuner's own writer).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from legdsl.api.tuned_file import write_tuned
from legdsl.check.source import check_model

SOURCE = Path(__file__).resolve().parents[2] / "creatures" / "quadruped.leg"

# (the text in creatures/quadruped.leg, what stocky has instead, how many times it is there)
PROPORTIONS = (
    ("creature quadruped {", "creature stocky {", 1),
    ("    mass 10.0 kg\n", "    mass 13.0 kg\n", 1),
    ("z = 0.84 m   # chosen: feet 3 cm", "z = 0.79 m   # feet 3 cm", 1),
    ("length 0.41 m  com 0.2 m  mass 1.5 kg", "length 0.36 m  com 0.18 m  mass 1.3 kg", 1),
    ("(0.39 m, 0.12 m, 0 m)", "(0.33 m, 0.14 m, 0 m)", 2),
    ("(-0.39 m, 0.12 m, 0 m)", "(-0.33 m, 0.14 m, 0 m)", 2),
    # the leg is 0.76 m from hip to foot at zero slide, 5 cm shorter: so are these two
    ("param full = 0.80 m ", "param full = 0.75 m ", 1),
    ("input height = 0.64 m ", "input height = 0.59 m ", 1),
)

# What the searches found (docs/quadruped.md, "A quadruped of other proportions"), in SI
# units: the trot's by `legdsl tune`, then the bound's and the pace's by
# docs/scripts/quadruped_search.py on the file with the trot's.
TUNED = {
    "trot": {
        "k_speed": 0.0581106,
        "k_trim": 0.332109,
        "kp": 879.291,
        "kv": 60.0505,
        "stroke": 0.0283169,
        "leg_k": 4578.28,
    },
    "bound": {
        "kv_rate": 22.2,
        "omega_f": 2.58,
        "omega_r": 4.0,
        "k_center": 2.74,
        "k_pitch_i": 2.74,
        "k_pitch_thrust": 0.0536,
        "idle_delay": 0.0691,
        "k_speed": 0.0304,
        "k_trim": 0.00385,
        "stroke": 0.025,
        "k_height": 0.0065,
        "stroke_max": 0.0661,
        "stand": -0.0569,
        "leg_k": 5900.0,
        "leg_b": 78.2,
        "kp_roll": 437.0,
        "kv_roll": 22.4,
        "accel": 1.12,
    },
    "pace": {
        "kp": 1070.0,
        "kv": 78.4,
        "kp_roll": 636.0,
        "kv_roll": 97.3,
        "k_side_trim": 0.5,
        "leg_k": 7730.0,
        "leg_b": 198.0,
        "k_speed": 0.109,
        "stroke": 0.0123,
    },
}


def stocky_text(source: str) -> str:
    """``creatures/quadruped.leg``'s text with stocky's proportions."""
    for old, new, count in PROPORTIONS:
        if source.count(old) != count:
            raise ValueError(f"expected {old!r} {count} time(s) in quadruped.leg")
        source = source.replace(old, new)
    return source


def write_stocky(out: Path, tuned: bool = False) -> Path:
    """Write stocky's ``.leg`` file at ``out`` (with its tuned values if ``tuned``)."""
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(stocky_text(SOURCE.read_text()))
    if tuned:
        for name, values in TUNED.items():
            write_tuned(out, check_model(out).controller(name), values, out)
    return out


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", type=Path, required=True)
    parser.add_argument("--tuned", action="store_true", help="with the values tune found")
    args = parser.parse_args()
    print(f"wrote {write_stocky(args.output, args.tuned)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
