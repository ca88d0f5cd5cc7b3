"""The scuff example of docs/metrics.md ("Scuffs and --min-stance") is what the command gives:
the run it named had changed, and the scuffs it listed were no longer there. The doc's
command is run, and the scuffs, --min-stance and strides the paragraph gives are checked."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from conftest import OUTSIDE, ROOT, outside_session

from legdsl.cli import main


def test_the_docs_scuffed_bound_is_the_runs(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    doc = (ROOT / "docs" / "metrics.md").read_text(encoding="utf-8")
    section = doc[doc.index("### Scuffs and `--min-stance`") : doc.index("When there are not two")]
    paragraph = " ".join(section[section.index("The bound of dachs") :].split())
    command = re.search(r"`legdsl metrics runs/tbt (--from \S+ --to \S+)`", paragraph)
    assert command, paragraph
    window = command.group(1).split()
    generated = outside_session("dachs.leg").generated  # compiled once for every test
    run = str(tmp_path / "tbt")
    argv = ["run", str(OUTSIDE / "dachs.leg"), "--scene", "trot_bound_trot", "--out", run]
    assert main([*argv, "--generated", str(generated)]) == 0
    capsys.readouterr()
    assert main(["metrics", run, *window]) == 0
    captured = capsys.readouterr()
    scuffs = re.search(r"scuffs \(([^)]*)\)", paragraph)
    assert scuffs, paragraph
    for foot, at, lasting in re.findall(r"(\w+) at ([\d.]+) s for ([\d.]+) s", scuffs.group(1)):
        assert f"{foot} at {at} s ({lasting} s)" in captured.err, captured.err
    advised = re.search(r"and `(--min-stance \w+)`", paragraph)
    assert advised and f"{advised.group(1)} leaves them out" in captured.err
    figures = re.findall(r"([\d.]+) ± ([\d.]+) s over (\d+)", paragraph)
    plain, filtered = figures[0:2], figures[2:4]
    assert main(["metrics", run, *window, *advised.group(1).split()]) == 0
    again = capsys.readouterr()
    for (value, spread, n), label, out in (
        (plain[0], "stride duration (s)", captured.out),
        (plain[1], "stance duration (s)", captured.out),
        (filtered[0], "stride duration (s)", again.out),
        (filtered[1], "stance duration (s)", again.out),
    ):
        row = next(line for line in out.splitlines() if line.startswith(label))
        assert row.split()[-3:] == [value, spread, n], (row, value, spread, n)
