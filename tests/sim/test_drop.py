"""A passive drop of each shipped creature from 0.3 m: it lands, bounces on its springs and comes to rest.

Checked: total energy (kinetic + gravitational + elastic) never rises; at the
end nothing moves; the ground carries the whole weight; and each contact's
penetration is the static value of the declared ground spring for the load it
carries (mg/k shared by symmetric feet; eq. (6) inverted for the paw pad).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import CREATURES

from legdsl.check.source import check_model
from legdsl.ir.model import Pad
from legdsl.pipeline.generated import load_dynamics
from legdsl.sim.run_loop import RunOptions
from legdsl.sim.simulate import Simulation


@pytest.mark.parametrize("name", ["kangaroo", "biped", "quadruped"])
def test_passive_drop_comes_to_rest_at_the_static_penetration(name: str, generated: Path) -> None:
    source = CREATURES / f"{name}.leg"
    model = check_model(source)
    dyn = load_dynamics(model, source, generated)
    sim = Simulation(model, dyn, RunOptions(duration=6.0, drop=0.3))
    result = sim.run()
    assert result.status == "ok", result.message
    tr = result.trajectory
    assert sum(e["kind"] == "touchdown" for e in result.events) >= len(model.contacts)

    energy = tr.kinetic + tr.potential + tr.elastic
    rises = np.diff(energy)
    assert rises.max() < 1e-6 * energy[0]  # never rises, beyond round-off
    assert energy[-1] < 0.9 * energy[0]  # the landing dissipated some of it

    late = tr.t > tr.t[-1] - 0.5
    assert np.abs(tr.v[late]).max() < 0.02  # at rest

    weight = tr.total_mass * tr.gravity
    loads = tr.force[-1, :, 2]
    assert loads.sum() == pytest.approx(weight, rel=0.02)
    feet = dyn.contact_positions(list(tr.q[-1]))
    ground = model.ground
    assert ground is not None
    for load, foot in zip(loads, feet, strict=True):
        if load <= 0:
            continue
        if isinstance(ground.normal, Pad):
            static = ground.normal.thickness * load / (ground.normal.k + load)  # eq. (6) inverted
        else:
            static = load / ground.normal.k
        assert -foot[2] == pytest.approx(static, rel=0.02)
    if name != "kangaroo":  # symmetric feet share the weight: penetration mg / (n k)
        n = len(model.contacts)
        assert -feet[0][2] == pytest.approx(weight / (n * ground.normal.k), rel=0.02)
