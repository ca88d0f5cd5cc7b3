"""A switch the run ends before (given for after ``--time``, or still waiting for a liftoff)
is said in one line, on both backends; a run whose switches were all made says nothing."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import CREATURES, GENERATED

from legdsl.cli import main


@pytest.mark.parametrize("backend", ["python", "c"])
def test_a_switch_after_the_end_is_said(
    backend: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    if backend == "c":
        from legdsl.sim.c_library import available

        if available() is not None:
            pytest.skip(f"needs a C compiler: {available()}")
    argv = ["run", str(CREATURES / "hopper.leg"), "--controller", "hop", "--time", "0.2",
            "--generated", str(GENERATED), "--out", str(tmp_path / "run"), "--backend", backend,
            "--switch", "5s=hop", "--switch", "0.19s=hop"]  # fmt: skip
    assert main(argv) == 0
    err = capsys.readouterr().err
    assert (
        "legdsl: the run ended at 0.2 s before the switches to hop at 0.19 s, hop at 5 s took "
        "over (a switch waits up to 1 s for a liftoff); give a longer --time to see it"
    ) in err, err
    argv[argv.index("--time") + 1] = "1.2"  # the handover comes by 1.05 s at the latest
    assert main([*argv[:-4], "--switch", "0.05s=hop"]) == 0
    assert "before the switch" not in capsys.readouterr().err
