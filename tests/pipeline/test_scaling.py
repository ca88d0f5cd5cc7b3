"""Dynamic scaling (Table 1 of the paper), both ways: the file ``legdsl scale`` writes and the
run ``legdsl run --scale`` makes agree sample by sample (docs/scaling.md)."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
from conftest import CREATURES

from legdsl.check.source import check_file
from legdsl.cli import main
from legdsl.lang.scaling import exponent, factor, format_number, scale_name, scale_source
from legdsl.lang.units import KINDS, parse_unit
from legdsl.pipeline.scaled import run_options
from legdsl.sim.trajectory import ARRAYS, Trajectory

# Table 1 of Raibert & Hodgins (1991), and the rest of the units by the same rule
TABLE_1 = {
    "m": 1,
    "kg": 3,
    "s": 0.5,
    "m/s": 0.5,
    "m/s^2": 0,
    "N": 3,
    "N*m": 4,
    "J": 4,
    "W": 3.5,
    "N/m": 2,
    "N*s/m": 2.5,
    "N*m/rad": 4,
    "N*m*s/rad": 4.5,
    "kg*m^2": 5,
    "Hz": -0.5,
    "rad/s": -0.5,
    "deg": 0,
    "deg/m": -1,
    "rad/s^2": -1,
    "deg/s": -0.5,
}


@pytest.mark.parametrize(("unit", "power"), TABLE_1.items())
def test_each_unit_scales_as_table_1_says(unit: str, power: float) -> None:
    dim = parse_unit(unit)[1]
    assert exponent(dim) == power
    assert factor(dim, 4.0) == pytest.approx(4.0**power, rel=1e-15)


def test_numbers_print_short_and_exact() -> None:
    assert format_number(0.34 * 2) == "0.68"
    assert format_number(150 * 16) == "2400"
    assert format_number(1e-5) == "1e-05"
    value = 0.4 * math.sqrt(0.5)
    assert abs(float(format_number(value)) - value) <= 1e-14 * value
    assert scale_name("kangaroo", 2) == "kangaroo_x2"
    assert scale_name("biped", 0.5) == "biped_x0_5"


@pytest.mark.parametrize("name", ["kangaroo", "biped", "hopper", "quadruped"])
def test_the_scaled_file_checks_keeps_its_comments_and_scales_every_quantity(
    name: str, tmp_path: Path
) -> None:
    source = CREATURES / f"{name}.leg"
    text = source.read_text(encoding="utf-8")
    out = tmp_path / f"{name}_x2.leg"
    out.write_text(scale_source(text, 2.0, str(source)), encoding="utf-8")
    scaled_text = out.read_text(encoding="utf-8")
    assert scaled_text.startswith(f"# {source} scaled by L = 2")
    comments = [line for line in text.splitlines() if line.lstrip().startswith("#")]
    assert all(c in scaled_text for c in comments)
    (small,) = check_file(source)
    (big,) = check_file(out)
    assert big.name == f"{name}_x2"
    assert [c.name for c in big.controllers] == [c.name for c in small.controllers]
    for a, b in zip(small.bodies, big.bodies, strict=True):
        assert b.mass == pytest.approx(8 * a.mass, rel=1e-13)
        assert np.allclose(np.asarray(b.inertia), 32 * np.asarray(a.inertia), rtol=1e-13)
        assert np.allclose(np.asarray(b.com), 2 * np.asarray(a.com), rtol=1e-13, atol=0)
        assert (b.length or 0) == pytest.approx(2 * (a.length or 0), rel=1e-13)
    slides = [d.motion == "slide" for j in small.joints for d in j.dofs]
    if not any(j.is_free_3d for j in small.joints):
        want = [x * (2 if slide else 1) for x, slide in zip(small.q0, slides, strict=True)]
        assert big.q0 == pytest.approx(want, rel=1e-13)
    for a, b in zip(small.actuators, big.actuators, strict=True):
        for (key, value), (_, new) in zip(a.params, b.params, strict=True):
            assert new == pytest.approx(value * _actuator_factor(key, a.rotary), rel=1e-13)
        if a.max is not None:
            assert b.max == pytest.approx(a.max * _actuator_factor("max", a.rotary), rel=1e-13)
    for ca, cb in zip(small.controllers, big.controllers, strict=True):
        for x, y in zip((*ca.inputs, *ca.params), (*cb.inputs, *cb.params), strict=True):
            assert y.value == pytest.approx(x.value * factor(x.dim, 2.0), rel=1e-13, abs=0)
    assert big.simulation.dt == pytest.approx(0.0004 * math.sqrt(2), rel=1e-14)
    assert big.simulation.control_dt == pytest.approx(0.002 * math.sqrt(2), rel=1e-14)
    assert big.simulation.record_rate == pytest.approx(200 / math.sqrt(2), rel=1e-14)


def _actuator_factor(key: str, rotary: bool) -> float:
    from legdsl.ir.model import setting_kind

    return factor(KINDS[setting_kind("force" if key == "value" else key, rotary)][0], 2.0)


def test_scaling_by_l_then_1_over_l_gives_the_numbers_back() -> None:
    text = (CREATURES / "kangaroo.leg").read_text(encoding="utf-8")
    back = scale_source(scale_source(text, 0.5), 2.0)
    number = r"(?<![\w.])\d+\.?\d*(?:[eE][-+]?\d+)?"
    body = back.split("\n", 4)[4]  # past the two headers
    body = re.sub(r"\n  # the integration step.*?\n  }\n", "", body, flags=re.S)
    got = [float(x) for x in re.findall(number, body)]
    want = [float(x) for x in re.findall(number, text)]
    assert got == pytest.approx(want, rel=1e-13)


def test_the_simulation_block_gives_the_run_defaults(tmp_path: Path) -> None:
    path = tmp_path / "slider.leg"
    path.write_text(
        "creature slider {\n  planar\n  body mass free { mass 1 kg  inertia 0.01 kg*m^2 }\n"
        "  simulation { dt 0.2 ms  control_dt 1 ms  record_rate 500 Hz }\n}\n",
        encoding="utf-8",
    )
    (model,) = check_file(path)
    options = run_options(model, duration=1.0)
    assert (options.dt, options.control_dt, options.record_rate) == (0.0002, 0.001, 500.0)
    assert run_options(model, dt=0.001).dt == 0.001  # the command line overrides it
    scaled = run_options(model, 4.0)  # defaults for the creature 4 times as large
    assert (scaled.dt, scaled.record_rate) == pytest.approx((0.0004, 250.0))


def _agree(a: Trajectory, b: Trajectory) -> float:
    """The largest difference of the two runs, each relative to the larger of the two values
    (with a floor of 1e-12 of the column's magnitude, for values that cross zero)."""
    assert len(a) == len(b) > 0
    worst = 0.0
    for name in ARRAYS:
        x, y = getattr(a, name).astype(float), getattr(b, name).astype(float)
        both = np.isfinite(x) & np.isfinite(y)
        assert (np.isnan(x) == np.isnan(y)).all(), name
        if not both.any():
            continue
        x, y = x[both], y[both]
        floor = 1e-12 * max(float(np.abs(x).max()), 1e-300)
        rel = np.abs(x - y) / np.maximum(np.maximum(np.abs(x), np.abs(y)), floor)
        worst = max(worst, float(rel.max()))
    return worst


CASES = [
    ("kangaroo", "hop", 2.0, ["speed=3m/s", "speed=4m/s@0.2s"]),
    ("biped", "run", 0.5, ["speed=0.8m/s", "k_speed=0.05s"]),
]


@pytest.mark.parametrize(("name", "controller", "scale", "settings"), CASES)
def test_the_scaled_file_and_the_scaled_run_agree_sample_by_sample(
    name: str,
    controller: str,
    scale: float,
    settings: list[str],
    generated: Path,
    tmp_path: Path,
) -> None:
    source = CREATURES / f"{name}.leg"
    out = tmp_path / f"{scale_name(name, scale)}.leg"
    assert main(["scale", str(source), "--by", str(scale), "-o", str(out)]) == 0
    sets = [x for s in settings for x in ("--set", s)]
    # the Python backend: 0.3 s run faster there than two scaled creatures take to build in C
    common = ["--controller", controller, "--time", "0.3", "--generated", str(generated),
              "--backend", "python", *sets]  # fmt: skip
    assert main(["run", str(out), *common, "--out", str(tmp_path / "file")]) == 0
    assert (
        main(["run", str(source), *common, "--scale", str(scale), "--out", str(tmp_path / "run")])
        == 0
    )
    a = Trajectory.load(tmp_path / "file")
    b = Trajectory.load(tmp_path / "run")
    assert _agree(a, b) < 1e-9
    assert 0.29 < a.t[-1] <= 0.3
    assert a.total_mass == pytest.approx(b.total_mass, rel=1e-13)


def test_the_apex_metrics_of_a_hop_and_of_its_run_scaled_by_4(
    generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Apex height of the centre of mass (from the trajectory) and the clearance of the lowest
    contact there (from the generated kinematics); the run scaled by 4 has both 4 times."""
    from legdsl.pipeline.measure import measure_run

    hopper = CREATURES / "hopper.leg"
    common = ["--controller", "hop", "--generated", str(generated)]
    assert main(["run", str(hopper), *common, "--time", "1.5", "--out", str(tmp_path / "a")]) == 0
    assert (
        main(
            [
                "run",
                str(hopper),
                *common,
                "--time",
                "3",
                "--scale",
                "4",
                "--out",
                str(tmp_path / "b"),
            ]
        )
        == 0
    )
    capsys.readouterr()
    small, _ = measure_run(tmp_path / "a", generated=generated)
    big, _ = measure_run(tmp_path / "b", generated=generated)
    apex, clearance = small.summary("apex_height"), small.summary("apex_foot_clearance")
    assert apex.n == clearance.n >= 1
    tr = Trajectory.load(tmp_path / "a")
    highest = [
        float(tr.com[(tr.t >= f.t_start) & (tr.t <= f.t_end), 2].max()) for f in small.flights
    ]
    assert apex.value == pytest.approx(float(np.mean(highest)))
    assert 0 < clearance.value < apex.value
    assert big.value("apex_height") == pytest.approx(4 * apex.value, rel=1e-9)
    assert big.value("apex_foot_clearance") == pytest.approx(4 * clearance.value, rel=1e-9)
    assert main(["metrics", str(tmp_path / "a"), "--generated", str(generated)]) == 0
    assert "foot clearance at the apex (m)" in capsys.readouterr().out


def test_a_path_is_scaled_with_its_default_lookahead_written(tmp_path: Path) -> None:
    from legdsl.ir.paths import DEFAULT_LOOKAHEAD
    from legdsl.lang import scaling
    from legdsl.sim.run_loop import RunOptions

    assert scaling.DEFAULT_LOOKAHEAD == DEFAULT_LOOKAHEAD
    defaults = RunOptions()
    assert (
        defaults.dt,
        defaults.control_dt,
        defaults.record_rate,
    ) == (scaling.DEFAULT_DT, scaling.DEFAULT_CONTROL_DT, scaling.DEFAULT_RECORD_RATE)
    text = (
        (CREATURES / "biped.leg")
        .read_text(encoding="utf-8")
        .replace(
            "  path route\n",
            "  path route = circle(center = (0, 5) m, radius = 5 m, turn = left)\n",
        )
    )
    out = tmp_path / "biped_x2.leg"
    out.write_text(scale_source(text, 2.0), encoding="utf-8")
    assert (
        "circle(center = (0, 10) m, radius = 10 m, turn = left, lookahead = 2 m)" in out.read_text()
    )
    (big,) = check_file(out)
    (path,) = big.controller("run").paths
    assert (path.center, path.radius, path.lookahead) == ((0.0, 10.0), 10.0, 2.0)


def test_bad_scale_factors_are_user_errors(
    generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    hopper = str(CREATURES / "hopper.leg")
    out = str(tmp_path / "x.leg")
    gen = ["--generated", str(generated)]
    assert main(["scale", hopper, "--by", "0", "-o", out]) == 2
    assert main(["scale", hopper, "--by", "-2", "-o", out]) == 2
    assert main(["run", hopper, *gen, "--scale", "-1", "--time", "0.01", "--out", out]) == 2
    assert main(["run", hopper, *gen, "--scale", "2", "--animate", "--out", out]) == 2
    err = capsys.readouterr().err
    assert "the scale factor is a positive, finite number" in err
    # past a double as written: told as written ('--by 0.0', '--scale 0', '--by inf' before)
    for by, told in (("1e-400", "small a number: it underflows"), ("1e400", "large a number")):
        for args in (["scale", hopper, "--by", by, "-o", out],
                     ["run", hopper, *gen, "--scale", by, "--time", "0.01", "--out", out]):  # fmt: skip
            with pytest.raises(SystemExit) as refused:  # argparse's
                main(args)
            assert refused.value.code == 2
        said = capsys.readouterr().err
        assert said.count(f"{by!r} is too {told}") == 2 and "positive, finite" in said
    # float() read '1_5' as 15 (meant 1.5?) and Arabic-Indic digits: as a .leg file, refused
    for by in ("1_5", "\u0661"):
        for args in (["scale", hopper, "--by", by, "-o", out],
                     ["run", hopper, *gen, "--scale", by, "--time", "0.01", "--out", out]):  # fmt: skip
            with pytest.raises(SystemExit) as refused:  # argparse's
                main(args)
            assert refused.value.code == 2
        said = capsys.readouterr().err
        assert said.count(f"{by!r} is not a number: write it with the digits 0-9, without '_'") == 2
    assert "--animate with --scale is not supported" in err and "legdsl scale" in err
    assert not Path(out).exists()


def test_a_bad_run_scale_is_refused_before_anything_is_compiled(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """runtime.md: values that make no sense are refused before anything is compiled;
    --scale 0 filled generated/hopper/ (a sympy compile) and only then was refused."""
    hopper = str(CREATURES / "hopper.leg")
    gen = tmp_path / "generated"
    for by in ("0", "-1", "1e100"):
        out = tmp_path / "run"
        args = ["run", hopper, "--controller", "hop", "--scale", by, "--generated", str(gen)]
        assert main([*args, "--out", str(out)]) == 2
        err = capsys.readouterr().err
        assert "compiling" not in err
        assert f"--scale {float(by):g}: " in err
        assert not gen.exists() and not out.exists()
    assert main(["run", hopper, "--scale", "0", "--generated", str(gen)]) == 2
    assert "--scale 0: the scale factor is a positive, finite number" in capsys.readouterr().err


def test_a_factor_whose_numbers_no_double_holds_is_refused_at_the_numbers(
    generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """L = 1e100 makes an inertia 1e500 (L^5): an internal error (OverflowError) before; L =
    1e-300 made the masses 0, written out, then refused in the file written."""
    hopper = str(CREATURES / "hopper.leg")
    out = tmp_path / "x.leg"
    for by, words in (("1e100", "past a double"), ("1e-300", "nearer 0 than a double holds")):
        assert main(["scale", hopper, "--by", by, "-o", str(out)]) == 2
        err = capsys.readouterr().err
        assert f"hopper.leg:13:25: error: scaled by L^5 with L = {by} this number is {words}" in err
        assert "inertia 0.4 kg*m^2" in err and "Traceback" not in err
        assert not out.exists()
    gen = ["--generated", str(generated), "--time", "0.01", "--out", str(out)]
    assert main(["run", hopper, "--scale", "1e100", *gen]) == 2
    assert "too far from 1" in capsys.readouterr().err


def test_a_file_with_a_byte_order_mark_and_its_own_use_scales_into_another_folder(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """It is read as the checker reads it (the mark was 'unexpected character U+FEFF'), and
    its 'use "actions.leg"' points at the same file from the new folder."""
    good = CREATURES.parent / "tests" / "good"
    (tmp_path / "actions.leg").write_text((good / "actions.leg").read_text())
    source = tmp_path / "hopper.leg"
    source.write_bytes(b"\xef\xbb\xbf" + (good / "hopper.leg").read_bytes())
    out = tmp_path / "scaled" / "hopper_x2.leg"
    out.parent.mkdir()
    assert main(["scale", str(source), "--by", "2", "-o", str(out)]) == 0, capsys.readouterr().err
    assert 'use "../actions.leg"' in out.read_text()
    assert [m.name for m in check_file(out)] == ["hopper_x2"]


def test_a_used_file_of_actions_scales_too(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """docs/scaling.md says to scale a 'use'd file of one's own too; a file of actions alone
    was refused ('no creature in this file')."""
    good = CREATURES.parent / "tests" / "good"
    (tmp_path / "actions.leg").write_text(
        (good / "actions.leg").read_text().replace("+ amount", "+ amount + 2 cm")
    )
    (tmp_path / "hopper.leg").write_text((good / "hopper.leg").read_text())
    lib = tmp_path / "actions_x2.leg"
    assert main(["scale", str(tmp_path / "actions.leg"), "--by", "2", "-o", str(lib)]) == 0
    assert "+ amount + 4 cm" in lib.read_text()
    assert "point the scaled creature's 'use' at it" in capsys.readouterr().out
    out = tmp_path / "hopper_x2.leg"
    monkeypatch.chdir(tmp_path)  # the note names the used file relative to here
    assert main(["scale", str(tmp_path / "hopper.leg"), "--by", "2", "-o", str(out)]) == 0
    assert (  # the used file is left as it is, and said so (its 2 cm would not scale)
        "legdsl: note: actions.leg, which it uses, is not scaled and has "
        "numbers with units: scale it too (legdsl scale actions.leg --by 2"
    ) in capsys.readouterr().err
    out.write_text(out.read_text().replace('use "actions.leg"', 'use "actions_x2.leg"'))
    assert [m.name for m in check_file(out)] == ["hopper_x2"]
    (tmp_path / "empty.leg").write_text("# nothing here\n")
    assert main(["scale", str(tmp_path / "empty.leg"), "--by", "2", "-o", str(lib)]) == 2
    assert "no creature in this file" in capsys.readouterr().err


def test_a_scene_scales_with_its_creature(tmp_path: Path) -> None:
    """A scene's times, commands and gait bands were left as written (the scaled biped switched
    gait at 8 s, not 8 sqrt(L) s), and 'scene NAME for CREATURE' kept the old name, so the
    scaled file of two creatures failed its own check."""
    biped = scale_source((CREATURES / "biped.leg").read_text(encoding="utf-8"), 4.0)
    for line in ("set speed = 4 m/s", "at 16 s switch gallop", "at 32 s set speed = 5 m/s",
                 "time 52 s", "gait by speed { gallop to 3.2 m/s; run from 2.8 m/s }"):  # fmt: skip
        assert f"  {line}\n" in biped
    two = """\
creature a { planar
  body b free { mass 1 kg inertia 0.1 kg*m^2 initial z = 1 m }
  contact c on b at (0 m, -0.1 m)
}
creature b { planar
  body b free { mass 1 kg inertia 0.1 kg*m^2 initial z = 1 m }
}
controller idle for a { input speed = 1 m/s  table { state S on speed > 0 m/s: } }
scene s for a { controller idle  set speed = 2 m/s  at 1 s set speed = 3 m/s  time 2 s }
"""
    out = tmp_path / "two_x4.leg"
    out.write_text(scale_source(two, 4.0), encoding="utf-8")
    assert (
        "scene s for a_x4 { controller idle  set speed = 4 m/s  at 2 s set speed = 6 m/s  time 4 s }"
        in out.read_text()
    )
    assert [m.name for m in check_file(out)] == ["a_x4", "b_x4"]


def test_the_output_may_not_be_the_file_or_a_file_it_uses(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """'-o' naming FILE replaced the user's creature with the scaled one (and 'check passes');
    naming the file of actions it uses replaced that."""
    good = CREATURES.parent / "tests" / "good"
    for name in ("hopper.leg", "actions.leg"):
        (tmp_path / name).write_text((good / name).read_text())
    before = {p.name: p.read_text() for p in tmp_path.iterdir()}
    hopper = str(tmp_path / "hopper.leg")
    for out in (hopper, str(tmp_path / "actions.leg"), str(tmp_path)):
        assert main(["scale", hopper, "--by", "2", "-o", out]) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err
    assert f"-o {hopper}: this is {hopper}, an input that writing would destroy" in err
    assert "give another file name, such as hopper_x2.leg" in err
    assert "actions.leg, an input that writing would destroy" in err
    assert "this is a directory; give a file name" in err
    assert {p.name: p.read_text() for p in tmp_path.iterdir()} == before


@pytest.mark.parametrize(
    "block",
    [
        "  simulation { dt 0.2 ms }\n",
        "  simulation {\n    record_rate 100 Hz\n  }\n",
        "  simulation { dt 5 ms  record_rate 50 Hz }\n",
    ],
)
def test_a_partial_simulation_block_is_completed_with_the_scaled_defaults(
    block: str, tmp_path: Path
) -> None:
    """The entries a block leaves out were left out of OUT too, so the scaled file ran with the
    runner's unscaled 2 ms and 200 Hz where --scale L runs with 2 ms sqrt(L) and 200 Hz / sqrt(L)."""
    text = (
        "creature slider {\n  planar\n  body mass free { mass 1 kg  inertia 0.01 kg*m^2 }\n"
        f"{block}}}\n"
    )
    path = tmp_path / "slider.leg"
    path.write_text(text, encoding="utf-8")
    (model,) = check_file(path)
    for by in (2.0, 0.3):
        out = tmp_path / f"x{by}.leg"
        out.write_text(scale_source(text, by), encoding="utf-8")
        (scaled,) = check_file(out)
        asked, written = run_options(model, by), run_options(scaled)
        for key in ("dt", "control_dt", "record_rate"):
            assert getattr(written, key) == pytest.approx(getattr(asked, key), rel=1e-13), key


def test_an_absolute_use_stays_absolute(tmp_path: Path) -> None:
    """It came back relative ('../../..' up to the root and down again), which worked only
    until the scaled file moved."""
    good = CREATURES.parent / "tests" / "good"
    (tmp_path / "actions.leg").write_text((good / "actions.leg").read_text())
    text = (good / "hopper.leg").read_text()
    assert 'use "actions.leg"' in text
    source = tmp_path / "hopper.leg"
    source.write_text(text.replace('use "actions.leg"', f'use "{tmp_path / "actions.leg"}"'))
    out = tmp_path / "scaled" / "hopper_x2.leg"
    out.parent.mkdir()
    assert main(["scale", str(source), "--by", "2", "-o", str(out)]) == 0
    assert f'use "{tmp_path / "actions.leg"}"' in out.read_text()
    assert [m.name for m in check_file(out)] == ["hopper_x2"]
