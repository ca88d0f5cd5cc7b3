"""legdsl tune replaces OUT/NAME.leg only where a run of the same tune wrote it.

An outside user copied hopper.leg into a folder, edited it ('# my edits'), and from that folder
ran `legdsl tune ../hopper.leg ... --out .`: it exited 0 and replaced their edited hopper.leg
with the tuned one, unsaid (only the input file itself was refused). The journal records the
tuned file each run writes; any other file of that name is refused, before any run."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from legdsl.api.tune_journal import JOURNAL
from legdsl.cli import main

ROOT = Path(__file__).resolve().parents[2]
HOPPER = ROOT / "creatures" / "hopper.leg"

pytestmark = pytest.mark.usefixtures("hopper_modules")


def tune(tmp_path: Path, out: Path, generated: str = "generated") -> int:
    return main(["tune", str(tmp_path / "hopper.leg"), "--controller", "hop", "--param",
                 "kp=100:200", "--speeds", "1", "--time", "1", "--from", "0.2", "--generations",
                 "1", "--popsize", "2", "--jobs", "1", "--out", str(out),
                 "--generated", str(tmp_path / generated)])  # fmt: skip


def test_a_users_own_file_of_the_tuned_files_name_is_not_replaced(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "hopper.leg").write_text(HOPPER.read_text())
    out = tmp_path / "tself2"
    out.mkdir()
    mine = out / "hopper.leg"
    mine.write_text(HOPPER.read_text() + "# my edits\n")
    assert tune(tmp_path, out, "none") == 2
    assert capsys.readouterr().err == (
        f"legdsl: --out {out}: {mine} is not a file this tune wrote, and the tuned hopper.leg "
        f"would replace it; choose another --out or remove {mine}\n"
    )
    assert mine.read_text().endswith("# my edits\n")
    assert sorted(p.name for p in out.iterdir()) == ["hopper.leg"]  # no journal, no lock left
    assert not (tmp_path / "none").exists()  # refused before anything was compiled or run


def test_the_same_tune_again_replaces_its_own_file_and_no_edits_of_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "hopper.leg").write_text(HOPPER.read_text())
    out = tmp_path / "tuned"
    assert tune(tmp_path, out) == 0
    tuned = (out / "hopper.leg").read_bytes()
    assert tune(tmp_path, out) == 0  # its own file: the same command again comes to the same
    assert (out / "hopper.leg").read_bytes() == tuned
    (out / "hopper.leg").write_bytes(tuned + b"# my edits\n")
    capsys.readouterr()
    assert tune(tmp_path, out) == 2
    err = capsys.readouterr().err
    assert f"{out / 'hopper.leg'} has changed since this tune wrote it, and the tuned " in err
    assert (out / "hopper.leg").read_bytes().endswith(b"# my edits\n")


def test_an_earlier_legdsls_journal_of_the_same_tune_is_trusted(tmp_path: Path) -> None:
    """A journal written before it recorded the tuned file: the file is taken as the tune's,
    so that a finished tune still goes further with the same command."""
    (tmp_path / "hopper.leg").write_text(HOPPER.read_text())
    out = tmp_path / "tuned"
    assert tune(tmp_path, out) == 0
    journal = json.loads((out / JOURNAL).read_text())
    assert set(journal.pop("wrote")) == {"hopper.leg"}
    (out / JOURNAL).write_text(json.dumps(journal))
    (out / "hopper.leg").write_text("# whatever an earlier run wrote\n")
    assert tune(tmp_path, out) == 0
    assert "param kp" in (out / "hopper.leg").read_text()
    assert "hopper.leg" in json.loads((out / JOURNAL).read_text())["wrote"]
