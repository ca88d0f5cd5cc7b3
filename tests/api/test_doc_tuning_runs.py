"""docs/api.md's "Tuning from detuned gains" and "Tuning a new creature": the runs the two
sections quote before their tunes (the heavy hopper on the hopper's own gains, the detuned
kangaroo) come out as written, each file made as the section makes it. The tunes themselves
(20 s to a minute each) are not rerun here: re-measure them with the sections' commands."""

from __future__ import annotations

import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

from doc_tables import printed_as
from runtime_helpers import needs_c_compiler

import legdsl

pytestmark = needs_c_compiler

ROOT = Path(__file__).resolve().parents[2]
API = (ROOT / "docs" / "api.md").read_text(encoding="utf-8")


def _section(title: str) -> str:
    """The text of the '### TITLE' section of docs/api.md, its lines joined by single spaces."""
    start = API.index(f"### {title}\n")
    end = API.index("\n### ", start + 1)
    return " ".join(API[start:end].split())


def _wrong(doc: str, value: float, what: str) -> list[str]:
    """``what`` if ``value`` printed as the doc prints ``doc`` is not ``doc``."""
    doc = doc.replace("\u2212", "-")
    ran = printed_as(doc, value)
    return [] if float(ran) == float(doc) else [f"{what}: the doc says {doc}, the run gives {ran}"]


def _fell_at(run: legdsl.Run) -> float:
    assert run.status == "fell", f"the run did not fall ({run.status})"
    return float(run.info["ended_at"])


def test_the_heavy_hopper_on_the_hoppers_gains(tmp_path: Path) -> None:
    text = _section("Tuning a new creature")
    heavy_body = re.search(r"twice as heavy \(`([^`]+)`; nothing else changed\)", API)
    figures = re.search(
        r"falls at 1 and 1\.5 m/s with the hopper's own gains \(at ([\d.]+) and ([\d.]+) s\) "
        r"and at 0\.5 m/s stumbles at ([\d.]+) ± ([\d.]+) m/s over the search's 3 to 10 s "
        r"\(([-+\u2212]?[\d.]+)%\), falling at ([\d.]+) s",
        text,
    )
    assert heavy_body and figures, "docs/api.md, Tuning a new creature: the sentences moved"
    shipped = (ROOT / "creatures" / "hopper.leg").read_text(encoding="utf-8")
    body = "mass 10 kg  inertia 0.4 kg*m^2"
    assert shipped.count(body) == 1
    (tmp_path / "heavy").mkdir()
    heavy = tmp_path / "heavy" / "hopper.leg"
    heavy.write_text(shipped.replace(body, heavy_body[1]), encoding="utf-8")
    creature = legdsl.load(heavy, generated=tmp_path / "generated")

    def run(speed: str) -> legdsl.Run:
        return creature.run(controller="hop", set={"speed": f"{speed} m/s"}, time=20)

    at_1, at_1_5, speed, spread, error, at_0_5 = figures.groups()
    slow = run("0.5")
    wrong = _wrong(at_1, _fell_at(run("1")), "the fall at 1 m/s (s)")
    wrong += _wrong(at_1_5, _fell_at(run("1.5")), "the fall at 1.5 m/s (s)")
    wrong += _wrong(at_0_5, _fell_at(slow), "the fall at 0.5 m/s (s)")
    ran = slow.metrics(start=3, end=10).summary("running_speed")
    wrong += _wrong(speed, ran.value, "0.5 m/s: the running speed from 3 to 10 s")
    wrong += _wrong(spread, ran.std, "0.5 m/s: its spread")
    wrong += _wrong(error, 100 * (ran.value / 0.5 - 1), "0.5 m/s: its error (%)")
    assert not wrong, "docs/api.md, Tuning a new creature: " + "; ".join(wrong)


def test_the_detuned_kangaroo(tmp_path: Path) -> None:
    text = _section("Tuning from detuned gains")
    command = re.search(r"(python docs/scripts/detune\.py .*? -o (\S+))", text)
    figures = re.search(
        r"it falls at ([\d.]+) s at 3 m/s and misses the other two speeds \(([\d.]+) and "
        r"([\d.]+) m/s for 4 and 5: ([-+]?[\d.]+)% and ([-+]?[\d.]+)%",
        text,
    )
    assert command and figures, "docs/api.md, Tuning from detuned gains: the sentences moved"
    shutil.copytree(ROOT / "creatures", tmp_path / "creatures")
    args = shlex.split(command[1].replace("\\ ", ""))
    subprocess.run([sys.executable, str(ROOT / args[1]), *args[2:]], cwd=tmp_path, check=True,
                   capture_output=True)  # fmt: skip
    creature = legdsl.load(tmp_path / command[2], generated=tmp_path / "generated")

    def run(speed: float) -> legdsl.Run:
        return creature.run(controller="hop", set={"speed": f"{speed:g} m/s"}, time=20)

    at_3, speed_4, speed_5, error_4, error_5 = figures.groups()
    wrong = _wrong(at_3, _fell_at(run(3)), "the fall at 3 m/s (s)")
    for command_speed, doc_speed, doc_error in [(4, speed_4, error_4), (5, speed_5, error_5)]:
        done = run(command_speed)
        assert done.status == "ok", f"at {command_speed} m/s: {done.info.get('message')}"
        ran = done.metrics(start=3).value("running_speed")
        wrong += _wrong(doc_speed, ran, f"{command_speed} m/s: the running speed from 3 s")
        wrong += _wrong(doc_error, 100 * (ran / command_speed - 1), f"{command_speed} m/s: %")
    assert not wrong, "docs/api.md, Tuning from detuned gains: " + "; ".join(wrong)
