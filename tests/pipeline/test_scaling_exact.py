"""docs/scaling.md: "With L a power of 4, sqrt(L) is a power of 2 and every factor is one":
each scaled number is the original's times a power of two. Where the scaled file's generated
code keeps the original's order (the hopper, the kangaroo) that is bit for bit: the run of the
file ``legdsl scale`` writes, the ``legdsl run --scale L`` run and the original's run brought
back by Table 1 are the same doubles; where it does not (the outside tailpod), to an ulp. At L = 1024 the file held its numbers to 14 digits only (5 N*s/m scaled by
1024^2.5 printed ``1.49011611938477e-07``, the double is 1.4901161193847656e-07), and its run
parted from the other two by 1e-15."""

from __future__ import annotations

import math
import re
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest
from conftest import CREATURES, OUTSIDE

from legdsl.check.source import check_file
from legdsl.cli import main
from legdsl.cli.common import EXIT_DIVERGED
from legdsl.ir.model import Model
from legdsl.lang.scaling import format_number, scale_source
from legdsl.pipeline.generated import load_dynamics
from legdsl.pipeline.scaled import q_factors, scale_trajectory, v_factors
from legdsl.sim.trajectory import ARRAYS, Trajectory

SCALES = [4.0, 1024.0, 1 / 1024, 4.0**10]
TIME = 0.25  # s of the original: a touchdown of each (the hopper's at 0.178 s)


def _same(a: Trajectory, b: Trajectory) -> list[str]:
    """The arrays in which the two runs differ in any bit (NaN equal to NaN)."""
    assert len(a) == len(b) > 0
    return [
        name
        for name in ARRAYS
        if not np.array_equal(getattr(a, name), getattr(b, name), equal_nan=True)
    ]


# the hopper at every factor; the kangaroo (4 s of the suite's time each) at the two that
# parted from the exact run before the scaled file's numbers were written whole
CASES = [("hopper", s) for s in SCALES] + [("kangaroo", SCALES[1]), ("kangaroo", SCALES[2])]


@pytest.mark.parametrize(("name", "scale"), CASES, ids=[f"{n}-{s:g}" for n, s in CASES])
def test_a_power_of_4_scales_bit_for_bit(
    name: str, scale: float, generated: Path, tmp_path: Path
) -> None:
    source = CREATURES / f"{name}.leg"
    out = tmp_path / f"{name}_scaled.leg"
    assert main(["scale", str(source), "--by", repr(scale), "-o", str(out)]) == 0
    time = repr(TIME * math.sqrt(scale))
    common = ["--controller", "hop", "--generated", str(generated), "--backend", "python"]
    runs = {
        "original": [str(source), "--time", repr(TIME)],
        "file": [str(out), "--time", time],
        "scaled": [str(source), "--time", time, "--scale", repr(scale)],
    }
    ends = {
        run: main(["run", *args, *common, "--out", str(tmp_path / run)])
        for run, args in runs.items()
    }
    file, scaled = Trajectory.load(tmp_path / "file"), Trajectory.load(tmp_path / "scaled")
    (model,) = check_file(source)
    original = scale_trajectory(Trajectory.load(tmp_path / "original"), model, scale)
    assert ends["original"] == 0
    assert ends["file"] == ends["scaled"]
    assert _same(file, scaled) == []
    if ends["file"] == EXIT_DIVERGED:
        # 4^10 as large (the hopper 945 km tall), a creature falls faster than 1000 m/s, the
        # divergence rule's limit above 10 cm (docs/scaling.md), within 0.1 s of the original's
        # time: the two scaled runs stop there alike; the original's samples until then are theirs
        assert scale == 4.0**10 and len(file) >= 10
        original = original.head(len(file))
    else:
        assert ends["file"] == 0
        assert file.t[-1] == pytest.approx(TIME * math.sqrt(scale), rel=0.01)
    assert _same(file, original) == []


def test_every_scaled_number_reads_back_as_the_same_double() -> None:
    """The numbers are Python's shortest round-trip texts; short numbers stay short."""
    value = 5 * 1024**-2.5
    assert format_number(value) == "1.4901161193847656e-07"
    assert float(format_number(value)) == value
    assert float(format_number(0.4 * math.sqrt(2))) == 0.4 * math.sqrt(2)
    assert [format_number(x) for x in (0.68, 2400.0, 1e-5, 1e16, 0.5, 3.0)] == [
        "0.68", "2400", "1e-05", "1e16", "0.5", "3"]  # fmt: skip
    text = (CREATURES / "hopper.leg").read_text(encoding="utf-8")
    small = scale_source(text, 1 / 1024)
    assert "spring(k = 0.00286102294921875 N/m, b = 1.4901161193847656e-07 N*s/m," in small
    assert "mass 10 kg" not in small and "rest = 0 m" in small


def _dynamics(source: Path, generated: Path) -> tuple[Model, ModuleType]:
    (model,) = check_file(source)
    return model, load_dynamics(model, source, generated)


def _masked(module: ModuleType) -> str:
    """The generated code after its header, its numbers masked: the order of its arithmetic."""
    text = Path(str(module.__file__)).read_text(encoding="utf-8")
    return re.sub(
        r"\d[\d.]*(e-?\d+)?", "#", text.split("MODEL_FINGERPRINT", 1)[1].split("\n", 1)[1]
    )


@pytest.mark.parametrize(("name", "exact"), [("hopper", True), ("tailpod", False)])
def test_a_power_of_4_is_exact_where_the_generated_sums_keep_their_order(
    name: str, exact: bool, tmp_path: Path
) -> None:
    """docs/scaling.md said every run at a power of 4 is bit-identical; an outside 3D hopper
    with a full inertia tensor (tailpod) parts by an ulp at L = 4. The code is generated with
    the constants as numbers, and sympy orders a sum's terms by them: a mass (L^3) and an
    inertia (L^5) can change places, and the sum rounds otherwise. What holds: where the scaled
    file's code computes in the original's order (the hopper), its dynamics are the original's
    brought back bit for bit; where it does not, to an ulp or so."""
    source = CREATURES / "hopper.leg" if exact else OUTSIDE / "tailpod.leg"
    out = tmp_path / f"{name}_x4.leg"
    assert main(["scale", str(source), "--by", "4", "-o", str(out)]) == 0
    (model, original), (_, scaled) = (_dynamics(f, tmp_path / "gen") for f in (source, out))
    if not exact:  # the same arithmetic in another order (the hopper's differs by 1 * x alone)
        assert _masked(original) != _masked(scaled)
    rng = np.random.default_rng(4)
    q = np.array(model.q0) + rng.normal(0.0, 0.1, len(model.q0))
    for joint in model.joints:  # a free joint's quaternion stays a unit one
        if joint.is_free_3d:
            turn = slice(joint.q_start + 3, joint.q_start + 7)
            q[turn] /= np.linalg.norm(q[turn])
    v, tau = rng.normal(0.0, 1.0, len(model.v0)), rng.normal(0.0, 1.0, len(model.v0))
    turning = np.array(model.v_angular, dtype=float)  # generalized forces L^3, torques L^4
    by = 4.0 ** (3.0 + turning)
    q4, v4 = (q * q_factors(model, 4.0)).tolist(), (v * v_factors(model, 4.0)).tolist()
    assert np.array_equal(np.array(scaled.mass_matrix(q4)),
                          np.array(original.mass_matrix(q.tolist())) * np.outer(by, by) / 4.0**3)  # fmt: skip
    accel = np.array(original.forward_dynamics(q.tolist(), v.tolist(), tau.tolist()))
    accel4 = np.array(scaled.forward_dynamics(q4, v4, (tau * by).tolist())) * 4.0**turning
    assert np.array_equal(accel4, accel) is exact
    assert np.allclose(accel4, accel, rtol=1e-14, atol=0.0)
