"""The quadruped's controllers on a quadruped of other proportions (docs/scripts/
stocky_quadruped.py: a heavier trunk, hips closer fore and aft and wider apart, shorter
thighs): with the values the searches found for it, it trots, paces and bounds with the
pairs landing together and the speed within 5% of the command (docs/quadruped.md, "A
quadruped of other proportions"). It is compiled here from its own file, as a user's
creature would be."""

from __future__ import annotations

import importlib.util

import numpy as np
import pytest
from conftest import ROOT

SCRIPT = ROOT / "docs" / "scripts" / "stocky_quadruped.py"
PAIRS = {"trot": ({"toe_fl", "toe_rr"}, {"toe_fr", "toe_rl"}),
         "pace": ({"toe_fl", "toe_rl"}, {"toe_fr", "toe_rr"}),
         "bound": ({"toe_fl", "toe_fr"}, {"toe_rl", "toe_rr"})}  # fmt: skip


@pytest.fixture(scope="module")
def stocky(tmp_path_factory: pytest.TempPathFactory):  # type: ignore[no-untyped-def]
    import legdsl

    spec = importlib.util.spec_from_file_location("stocky_quadruped", SCRIPT)
    assert spec is not None and spec.loader is not None
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    tmp = tmp_path_factory.mktemp("stocky")
    leg = script.write_stocky(tmp / "stocky.leg", tuned=True)
    return legdsl.load(leg, generated=tmp / "generated")


@pytest.mark.parametrize(("gait", "speed"), [("trot", 2.0), ("pace", 1.5), ("bound", 2.8)])
def test_a_quadruped_of_other_proportions_runs_the_gaits(stocky, gait: str, speed: float) -> None:  # type: ignore[no-untyped-def]
    run = stocky.run(controller=gait, set={"speed": f"{speed} m/s"}, time=10)
    assert run.status == "ok", run.info.get("message")
    times, x = run.samples["t"], run.samples["q.x"]
    i = int(np.searchsorted(times, 3.0))
    assert (x[-1] - x[i]) / (times[-1] - times[i]) == pytest.approx(speed, rel=0.05)
    downs = [(e["t"], e["contact"]) for e in run.info["events"] if e["kind"] == "touchdown"]
    later = [(t, c) for t, c in downs if t > 3.0]
    together = [{c for t2, c in later if abs(t2 - t) < 0.01} for t, _ in later]
    assert len(later) >= 20
    assert np.mean([p in PAIRS[gait] for p in together]) > 0.9  # the pairs land as pairs
