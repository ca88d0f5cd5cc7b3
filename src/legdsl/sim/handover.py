"""Where a controller takes over a moving creature: the state and role binding that match
which feet are down (``legdsl run --switch``; docs/runtime.md, "Changing controllers").

A controller's table says, through its contact events, which feet are down in each state:
``touchdown(X)`` entered a state with one of X's feet down, ``liftoff(X)`` with none of them,
and a state entered on any other condition keeps what its predecessor knew. Walking the
table's cycle of (binding, state) pairs twice, as the machine would run it, gives every pair
its *contact facts*, most recent first, each over concrete feet (a role is resolved under the
binding that waited for the event). When a controller takes over at time t:

1. every pair of the cycle is scored against the feet down now: fewer facts contradicted
   first, then the most recent of its facts that holds made true latest (by the foot whose
   contact last changed the way the fact says), so that of two mirror-image flights the one
   whose leg just lifted off wins, and of two stances the one whose leg landed last;
2. the best pairs form stretches of consecutive states (e.g. LOADING, COMPRESSION, THRUST,
   UNLOADING with the same foot down); of the chosen stretch the machine starts in the last
   state whose own event holds now (its time in state 0), else the stretch's first: mid-thrust
   that is THRUST, just after a landing LOADING.

A role bound to several legs (the trot's diagonals, the bound's pairs, a tripod) is down while
any of its feet is, as its events are: a fact holds with the role only partly down
(``split``), at an edge of its stance, its first feet landed or its last ones about to leave.
The contacts cannot tell which (the gallop gives the trot both, with the same order of
touchdowns and liftoffs), so ``on_liftoff`` waits for the role's feet to agree; a takeover
without a liftoff (``HANDOVER_WAIT``, a table without liftoff events) counts it as down.

Everything here reads the controller IR (``legdsl.ir.controller``) and the model's legs;
the events themselves are evaluated with the generated module's ``EVENTS``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

from legdsl.ir import controller as ir
from legdsl.ir.model import Model


@dataclass(frozen=True)
class Fact:
    """At least one of ``feet`` touches (``down``), or none of them does."""

    feet: frozenset[str]  # contact names
    down: bool


@dataclass(frozen=True)
class Pair:
    """One step of the table's cycle: the binding a state runs under, the binding that waited
    for its event, and what is known of the feet on entering it (most recent fact first)."""

    binding: int
    state: int
    waited: int
    facts: tuple[Fact, ...]


def _contact_events(e: ir.Expr) -> list[ir.Event]:
    """The contact events a condition requires: the event itself, or those of an ``and``;
    of an ``or``, those of its first alternative, the way the table enters the state when
    its feet do as expected (the others are fallbacks: the outside knee quadruped's bound
    enters FLIGHT ``on liftoff(active) or touchdown(idle)``; read as no fact, its FLIGHT
    knew the active pair down, the table had no liftoff and the gallop took over from it at
    once, in a stance of the wrong pair: docs/quadruped.md, "Changing gait" of the knee
    quadruped)."""
    if isinstance(e, ir.Event):
        return [e]
    if isinstance(e, ir.Binary) and e.op == "and":
        return _contact_events(e.left) + _contact_events(e.right)
    if isinstance(e, ir.Binary) and e.op == "or":
        return _contact_events(e.left)
    return []


def _feet(model: Model, thing: ir.Thing, roles: Mapping[str, tuple[str, ...]]) -> frozenset[str]:
    """The foot contacts an event watches under one binding."""
    feet = {leg.name: leg.foot for leg in model.legs}
    if isinstance(thing, ir.Legs):
        legs = roles[thing.role] if thing.role is not None else (thing.leg or "",)
        return frozenset(feet[leg] for leg in legs if leg in feet)
    if isinstance(thing, ir.Part) and thing.kind == "contact":
        return frozenset([thing.name])
    if isinstance(thing, ir.Alias) and thing.kind == "contact":
        legs = roles[thing.legs.role] if thing.legs.role is not None else (thing.legs.leg or "",)
        aliases = {leg.name: dict(leg.aliases) for leg in model.legs}
        return frozenset(
            aliases[leg][thing.alias] for leg in legs if thing.alias in aliases.get(leg, {})
        )
    return frozenset()


def _learn(facts: tuple[Fact, ...], new: Fact) -> tuple[Fact, ...]:
    """The facts after an event: the new one first; older ones about any of its feet dropped."""
    return (new, *(f for f in facts if not f.feet & new.feet))


def cycle(model: Model, ctl: ir.Controller) -> list[Pair]:
    """The (binding, state) pairs the table runs through from its start, in order, each with
    its contact facts as known after a full lap."""
    after = dict(ctl.after_entry)
    n = len(ctl.states)
    start = ctl.state_names.index(ctl.start)
    order: list[tuple[int, int, int]] = []  # (binding, state, waited)
    seen: dict[tuple[int, int], int] = {}
    b, i, waited = 0, start, 0
    while (b, i) not in seen:
        seen[(b, i)] = len(order)
        order.append((b, i, waited))
        j = (i + 1) % n
        waited, b, i = b, after.get((b, j), b), j
    loop = order[seen[(b, i)] :]  # the pairs that repeat (a start outside the loop is left)
    # each waits under the binding of the one before it in the loop (the start, too)
    loop = [(b, i, loop[k - 1][0]) for k, (b, i, _) in enumerate(loop)]
    facts: dict[tuple[int, int], tuple[Fact, ...]] = {}
    known: tuple[Fact, ...] = ()
    for _lap in range(2):
        for b, i, w in loop:
            roles = dict(ctl.bindings[w])
            for event in _contact_events(ctl.states[i].event):
                feet = _feet(model, event.thing, roles)
                if feet:
                    known = _learn(known, Fact(feet, event.kind == "touchdown"))
            facts[(b, i)] = known
    return [Pair(b, i, w, facts[(b, i)]) for b, i, w in loop]


@dataclass(frozen=True)
class Clock:
    """One foot now: down or not, and when it last touched down and lifted off (NaN: never)."""

    down: bool
    touchdown: float
    liftoff: float


def _score(facts: Sequence[Fact], feet: Mapping[str, Clock]) -> tuple[int, float]:
    """(facts contradicted, when the most recent fact that holds was last made true: later
    is better)."""
    held = [f for f in facts if any(feet[c].down for c in f.feet if c in feet) == f.down]
    recent = -math.inf
    if held:
        f = held[0]
        times = [feet[c].touchdown if f.down else feet[c].liftoff for c in f.feet if c in feet]
        times = [x for x in times if math.isfinite(x)]
        recent = max(times) if times else -math.inf
    return len(facts) - len(held), recent


def split(fact: Fact, feet: Mapping[str, Clock]) -> bool:
    """Whether a ``touchdown`` fact over several feet holds through some of them only: the
    role (a virtual leg) is at an edge of its stance, its first feet landed or its last ones
    about to leave, and which the contacts cannot tell."""
    down = [feet[c].down for c in fact.feet if c in feet]
    return fact.down and any(down) and not all(down)


def lands_on(pairs: Sequence[Pair], k: int) -> frozenset[str]:
    """The feet the table lands on next after ``pairs[k]``: those of the first touchdown fact
    learned after it, round the cycle (none if it learns none)."""
    n = len(pairs)
    for j in range(1, n + 1):
        facts = pairs[(k + j) % n].facts
        if facts and facts[0].down and facts[0] not in pairs[k].facts:
            return facts[0].feet
    return frozenset()


def on_liftoff(
    pairs: Sequence[Pair],
    feet: Mapping[str, Clock],
    t: float,
    soon: frozenset[str] = frozenset(),
) -> bool:
    """Whether a controller whose table runs through ``pairs`` can take over at ``t`` as a
    foot leaves the ground: a pair of it contradicts no contact fact, none of its roles has
    only some of its feet down (``split``), one of its facts is a liftoff made true at
    ``t`` (``take_over`` then chooses that pair), and the feet about to land (``soon``) are
    among those it lands on next (``lands_on``). A role whose feet disagree waits: the
    quadruped's trot taking over from the gallop as ``toe_fl`` lifted, with ``toe_fr`` of
    its diagonal (fr, rl) still down, started in that pair's LOADING, which waits for its
    compression while ``toe_fr`` left 7.6 ms later, and lost a step; the gallop's front pair
    landing a foot at a time looks the same to the contacts (docs/runtime.md). A foot about
    to land that the new table does not land on next was aimed at the ground by the old one:
    the outside knee quadruped's bound and gallop leave the rear pair with the front pair
    0 to 100 ms from the ground, and the trot (to land a diagonal) taking over there fell
    within 0.6 s; the gallop (to land the front pair) takes over there."""

    def lifted_now(f: Fact) -> bool:
        return not f.down and any(feet[c].liftoff == t for c in f.feet if c in feet)

    return any(
        _score(p.facts, feet)[0] == 0
        and not any(split(f, feet) for f in p.facts)
        and any(map(lifted_now, p.facts))
        and soon <= lands_on(pairs, k)
        for k, p in enumerate(pairs)
    )


def lifts_off(pairs: Sequence[Pair]) -> bool:
    """Whether the table has a liftoff event (else there is no moment to wait for)."""
    return any(not f.down for p in pairs for f in p.facts)


def take_over(
    pairs: Sequence[Pair], feet: Mapping[str, Clock], holds: Callable[[Pair], bool]
) -> Pair:
    """The pair a controller starts in, given each foot's ``Clock`` now; ``holds(pair)`` says
    whether the pair's own entry event holds now (evaluated under ``pair.waited``)."""
    scores = [_score(p.facts, feet) for p in pairs]
    best = min(scores, key=lambda s: (s[0], -s[1]))
    good = [s == best for s in scores]
    n = len(pairs)
    # stretches of consecutive best pairs, cyclically; the first stretch found by recency wins
    first = next(
        (k for k in range(n) if good[k] and not good[(k - 1) % n]), 0 if all(good) else None
    )
    assert first is not None
    stretch = [first]
    while len(stretch) < n and good[(stretch[-1] + 1) % n]:
        stretch.append((stretch[-1] + 1) % n)
    chosen = stretch[0]
    for k in stretch:
        if holds(pairs[k]):
            chosen = k
    return pairs[chosen]
