"""``run_copies`` misused from a notebook: a name both in ``set=`` and ``vary=`` (vary's
values used to win unseen), True/False or complex values (read as 1/0, or cut to their real
part), and the batch's repr (it said only ``<legdsl.api.Copies object at 0x...>``)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT

import legdsl
from legdsl.lang.errors import UsageError

POGO = ROOT / "tests" / "good" / "outside" / "insect_pogo.leg"


@pytest.fixture(scope="module")
def pogo(generated: Path) -> legdsl.api.Creature:
    return legdsl.load(POGO, generated=generated)


def test_a_name_in_both_set_and_vary_is_refused(pogo) -> None:
    with pytest.raises(UsageError, match=r"speed is in both set= and vary="):
        pogo.run_copies(2, "hop", set={"speed": "0.1 m/s"}, vary={"speed": ([0.2, 0.3], "m/s")},
                        time=0.02)  # fmt: skip


def test_a_parameter_set_as_controller_dot_name_and_varied_is_refused(pogo) -> None:
    """hop.kp is hop's kp: accepted, the copies ran vary's values and recorded set='s."""
    with pytest.raises(UsageError, match=r"kp is in both set= \(as hop.kp\) and vary="):
        pogo.run_copies(2, "hop", set={"hop.kp": "0.003 N*m/rad"},
                        vary={"kp": ([0.002, 0.004], "N*m/rad")}, time=0.02)  # fmt: skip


def test_a_change_during_the_run_goes_with_vary(pogo) -> None:
    copies = pogo.run_copies(2, "hop", set={"speed@10ms": "0.1 m/s"},
                             vary={"speed": ([0.2, 0.3], "m/s")}, time=0.02)  # fmt: skip
    assert copies[1].info["inputs"]["speed"] == pytest.approx(0.3)


@pytest.mark.parametrize(("values", "what"), [([True, False], "True/False"),
                                              (np.array([1j, 2]), "complex")])  # fmt: skip
def test_booleans_and_complex_values_are_refused(pogo, values, what) -> None:
    with pytest.raises(UsageError, match=what):
        pogo.run_copies(2, "hop", vary={"speed": (values, "m/s")}, time=0.02)


def test_copies_say_what_they_are(pogo) -> None:
    copies = pogo.run_copies(2, "hop", vary={"speed": ([0.2, 0.3], "m/s")}, time=0.02)
    assert repr(copies) == "<legdsl copies of 'insect_pogo': 2 (ok 2)>"


def test_copies_without_a_c_compiler_are_told_what_a_python_caller_can_do(
    pogo, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The batch runs in C only: without a compiler it was refused as '--backend c: ...; or
    use --backend python', options the API has not."""
    monkeypatch.setenv("LEGDSL_CC", "/nonexistent")
    with pytest.raises(UsageError) as refused:
        pogo.run_copies(2, "hop", vary={"speed": ([0.2, 0.3], "m/s")}, time=0.02)
    said = str(refused.value)
    assert said.startswith("run_copies() runs in C: LEGDSL_CC=/nonexistent: no such program")
    assert said.endswith("or run them with run_many()") and "--backend" not in said


def test_a_copy_with_its_own_start_records_it(generated: Path, tmp_path: Path) -> None:
    """A copy's q0/v0 was in no run.json: it read as a run from the file's initial state, and
    a changed file's 'run it again (legdsl run ...)' advice would make another run."""
    leg = tmp_path / "insect_pogo.leg"
    leg.write_text(POGO.read_text())
    pogo = legdsl.load(leg, generated=generated)
    q0 = np.array([[0.0, 0.08, 0.1, 0.0, 0.0]] * 2)
    v0 = np.zeros((2, 5))
    v0[:, 0] = [0.2, 0.3]
    copies = pogo.run_copies(2, "hop", q0=q0, v0=v0, time=0.02)
    names = pogo.model.q_names
    assert copies[1].info["start"]["q"] == dict(zip(names, q0[1].tolist(), strict=True))
    assert copies[1].info["start"]["v"] == dict(zip(pogo.model.v_names, v0[1], strict=True))
    assert "start" not in pogo.run_copies(2, "hop", time=0.02)[0].info  # the file's start
    saved = copies[1].save(tmp_path / "copy")
    assert json.loads((saved / "run.json").read_text())["start"]["v"]["x"] == 0.3
    assert legdsl.open_run(saved, generated=generated).info["start"]["q"]["z"] == 0.08
    leg.write_text(leg.read_text().replace("mass 3 g", "mass 4 g", 1))
    with pytest.raises(UsageError, match=r"run it again \(with run_copies\(\), from the start"):
        legdsl.open_run(saved, generated=generated)
