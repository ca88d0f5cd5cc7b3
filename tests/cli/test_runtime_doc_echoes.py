"""An outside user's literal audit of docs/runtime.md: its `--set bund.k_speed=0.05s` example
echoed `bund.k_speed=0.05s` where legdsl echoes `    --set bund.k_speed=0.05s`, and it said
"a mistake argparse finds is one line" while its own example prints the message, the echoed
option and a caret. The doc's blocks are compared with what the commands print."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import CREATURES

from legdsl.cli import main

DOC = (Path(__file__).resolve().parents[2] / "docs" / "runtime.md").read_text().splitlines()


def _block(first: str) -> list[str]:
    """The doc's printed lines from the one starting ``first``, as printed (its indent off)."""
    (i,) = [k for k, line in enumerate(DOC) if line.lstrip().startswith(first)]
    indent = len(DOC[i]) - len(DOC[i].lstrip())
    lines = [DOC[i]]
    for line in DOC[i + 1 :]:
        if not line.startswith(" " * (indent + 1)):
            break
        lines.append(line)
    return [line[indent:] for line in lines]


@pytest.mark.parametrize(
    ("first", "argv"),
    [
        (
            "legdsl: --set bund.k_speed=0.05s",
            [
                "run",
                str(CREATURES / "quadruped.leg"),
                "--controller",
                "trot",
                "--switch",
                "1s=bound",
                "--set",
                "bund.k_speed=0.05s",
                "--time",
                "0.1",
            ],
        ),  # fmt: skip
        ("legdsl: --slow-motion 2s", ["animate", "RUN", "--video", "x.mp4", "--slow-motion", "2s"]),
    ],
)
def test_the_docs_echo_and_caret_are_the_commands(
    first: str,
    argv: list[str],
    generated: Path,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:
    monkeypatch.chdir(tmp_path)
    argv = [str(generated) if a == "GEN" else a for a in argv]
    doc = _block(first)
    assert len(doc) == 3  # the message, the option echoed, the caret
    try:
        status = main(argv)
    except SystemExit as stop:  # argparse's own mistakes
        status = int(stop.code or 0)
    assert status == 2
    said = capsys.readouterr().err.splitlines()
    said = said[[k for k, line in enumerate(said) if line.startswith(first)][0] :]
    assert said[1:] == doc[1:]
    head = doc[0].removesuffix("...").removesuffix(": ...")
    assert said[0].startswith(head.split("(controllers")[0])


def test_the_doc_does_not_call_an_echoed_mistake_one_line() -> None:
    text = " ".join(" ".join(DOC).split())
    assert "A mistake argparse finds is one line" not in text
    assert "or an option without its value is one line" in text
