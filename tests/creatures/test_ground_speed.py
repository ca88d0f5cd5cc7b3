"""Ground speed matching (raibert's place_two_link_matched, the kangaroo's `match_window`) and
the metrics that measure it: the toe's speed over the ground at touchdown and the friction
it needs in the first 10 ms of stance (docs/kangaroo.md has the 20 s runs at 5 m/s)."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import CREATURES

from legdsl.pipeline.measure import measure_run
from legdsl.pipeline.scaled import run_options
from legdsl.pipeline.session import RunSession


def _measured(generated: Path, out: Path, *settings: str) -> dict[str, float]:
    session = RunSession.from_file(CREATURES / "kangaroo.leg", generated=generated)
    options = run_options(session.model, duration=5.0)
    run = session.run("hop", ["speed=5m/s", *settings], options=options)
    assert run.status == "ok"
    run.write(out)
    metrics, _ = measure_run(out, t_from=3.0, generated=generated)
    return {s.key: s.value for s in metrics.summaries}


@pytest.fixture(scope="module")
def both(generated: Path, tmp_path_factory: pytest.TempPathFactory):  # type: ignore[no-untyped-def]
    base = tmp_path_factory.mktemp("gm")
    return _measured(generated, base / "off"), _measured(
        generated, base / "on", "match_window=50ms"
    )


def test_without_matching_the_toe_lands_at_the_bodys_speed(both) -> None:  # type: ignore[no-untyped-def]
    off, _ = both
    assert off["touchdown_foot_speed"] > 4.0  # the toe moves with the body (about 5 m/s)
    assert off["friction_first_toe"] > off["friction_interior_toe"]


def test_matching_slows_the_toe_and_needs_less_friction_at_touchdown(both) -> None:  # type: ignore[no-untyped-def]
    off, on = both
    assert on["touchdown_foot_speed"] < 0.6 * off["touchdown_foot_speed"]
    assert on["friction_first_toe"] < 0.5 * off["friction_first_toe"]
