"""The divergence rule's speed limit follows the creature's size: 1000 m/s or rad/s for one
10 cm tall or taller (every shipped creature), more for a smaller one, whose joints turn
faster as 1/sqrt(its size) (Table 1)."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from legdsl.cli import main
from legdsl.sim.sizes import DIVERGENCE_SPEED, divergence_speed

ROOT = Path(__file__).resolve().parents[2]
POGO = ROOT / "tests" / "good" / "outside" / "insect_pogo.leg"


def test_the_limit_is_1000_from_10_cm_up_and_grows_as_one_over_sqrt_below() -> None:
    for height in (0.0, 0.1, 0.3351, 0.83, 24.0):  # 0: a root welded to the world
        assert divergence_speed(height) == DIVERGENCE_SPEED
    assert divergence_speed(0.001) == pytest.approx(1e4)


@pytest.mark.parametrize("backend", ["python", "c"])
def test_a_speck_scaled_from_the_insect_pogo_hops_without_being_called_diverged(
    backend: str, tmp_path: Path
) -> None:
    """The 3 g pogo scaled by 1/2000 (33 um tall) swings its hip at up to 1394 rad/s as it
    hops (the limit for it: about 55000): it was stopped as diverged at 5.9 ms, on either backend."""
    speck = tmp_path / "speck.leg"
    assert main(["scale", str(POGO), "--by", "0.0005", "-o", str(speck)]) == 0
    code = main(["run", str(speck), "--controller", "hop", "--time", "0.01", "--backend",
                 backend, "--generated", str(tmp_path / "gen"), "--out", str(tmp_path / "r")])  # fmt: skip
    assert code == 0
    assert json.loads((tmp_path / "r" / "run.json").read_text())["status"] == "ok"


@pytest.mark.parametrize("backend", ["python", "c"])
def test_a_giant_falling_past_the_limit_is_told_so_not_to_take_a_smaller_step(
    backend: str, generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The hopper 950 km tall (L = 1e6) falls past 1000 m/s in its first flight: it was told
    'the state grew without bound; try a smaller step or --integrator rk4', which changes
    nothing. It is told its own fall reached the fixed limit, and the --time that ends before."""
    common = ["run", str(ROOT / "creatures" / "hopper.leg"), "--controller", "hop", "--scale",
              "1e6", "--backend", backend, "--generated", str(generated)]  # fmt: skip
    assert main([*common, "--time", "1000", "--out", str(tmp_path / "a")]) == 3
    err = capsys.readouterr().err
    assert "grew without bound;" not in err and "rk4" not in err
    said = re.search(r"nothing grew without bound: the creature reached this speed falling "
                     r"\(\S+ m/s down .* a --time under (\S+) s ends the run before it", err)  # fmt: skip
    assert said is not None, err
    before = float(said[1]) - 1.0
    assert main([*common, "--time", f"{before:g}", "--out", str(tmp_path / "b")]) == 0
    assert json.loads((tmp_path / "b" / "run.json").read_text())["status"] == "ok"


STIFF = """creature stiffsp {
  planar
  body base fixed at (0 m, 2 m) { mass 1 kg  inertia 0.01 kg*m^2 }
  body arm on base via revolute sh {
    length 1 m  com 0.8 m  mass 2 kg  inertia 0.05 kg*m^2
    initial 90 deg
  }
  actuator clip on sh spring(k = 1e8 N*m/rad, rest = 80 deg)
}
"""


@pytest.mark.parametrize(("backend", "dt"), [("python", "0.1ms"), ("c", "0.1ms"), ("c", "0.01ms")])
def test_a_stiff_springs_real_speed_past_the_limit_is_told_from_its_energy(
    backend: str, dt: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A pendulum on a 1e8 N*m/rad spring 10 deg from its rest: the spring's 1.52e6 J turn
    it at up to 1513 rad/s. At 0.1 ms it passed the limit in its first step, before a sample
    at half of it was recorded, and was told 'the state grew without bound; try a smaller
    step', which changes nothing; it is told from the energy it has, and where that is."""
    leg = tmp_path / "stiff.leg"
    leg.write_text(STIFF)
    argv = ["run", str(leg), "--time", "1", "--dt", dt, "--control-dt", dt, "--backend", backend,
            "--generated", str(tmp_path / "gen"), "--out", str(tmp_path / "r")]  # fmt: skip
    assert main(argv) == 3
    err = capsys.readouterr().err
    assert "grew without bound;" not in err and "rk4" not in err and "this large" not in err
    assert "nothing grew without bound: the creature reached this speed in its own motion" in err
    assert "its springs held 1.52e+06 J at the start (1.52e+06 J of it in 'clip')" in err
    assert "enough for sh to reach 1513 rad/s" in err and "a softer spring" in err
