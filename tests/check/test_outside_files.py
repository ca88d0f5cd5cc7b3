"""Every creature written outside the team (tests/good/outside/) checks clean: they are
what the docs point new users at, and each takes the shipped files' parts through 'use'
and 'extends', so a change to those that breaks a user's file fails here. (A few are passive:
dropped to test the ground and the exports, they have no controller.)"""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.check.source import check_file
from legdsl.lang.errors import LegError

OUTSIDE = Path(__file__).resolve().parents[1] / "good" / "outside"


@pytest.mark.parametrize("name", sorted(p.name for p in OUTSIDE.glob("*.leg")))
def test_checks_clean(name: str) -> None:
    models = check_file(OUTSIDE / name)
    assert models and all(m.bodies for m in models)


@pytest.mark.parametrize("rest", ["-40 deg", "stand"])
def test_a_knee_action_given_a_telescoping_quadruped_is_told_at_the_leg(
    tmp_path: Path, rest: str
) -> None:
    """level_feet_rotary (stdlib/raibert.leg, for knee legs in a quadruped's roles) given the
    shipped quadruped's telescoping legs is told at the leg argument, as the other knee actions;
    with the telescoping leg's own rest (a length, `stand`) too, which said only "sin() takes
    an angle, not a length" inside the action."""
    shipped = OUTSIDE.parents[2] / "creatures" / "quadruped.leg"
    text = shipped.read_text(encoding="utf-8") + (
        "controller t2 {\n  path route\n  include quadruped_gains\n"
        "  roles active = (fl, rr), idle = (fr, rl)\n  table {\n"
        f"    state A on liftoff(active): level_feet_rotary(active, {rest}, 0.4 m, 0.4 m)\n"
        "    state B on touchdown(active): relax(active, stand)\n  }\n}\n"
    )
    leg = tmp_path / "quadruped.leg"
    leg.write_text(text, encoding="utf-8")
    with pytest.raises(LegError) as err:
        check_file(leg)
    message = str(err.value)
    assert "action 'level_feet_rotary' is written for a leg whose 'spring' is rotary" in message
    assert "'leg_fl_spring', is sliding" in message
