"""The runtime's own numbers that follow the creature's size (docs/scaling.md, "Far from a
metre"): how deep a foot may start under the ground, and how fast a coordinate may move before
the run is called diverged. Both were written for animals about a metre tall; every creature
from 25 cm to 4 m gets exactly the numbers it always had.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

# How deep a contact may start under the ground (a resting foot sinks in a little): 1 cm,
# but at most 4% and at least 0.25% of the creature's standing height, so an insect is not
# let sink its whole leg and a giant may rest in its own (scaled) footprint. Every creature
# from 25 cm to 4 m tall gets exactly 1 cm.
START_DEPTH = 0.01  # m
START_DEPTH_MOST, START_DEPTH_LEAST = 0.04, 0.0025  # of the standing height


def start_depth(standing_height: float) -> float:
    """How deep (m) a contact may start under the ground, for a creature this tall (0: a
    root welded to the world, of no standing height, gets 1 cm)."""
    if standing_height <= 0:
        return START_DEPTH
    least, most = START_DEPTH_LEAST * standing_height, START_DEPTH_MOST * standing_height
    return max(least, START_DEPTH) if most >= START_DEPTH else most


# A velocity past this is a divergence: 1000 m/s or rad/s for a creature 10 cm tall or taller;
# a smaller one's joints turn faster, as 1/sqrt(its size) (Table 1), and so its limit grows
# as sqrt(10 cm / standing height) (the kangaroo at 1/20 already swings at 173 rad/s).
DIVERGENCE_SPEED, DIVERGENCE_HEIGHT = 1e3, 0.1


def divergence_speed(standing_height: float) -> float:
    """The fastest a coordinate may move (m/s or rad/s) for a creature this tall."""
    if standing_height <= 0 or standing_height >= DIVERGENCE_HEIGHT:
        return DIVERGENCE_SPEED
    return DIVERGENCE_SPEED * math.sqrt(DIVERGENCE_HEIGHT / standing_height)


def too_fast(
    v: Sequence[float], standing_height: float, scale: float, factors: Sequence[float]
) -> tuple[int, float, float] | None:
    """The first coordinate of ``v`` past the divergence limit, as (its index, its speed, its
    limit), or None. A ``--scale L`` run (``scale`` L, ``factors`` each coordinate's Table 1
    factor; 1 and ones otherwise) is held to the scaled creature's limit, brought to the
    model's numbers (its message tells both as the scaled creature's), so that it diverges
    when the file ``legdsl scale`` writes would."""
    most = divergence_speed(scale * standing_height)
    for k, x in enumerate(v):
        if abs(x) > most / factors[k]:
            return k, abs(x), most / factors[k]
    return None
