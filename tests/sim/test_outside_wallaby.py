"""A wallaby written from the docs alone (tests/good/outside/wallaby.leg): a smaller kangaroo
of other proportions whose controllers extend the shipped kangaroo's. It compiles, hops the
same on both backends, jumps a box 0.18 m tall and deep (0.6 of the kangaroo's) and hops on,
and a contact under a thin paw pad is refused before the run."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT

sys.path.insert(0, str(ROOT / "docs" / "scripts"))
import kangaroo_jump  # noqa: E402

from legdsl.cli import main
from legdsl.sim.c_backend import available

LEG = ROOT / "tests" / "good" / "outside" / "wallaby.leg"
USE = 'use "../../../creatures/kangaroo.leg"'


def copy(tmp_path: Path, name: str, old: str = "", new: str = "") -> Path:
    """wallaby.leg in TMP_PATH, its `use` pointing at the repository's kangaroo."""
    text = LEG.read_text(encoding="utf-8").replace(old, new, 1) if old else LEG.read_text("utf-8")
    path = tmp_path / name
    path.write_text(text.replace(USE, f'use "{ROOT}/creatures/kangaroo.leg"'), encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def gen(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """One generated tree for the module: the wallaby is compiled once."""
    return tmp_path_factory.mktemp("wallaby_generated")


def run(
    tmp_path: Path, gen: Path, backend: str, monkeypatch: pytest.MonkeyPatch, leg: Path = LEG
) -> int:
    monkeypatch.setenv("LEGDSL_BACKEND", backend)
    argv = ["run", str(leg), "--controller", "hop", "--set", "speed=3m/s", "--time", "2",
            "--generated", str(gen), "--out", str(tmp_path / backend)]  # fmt: skip
    return main(argv)


@pytest.mark.skipif(available() is not None, reason=f"needs a C compiler: {available()}")
def test_wallaby_hops_identically_on_both_backends(
    tmp_path: Path, gen: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    assert run(tmp_path, gen, "python", monkeypatch) == 0
    assert run(tmp_path, gen, "c", monkeypatch) == 0
    py = (tmp_path / "python" / "trajectory.npz").read_bytes()
    assert py == (tmp_path / "c" / "trajectory.npz").read_bytes()
    data = np.load(tmp_path / "python" / "trajectory.npz")
    com = data["com"]
    assert com[-1, 0] > 2.0  # it hops forward (2.69 m in 2 s from standing, ramping to 3 m/s)


def test_contact_under_a_thin_pad_is_refused(
    tmp_path: Path, gen: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """The wallaby's 0.6 cm pad with its tail tip 0.8 cm under it: within the old fixed
    1 cm allowance, the pad threw the wallaby up and it 'fell' at 0.05 s."""
    text = LEG.read_text(encoding="utf-8").replace("initial -15 deg", "initial -25 deg", 1)
    text = text.replace(
        'use "../../../creatures/kangaroo.leg"', f'use "{ROOT}/creatures/kangaroo.leg"'
    )
    leg = tmp_path / "drooping.leg"
    leg.write_text(text, encoding="utf-8")
    assert run(tmp_path, gen, "python", monkeypatch, leg) == 2
    err = capsys.readouterr().err
    assert "tail_end" in err and "under the ground" in err and "raise the root's initial z" in err


def test_wallaby_jumps_the_box_and_hops_on(tmp_path: Path, gen: Path) -> None:
    """The box at 6 m at 3 m/s: no point of its shapes meets the box, it lands beyond it and
    hops to the end of a 5 s run (docs/kangaroo.md, "Another kangaroo: a wallaby")."""
    box = "    friction none\n    terrain box(x0 = 6 m, x1 = 6.18 m, height = 0.18 m)\n  }"
    source = copy(tmp_path, "wallaby_box.leg", "    friction none\n  }", box)
    model, dyn, result = kangaroo_jump.jump(source, 3.0, 5.0, gen)
    report = kangaroo_jump.report(model, dyn, result, 3.0)
    assert result.status == "ok", result.message
    assert report["overlap_samples"] == 0 and report["margin_m"] > 0.01
    assert report["landed_t"] is not None and report["landed_t"] < 3.6
    assert report["apex_m"] > 0.5  # a jump: the hops' apex is 0.26 m
