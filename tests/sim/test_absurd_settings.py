"""A huge value passed to a controller's action (reported from outside): the hopper's THRUST
calling ``hop_apex(active, 1e308 m, ...)`` or ``hop_apex(..., -1e308 * stroke, 1)`` sets the
leg spring's rest to 1e308 m; its force overflows and the run diverges. The likely cause was
"the state grew without bound; try a smaller step ... or --integrator rk4", and the advice
diverged the same way. It names the statement that set the rest and the value now
(``legdsl.sim.absurd_settings``)."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions

ROOT = Path(__file__).resolve().parents[2]
THRUST = "hop_apex(active, 0 m, height + apex_trim, 0 m, 3 * stroke, 1)"


@pytest.mark.parametrize(
    ("call", "value"),
    [
        ("hop_apex(active, 1e308 m, height + apex_trim, 0 m, 3 * stroke, 1)", "1e+308 m"),
        ("hop_apex(active, 0 m, height + apex_trim, 0 m, -1e308 * stroke, 1)", "e+306 m"),
    ],
)
def test_a_rest_set_past_reason_is_named_at_its_statement(
    tmp_path: Path, generated: Path, call: str, value: str
) -> None:
    text = (ROOT / "creatures" / "hopper.leg").read_text()
    assert text.count(THRUST) == 1
    leg = tmp_path / "hopper.leg"
    leg.write_text(text.replace(THRUST, call))
    line = next(n for n, row in enumerate(leg.read_text().splitlines(), 1) if call in row)
    sess = RunSession.from_file(leg, generated=generated)
    result = sess.run("hop", [], options=RunOptions(duration=1.0), backend="python").result
    assert result.status == "diverged"
    cause = result.message.split("Likely cause: ", 1)[1]
    assert cause.startswith("the controller set leg_spring.rest = "), cause
    assert value in cause.split(" at ", 1)[0]
    assert f"hopper.leg:{line}:" in cause
    assert "raibert.leg" in cause  # the action's own statement, inlined from the call
    assert "smaller step" not in cause and "rk4" not in cause
