"""A wallaby written from the docs alone (tests/good/outside/wallaby.leg): a smaller kangaroo
of other proportions whose controllers extend the shipped kangaroo's. It compiles, hops the
same on both backends, and a contact under a thin paw pad is refused before the run."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT

from legdsl.cli import main
from legdsl.sim.c_backend import available

LEG = ROOT / "tests" / "good" / "outside" / "wallaby.leg"


def run(tmp_path: Path, backend: str, monkeypatch: pytest.MonkeyPatch, leg: Path = LEG) -> int:
    monkeypatch.setenv("LEGDSL_BACKEND", backend)
    argv = ["run", str(leg), "--controller", "hop", "--set", "speed=3m/s", "--time", "2",
            "--generated", str(tmp_path / "gen"), "--out", str(tmp_path / backend)]  # fmt: skip
    return main(argv)


@pytest.mark.skipif(available() is not None, reason=f"needs a C compiler: {available()}")
def test_wallaby_hops_identically_on_both_backends(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    assert run(tmp_path, "python", monkeypatch) == 0
    assert run(tmp_path, "c", monkeypatch) == 0
    py = (tmp_path / "python" / "trajectory.npz").read_bytes()
    assert py == (tmp_path / "c" / "trajectory.npz").read_bytes()
    data = np.load(tmp_path / "python" / "trajectory.npz")
    com = data["com"]
    assert com[-1, 0] > 2.0  # it hops forward (2.69 m in 2 s from standing, ramping to 3 m/s)


def test_contact_under_a_thin_pad_is_refused(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """The wallaby's 0.6 cm pad with its tail tip 0.8 cm under it: within the old fixed
    1 cm allowance, the pad threw the wallaby up and it 'fell' at 0.05 s."""
    text = LEG.read_text(encoding="utf-8").replace("initial -15 deg", "initial -25 deg", 1)
    text = text.replace(
        'use "../../../creatures/kangaroo.leg"', f'use "{ROOT}/creatures/kangaroo.leg"'
    )
    leg = tmp_path / "drooping.leg"
    leg.write_text(text, encoding="utf-8")
    assert run(tmp_path, "python", monkeypatch, leg) == 2
    err = capsys.readouterr().err
    assert "tail_end" in err and "under the ground" in err and "raise the root's initial z" in err
