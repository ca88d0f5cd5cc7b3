"""Property: any mangled version of a shipped file is accepted or rejected with positions.

The shipped creatures (and tests/good/hopper.leg, for controllers) are mutated
by deleting, duplicating and swapping lines, deleting and inserting
characters and tokens, and replacing numbers, units and names. Checking a
mutant must either succeed or raise a ``LegError`` whose every diagnostic
points inside the file; any other exception is a bug in the front end.

The examples are derandomized so that CI runs the same ones every time.
"""

from __future__ import annotations

import io
import random
import re
import shutil
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from legdsl.check.source import check_file
from legdsl.cli import main
from legdsl.lang.errors import LegError

ROOT = Path(__file__).resolve().parents[2]
SEEDS = [*sorted((ROOT / "creatures").glob("*.leg")), ROOT / "tests" / "good" / "hopper.leg"]
TEXTS = [p.read_text(encoding="utf-8") for p in SEEDS]

TOKENS = [
    "{", "}", "(", ")", ",", "=", "==", ";", ":", ".", "-", "*", "/", "^", "#", '"', "to", "at",
    "on", "via", "tip", "free", "fixed", "body", "leg", "contact", "actuator", "creature",
    "controller", "state", "table", "swap", "record", "let", "action", "use", "planar",
    "spatial", "revolute", "prismatic", "gimbal", "ball", "0", "1e999", "5 kgs", "2 m/sec",
    "kg*m^2", "deg", "\t", "\n", "\r", "\x0c", "\u2028", "é", "²", "1.", ".5", "e5", "x = 0 m",
    "(0 m, 0 m, 0 m)", "((1, 0, 0), (0, 1, 0), (0, 0, 1)) kg*m^2",
]  # fmt: skip
NUMBERS = ["0", "-0", "-5", "3", "0.0", "1e-300", "1e308", "1e999", "123456789012345678901234"]
UNITS = ["", "kg", "g", "m", "cm", "s", "N", "N/m", "N*m/rad", "deg", "rad", "kg*m^2", "m/s^2"]
NUMBER = re.compile(r"(?<![\w.^])\d+\.?\d*(?:[eE][-+]?\d+)?")  # not in m^2 or hip_2
UNIT_AFTER_NUMBER = re.compile(r"(?<=\d )[A-Za-z][A-Za-z*/^0-9]*")
WORD = re.compile(r"[A-Za-z_]\w*")


# Values are where the checker does arithmetic, so they are changed more often.
OPERATIONS = ["delete", "duplicate", "swap", "cut", "char", "token", "token", "unit", "name",
              "number", "number", "numbers in a line", "numbers in a line"]  # fmt: skip


def mutate(text: str, rnd: random.Random) -> str:
    """One to four random edits of ``text``."""
    lines = text.split("\n")
    for _ in range(rnd.randint(1, 4)):
        op = rnd.choice(OPERATIONS)
        i = rnd.randrange(len(lines))
        if op == "numbers in a line":
            numbered = [k for k, line in enumerate(lines) if NUMBER.search(line)] or [i]
            k = rnd.choice(numbered)
            lines[k] = NUMBER.sub(rnd.choice(NUMBERS), lines[k])
        elif op == "delete" and len(lines) > 1:
            del lines[i]
        elif op == "duplicate":
            lines.insert(i, lines[i])
        elif op == "swap":
            j = rnd.randrange(len(lines))
            lines[i], lines[j] = lines[j], lines[i]
        else:
            text = "\n".join(lines)
            at = rnd.randint(0, len(text))
            if op == "cut":
                text = text[:at] + text[at + rnd.randint(1, 8) :]
            elif op == "char":
                # printable ASCII half the time, else any code point (surrogates become '?')
                code = rnd.randrange(32, 127) if rnd.random() < 0.5 else rnd.randrange(0x110000)
                text = text[:at] + chr(code) + text[at:]
            elif op == "token":
                text = text[:at] + rnd.choice(TOKENS) + text[at:]
            else:
                pattern = {"number": NUMBER, "unit": UNIT_AFTER_NUMBER, "name": WORD}[op]
                spots = list(pattern.finditer(text))
                if spots:
                    m = rnd.choice(spots)
                    choices = {"number": NUMBERS, "unit": UNITS}.get(op) or [
                        s.group() for s in spots
                    ]
                    text = text[: m.start()] + rnd.choice(choices) + text[m.end() :]
            lines = text.split("\n")
    return "\n".join(lines).encode("utf-8", errors="replace").decode("utf-8")


# The edits are made with a Random that hypothesis seeds (so that every kind of edit and
# value is drawn evenly; with derandomize=True the same ones in every run).
mutants = st.builds(mutate, st.sampled_from(TEXTS), st.randoms(use_true_random=True))


@pytest.fixture(scope="module")
def workdir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A directory for mutants, beside a copy of the actions file the hopper uses."""
    d = tmp_path_factory.mktemp("mutants")
    shutil.copy(ROOT / "tests" / "good" / "actions.leg", d / "actions.leg")
    return d


def assert_inside(error: LegError) -> None:
    assert error.diagnostics
    for d in error.diagnostics:
        text = error.sources.get(d.span.file)
        assert text is not None, d
        lines = text.split("\n")
        assert 1 <= d.span.line <= len(lines), d
        assert 1 <= d.span.col <= len(lines[d.span.line - 1]) + 1, d
        assert (d.span.end_line, d.span.end_col) >= (d.span.line, d.span.col), d
    assert "Traceback" not in error.render()


@settings(
    max_examples=40,  # the fuzz suite (tests/fuzz) mutates .leg text at random seeds too
    derandomize=True,
    database=None,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)
@given(text=mutants)
def test_mutant_is_accepted_or_rejected_with_positions(workdir: Path, text: str) -> None:
    path = workdir / "mutant.leg"
    path.write_bytes(text.encode("utf-8"))
    try:
        check_file(path)
    except LegError as e:
        assert_inside(e)


@settings(
    max_examples=12,
    derandomize=True,
    database=None,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)
@given(text=mutants)
def test_cli_on_a_mutant_exits_0_or_2(workdir: Path, text: str) -> None:
    path = workdir / "cli_mutant.leg"
    path.write_bytes(text.encode("utf-8"))
    err = io.StringIO()
    with redirect_stderr(err), redirect_stdout(io.StringIO()):
        status = main(["check", str(path)])
    assert status in (0, 2)
    assert "Traceback" not in err.getvalue() and "internal error" not in err.getvalue()
    assert (status == 2) == bool(err.getvalue())
