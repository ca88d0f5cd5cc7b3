"""The tuned file of a controller that extends a used file's controller of its own name.

An outside user's heavy quadruped, ``use "quadruped.leg"`` and ``controller trot extends trot
{ param kp = 530 N*m/rad }``, tuned for leg_k and kp: the tuned file declared
``param leg_k = 4584.77 N/m``, ``param kp = 530 N*m/rad``, ``param leg_k = 4050 N/m`` and
``param kp = 336.86 N*m/rad`` in trot, and did not check ('leg_k' is defined twice). The tuned
trot was taken for its own extender (its base's name is its own), and given the old values
of the tuned parameters to keep. An extender is a controller of the file whose base resolves
to the tuned one; the used file's trot is another controller.

The variants are drawn at random (the tuned controller named as the used one or not, its body
empty or declaring some of the parameters, chains of controllers extending it or the used
one), from ``LEGDSL_TUNE_EXTENDS_SEED`` (0) on; a failure names its seed and file."""

from __future__ import annotations

import os
import random
from pathlib import Path

import pytest
from seeded import told_with_seed

from legdsl.api.tuned_file import write_tuned
from legdsl.check.source import check_model

ROOT = Path(__file__).resolve().parents[2]
HOPPER = ROOT / "creatures" / "hopper.leg"
FIRST_SEED = int(os.environ.get("LEGDSL_TUNE_EXTENDS_SEED", "0"))
# hop's parameters a variant declares or tunes, each with its unit and a value to scale
PARAMS = {
    "k_speed": ("s", 0.06),
    "kp": ("N*m/rad", 150.0),
    "stroke": ("cm", 3.0),
    "k_height": ("", 0.3),
    "full": ("m", 0.79),
}
UNIT_SI = {"s": 1.0, "N*m/rad": 1.0, "cm": 0.01, "": 1.0, "m": 1.0}


def _decls(rng: random.Random, names: list[str]) -> list[str]:
    out = []
    for name in names:
        unit, value = PARAMS[name]
        out.append(
            f"param {name} = {value * rng.uniform(0.5, 1.5):.4g}{' ' + unit if unit else ''}"
        )
    return out


def _body(rng: random.Random, decls: list[str]) -> str:
    """A controller's body: empty in one of its forms, its items on lines of their own or on
    the controller's line."""
    if not decls:
        return rng.choice(["{ }", "{}", "{\n}"])
    if rng.random() < 0.3:
        return "{ " + "  ".join(decls) + " }"
    return "{\n" + "".join(f"  {d}\n" for d in decls) + "}"


def variant(rng: random.Random) -> tuple[str, str]:
    """The variant's text (after its creature) and the tuned controller's name."""
    tuned = rng.choice(["hop", "mine"])
    names = list(PARAMS)
    lines = [f"controller {tuned} extends hop "
             + _body(rng, _decls(rng, rng.sample(names, rng.randint(0, 2))))]  # fmt: skip
    parents = [tuned]
    for k in range(rng.randint(0, 3)):  # extenders, chains of them, and the used hop's
        parent = rng.choice([*parents, "hop"])
        own = _decls(rng, rng.sample(names, rng.randint(0, 2)))
        lines.append(f"controller c{k} extends {parent} {_body(rng, own)}")
        parents.append(f"c{k}")
    if rng.random() < 0.5:
        rng.shuffle(lines)  # a base may come after the controllers extending it
    return "\n".join(lines) + "\n", tuned


def params(path: Path, name: str) -> dict[str, float]:
    return {p.name: p.value for p in check_model(path).controller(name).params}


@pytest.mark.parametrize("seed", range(FIRST_SEED, FIRST_SEED + 24))
def test_a_tuned_file_keeps_one_declaration_each_and_the_others_values(
    tmp_path: Path, seed: int
) -> None:
    rng = random.Random(seed)
    (tmp_path / "base.leg").write_text(HOPPER.read_text())
    head = HOPPER.read_text().partition("controller hop {")[0]
    creature = head[head.index("creature hopper") :].replace("creature hopper", "creature heavy")
    text, tuned = variant(rng)
    source = tmp_path / "heavy.leg"
    source.write_text(f'use "base.leg"\n{creature}{text}')
    chosen = rng.sample(list(PARAMS), rng.randint(1, 3))
    values = {}
    for name in chosen:
        unit, value = PARAMS[name]
        values[name] = round(value * rng.uniform(0.5, 1.5), 3) * UNIT_SI[unit]
    rerun = f"LEGDSL_TUNE_EXTENDS_SEED={seed}"
    with told_with_seed(f"tuning {chosen} of {tuned}, seed {seed}", rerun, lambda: text):
        model = check_model(source)
        out = write_tuned(source, model.controller(tuned), values, tmp_path / "out" / "heavy.leg",
                          model.controllers)  # fmt: skip
        tuned_model = check_model(out)  # it checks: no parameter declared twice
        got = {p.name: p.value for p in tuned_model.controller(tuned).params}
        assert {n: got[n] for n in values} == pytest.approx(values)
        for c in model.controllers:
            if c.name != tuned:  # every other controller runs as before, the used file's too
                before = {p.name: p.value for p in c.params}
                after = {p.name: p.value for p in tuned_model.controller(c.name).params}
                assert after == pytest.approx(before), c.name
        assert params(tmp_path / "base.leg", "hop") == params(HOPPER, "hop")


def test_the_outside_heavy_trot_tuned_for_leg_k_and_kp(tmp_path: Path) -> None:
    """The outside user's file itself: the shipped quadruped used, trot extending trot."""
    (tmp_path / "quadruped.leg").write_text((ROOT / "creatures" / "quadruped.leg").read_text())
    head = (ROOT / "creatures" / "quadruped.leg").read_text()
    creature = head[head.index("creature quadruped") : head.index("\n}\n") + 3]
    source = tmp_path / "heavy2.leg"
    source.write_text('use "quadruped.leg"\n' + creature.replace("quadruped {", "heavy2 {", 1)
                      + "controller trot extends trot {\n  param kp = 530 N*m/rad\n}\n"
                      "controller pace extends pace { }\n")  # fmt: skip
    model = check_model(source)
    out = write_tuned(source, model.controller("trot"), {"leg_k": 4584.5, "kp": 336.5},
                      tmp_path / "tune_h2" / "heavy2.leg", model.controllers)  # fmt: skip
    trot = out.read_text().partition("controller trot extends trot {")[2].partition("}")[0]
    assert [line.strip() for line in trot.strip().splitlines()] == [
        "param leg_k = 4584.5 N/m",
        "param kp = 336.5 N*m/rad",
    ]
    assert params(out, "trot")["kp"] == 336.5
    assert params(out, "pace") == params(source, "pace")


def test_an_empty_body_closes_under_its_controller(tmp_path: Path) -> None:
    """'controller trot extends trot { }' tuned: its brace closed indented, under the
    parameter declared in it."""
    (tmp_path / "base.leg").write_text(HOPPER.read_text())
    head = HOPPER.read_text().partition("controller hop {")[0]
    creature = head[head.index("creature hopper") :].replace("creature hopper", "creature heavy")
    source = tmp_path / "heavy.leg"
    source.write_text(f'use "base.leg"\n{creature}controller hop extends hop {{ }}\n')
    model = check_model(source)
    out = write_tuned(source, model.controller("hop"), {"kp": 160.0},
                      tmp_path / "out" / "heavy.leg", model.controllers)  # fmt: skip
    assert out.read_text().endswith("controller hop extends hop {\n  param kp = 160 N*m/rad\n}\n")
