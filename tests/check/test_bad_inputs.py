"""The bad-input corpus: every file in tests/bad/ is rejected with exactly its diagnostics.

``tests/bad/NAME.leg`` holds one small mistake (the file is named for it) and
``tests/bad/NAME.expected`` the lines of ``legdsl check NAME.leg``'s stderr
that start with the file name, in order: ``NAME.leg:LINE:COL: error: MESSAGE``.
Each must come with the offending source line and a caret under its column,
the command must exit with status 2 and never show a traceback.

To add a case, write the .leg file, run ``legdsl check NAME.leg > /dev/null``
inside tests/bad/, check the output by eye, and save its header lines as
NAME.expected.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

import legdsl
from legdsl.cli import main

BAD = Path(__file__).parents[1] / "bad"
CASES = sorted(p.stem for p in BAD.glob("*.leg"))

# Run through a real `python -m legdsl` too: syntax, units, tree, body, controller,
# several at once, tabs.
SUBPROCESS_CASES = [
    "syntax_unknown_unit",
    "syntax_missing_close_brace",
    "unit_linear_spring_on_revolute",
    "tree_cycle",
    "body_inertia_triangle_inequality",
    "ctl_unknown_start_state",
    "several_errors_sorted",
    "tabs_caret_column",
]

SHOWN = 120  # the most of a long source line an error shows (legdsl.lang.errors.SHOWN)
HEAD = re.compile(r"(?P<file>[^:]+):(?P<line>\d+):(?P<col>\d+): error: (?P<message>.+)")


def check_stderr(name: str, stderr: str) -> None:
    """The exact header lines, each followed by its source line and a caret at its column."""
    assert "Traceback" not in stderr
    assert "internal error" not in stderr
    expected = (BAD / f"{name}.expected").read_text(encoding="utf-8").splitlines()
    lines = stderr.splitlines()
    heads = [i for i, line in enumerate(lines) if line.startswith(f"{name}.leg:")]
    assert [lines[i] for i in heads] == expected
    assert len(lines) == 3 * len(heads), "every diagnostic is three lines: head, source, caret"
    source = (BAD / f"{name}.leg").read_text(encoding="utf-8").split("\n")
    for i in heads:
        m = HEAD.fullmatch(lines[i])
        assert m is not None, lines[i]
        row, col = int(m["line"]), int(m["col"])
        line = source[row - 1].expandtabs(1)
        line = "".join("\ufffd" if ch < " " or "\x7f" <= ch < "\xa0" else ch for ch in line)
        caret = re.fullmatch(r"    (?P<pad> *)\^~*", lines[i + 2])
        assert caret is not None, lines[i + 2]
        if len(line) <= SHOWN:
            assert lines[i + 1] == "    " + line
            assert len(caret["pad"]) == col - 1, "the caret is under the reported column"
        else:  # 120 characters of it around the caret, cut with "..."
            shown = lines[i + 1][4:]
            assert shown.removeprefix("...").removesuffix("...") in line
            assert shown[len(caret["pad"])] == line[col - 1], "the caret is under its character"


def test_corpus_is_large_and_paired() -> None:
    assert len(CASES) >= 45
    assert sorted(p.stem for p in BAD.glob("*.expected")) == CASES
    for name in CASES:
        expected = (BAD / f"{name}.expected").read_text(encoding="utf-8").splitlines()
        assert expected, f"{name}.expected is empty"
        for line in expected:
            m = HEAD.fullmatch(line)
            assert m is not None and m["file"] == f"{name}.leg", line


def test_diagnostics_are_sorted_by_position() -> None:
    for name in CASES:
        expected = (BAD / f"{name}.expected").read_text(encoding="utf-8").splitlines()
        positions = [(int(m["line"]), int(m["col"])) for m in map(HEAD.fullmatch, expected) if m]
        assert positions == sorted(positions), name
    several = (BAD / "several_errors_sorted.expected").read_text(encoding="utf-8")
    assert len(several.splitlines()) >= 5


@pytest.mark.parametrize("name", CASES)
def test_bad_input(
    name: str, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.chdir(BAD)
    assert main(["check", f"{name}.leg"]) == 2
    out = capsys.readouterr()
    assert out.out == ""
    check_stderr(name, out.err)


def test_bad_inputs_through_python_m_legdsl() -> None:
    # One process for all of them (starting Python is the slow part); each file's
    # diagnostics are checked on their own.
    env = dict(os.environ)
    # Where this legdsl was imported from (an installed package or the source tree).
    env["PYTHONPATH"] = os.pathsep.join(
        [str(Path(legdsl.__file__).parents[1]), env.get("PYTHONPATH", "")]
    )
    done = subprocess.run(
        [sys.executable, "-m", "legdsl", "check", *(f"{n}.leg" for n in SUBPROCESS_CASES)],
        cwd=BAD,
        env=env,
        capture_output=True,
        text=True,
        check=False,
    )
    assert done.returncode == 2, done.stderr
    assert done.stdout == ""
    lines = done.stderr.splitlines()
    for name in SUBPROCESS_CASES:
        own = [
            line
            for i, line in enumerate(lines)
            if lines[i - i % 3].startswith(f"{name}.leg:")  # a head and its two lines
        ]
        check_stderr(name, "\n".join(own) + "\n")
    assert sum(len(lines_of(n)) for n in SUBPROCESS_CASES) * 3 == len(lines)


def lines_of(name: str) -> list[str]:
    return (BAD / f"{name}.expected").read_text(encoding="utf-8").splitlines()
