"""Small things an outside user found in legdsl sweep: '--dask tcp://127.0.0.1:99999' (no
port) waited 10 s to say it could not connect; '--samples 5 --seed 4' without --random or
--lhs were taken and unused, unsaid; a one-run sweep's summary said '1 runs'."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.api.workers import dask_address
from legdsl.cli import main
from legdsl.lang.errors import UsageError

HOPPER = Path(__file__).resolve().parents[2] / "creatures" / "hopper.leg"
pytestmark = pytest.mark.usefixtures("hopper_modules")


@pytest.mark.parametrize("port", ["99999", "0", "65536"])
def test_a_port_no_scheduler_can_have_is_refused_at_once(port: str) -> None:
    pytest.importorskip("distributed")
    with pytest.raises(UsageError, match=f"port {port} is not one from 1 to 65535"):
        dask_address(f"tcp://127.0.0.1:{port}")
    assert dask_address("tcp://127.0.0.1:65535") == "tcp://127.0.0.1:65535"


def test_draw_options_without_draws_are_noted_and_one_run_is_one_run(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["sweep", str(HOPPER), "--controller", "hop", "--grid", "speed=1.0",
                 "--samples", "5", "--seed", "4", "--time", "0.5", "--from", "0", "--jobs", "1",
                 "--out", str(tmp_path / "s"), "--generated", str(tmp_path / "generated")]) == 0  # fmt: skip
    said = capsys.readouterr()
    assert "legdsl: note: --samples and --seed are for --random and --lhs draws" in said.err
    assert said.out.startswith("1 run (0 fell or diverged): ")


def test_a_refusal_comes_without_the_notes_before_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """An outside user's --samples 0 with --grid alone was told '--samples is for --random and
    --lhs draws ...: not used', then refused: the notes are of the sweep that runs, said once
    no refusal comes."""
    assert main(["sweep", str(HOPPER), "--controller", "hop", "--grid", "speed=1:2:2",
                 "--samples", "0", "--out", str(tmp_path / "s")]) == 2  # fmt: skip
    err = capsys.readouterr().err
    assert err.startswith("legdsl: --samples 0: must be more than zero"), err
    assert "note" not in err
