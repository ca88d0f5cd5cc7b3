"""legdsl tune stopped early (nothing written, or one generation), and an --out that is a file."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

import legdsl.api.tune_cli as tune_cli
from legdsl.cli import main
from legdsl.sim.run_loop import Interrupted

ROOT = Path(__file__).resolve().parents[2]

pytestmark = pytest.mark.usefixtures("hopper_modules")


@pytest.mark.parametrize(("stop", "status"), [(KeyboardInterrupt, 130), (Interrupted, 143)])
def test_a_tune_stopped_before_its_start_leaves_no_empty_out(
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
    stop: type[BaseException],
    status: int,
) -> None:
    """Ctrl-C during the start's runs said only "legdsl: interrupted" and left --out made and
    empty: the user could not tell whether anything was kept."""

    def stopped(*args: Any, **kwargs: Any) -> None:
        raise stop("SIGTERM") if stop is Interrupted else stop()

    monkeypatch.setattr(tune_cli, "tune", stopped)
    out = tmp_path / "tuned"
    code = main(["tune", str(ROOT / "creatures" / "hopper.leg"), "--controller", "hop",
                 "--param", "k_speed=0.02:0.2", "--speeds", "1", "--time", "1", "--from", "0.2",
                 "--jobs", "1", "--out", str(out), "--generated", str(tmp_path / "generated")])  # fmt: skip
    assert code == status
    assert f"stopped before the file's own values were measured: nothing written to {out}" in (
        capsys.readouterr().err
    )
    assert not out.exists()


def test_an_out_that_was_there_is_kept(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    def stopped(*args: Any, **kwargs: Any) -> None:
        raise KeyboardInterrupt

    monkeypatch.setattr(tune_cli, "tune", stopped)
    out = tmp_path / "tuned"
    out.mkdir()
    main(["tune", str(ROOT / "creatures" / "hopper.leg"), "--controller", "hop", "--param",
          "k_speed=0.02:0.2", "--speeds", "1", "--time", "1", "--from", "0.2", "--jobs", "1",
          "--out", str(out), "--generated", str(tmp_path / "generated")])  # fmt: skip
    assert out.is_dir()


def test_a_tune_stopped_after_one_generation_says_one_generation(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """Stopped in its second generation it said "the best of 1 generations so far"."""
    row = {"speed": 1.0, "outcome": "ok", "running_speed": 0.9, "simulated": 1.0}
    result = {
        "start": {"values": {"k_speed": 0.08}, "objective": 0.2, "runs": [row]},
        "best": {"values": {"k_speed": 0.1}, "objective": 0.1, "runs": [row]},
        "history": [{"generation": 1, "best": 0.1, "mean": 0.15, "runs": 2}],
        "ended": "interrupted",
    }
    monkeypatch.setattr(tune_cli, "tune", lambda *args, **kwargs: result)
    out = tmp_path / "tuned"
    code = main(["tune", str(ROOT / "creatures" / "hopper.leg"), "--controller", "hop",
                 "--param", "k_speed=0.02:0.2", "--speeds", "1", "--time", "1", "--from", "0.2",
                 "--jobs", "1", "--out", str(out), "--generated", str(tmp_path / "generated")])  # fmt: skip
    assert code == 130
    assert "tune.png, the best of 1 generation so far\n" in capsys.readouterr().out


def test_an_out_that_is_a_file_is_refused_saying_so(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--out naming a file said "File exists (...); check the path and its permissions"."""
    out = tmp_path / "tuned"
    out.write_text("mine\n")
    code = main(["tune", str(ROOT / "creatures" / "hopper.leg"), "--controller", "hop",
                 "--param", "k_speed=0.02:0.2", "--speeds", "1", "--time", "1", "--from", "0.2",
                 "--jobs", "1", "--out", str(out), "--generated", str(tmp_path / "generated")])  # fmt: skip
    assert code == 2
    assert (
        f"--out {out}: this is a file, not a directory; give a directory" in capsys.readouterr().err
    )
    assert out.read_text() == "mine\n"


@pytest.mark.parametrize("where", ["check_model", "load"])
def test_a_tune_stopped_in_its_start_up_says_nothing_was_written(
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
    where: str,
) -> None:
    """Ctrl-C while the file was checked or its controller compiled (0.3 to 1.2 s into the
    command) said only "legdsl: interrupted", where at 1.6 s the documented sentence came."""

    def stopped(*args: Any, **kwargs: Any) -> None:
        raise KeyboardInterrupt

    import legdsl.api

    monkeypatch.setattr(tune_cli if where == "check_model" else legdsl.api, where, stopped)
    out = tmp_path / "tuned"
    code = main(["tune", str(ROOT / "creatures" / "hopper.leg"), "--controller", "hop",
                 "--param", "k_speed=0.02:0.2", "--speeds", "1", "--time", "1", "--from", "0.2",
                 "--jobs", "1", "--out", str(out), "--generated", str(tmp_path / "generated")])  # fmt: skip
    assert code == 130
    assert f"stopped before the file's own values were measured: nothing written to {out}" in (
        capsys.readouterr().err
    )
    assert not out.exists()


def test_a_tune_stopped_as_the_commands_load_says_nothing_was_written(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """Ctrl-C in the command's first second, as the parsers import the commands' modules
    (timeout -s INT 0.3 to 1.2 legdsl tune ...), said only "legdsl: interrupted"."""
    import legdsl.cli

    def stopped() -> None:
        raise KeyboardInterrupt

    monkeypatch.setattr(legdsl.cli, "_parser", stopped)
    out = tmp_path / "tuned"
    code = main(["tune", str(ROOT / "creatures" / "hopper.leg"), "--controller", "hop",
                 "--param", "k_speed=0.02:0.2", "--speeds", "1", f"--out={out}"])  # fmt: skip
    assert code == 130
    err = capsys.readouterr().err
    assert f"stopped before the file's own values were measured: nothing written to {out}" in err
    monkeypatch.setattr(legdsl.cli, "_parser", stopped)
    assert main(["run", str(ROOT / "creatures" / "hopper.leg"), "--out", str(out)]) == 130
    assert capsys.readouterr().err == "legdsl: interrupted\n"  # another command: as it was
