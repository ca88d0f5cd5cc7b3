"""The kangaroo's jump at 4 m/s into a 30 cm box at x = 10.6 m (reported from outside): its toe
enters through the box's side face 1.2 ms after a sample at the default record rate (5.2 ms),
is thrown out before the next, and the run diverges. The likely cause blamed the joint
limits the blow-up passed ("joint coordinate hip = 7.38 is past its limits") at the default
rate, and named the touchdown only at --record-rate 0, where the push is sampled. It is
judged from the ground's own touchdown events now (``legdsl.sim.causes.touched_deep``), so
both rates name the same cause."""

from __future__ import annotations

from pathlib import Path

from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions

ROOT = Path(__file__).resolve().parents[2]


def test_a_touchdown_between_samples_is_named_at_any_record_rate(
    tmp_path: Path, generated: Path
) -> None:
    text = (ROOT / "creatures" / "kangaroo.leg").read_text()
    anchor = "  ground {"
    assert text.count(anchor) == 1
    leg = tmp_path / "kangaroo.leg"
    box = "    terrain box(x0 = 10.6 m, x1 = 10.9 m, height = 0.3 m)\n"
    leg.write_text(text.replace(anchor, anchor + "\n" + box, 1))
    sess = RunSession.from_file(leg, generated=generated)
    for rate in (200.0, 0.0):
        options = RunOptions(duration=4.6, record_rate=rate)
        result = sess.run("jump", ["speed=4m/s"], options=options, backend="python").result
        assert result.status == "diverged", rate
        cause = result.message.split("Likely cause: ", 1)[1]
        assert cause.startswith("contact 'toe' touched down far under the surface"), (rate, cause)
        assert "at t = 4.5668 s" in cause
        assert "the side of a step or box" in cause
