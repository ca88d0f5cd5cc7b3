"""The API dropped every blank of a text with its unit, as an outside user found:
``run(set={'speed': '1.5 2 m/s'}, time='3 00 ms', drop='1 0 cm')`` ran 1.52 m/s for 0.3 s
from 0.1 m up, and ``metrics(start='0 1 s')`` measured from 1 s, while ``Quantity('1.5 2
m/s')`` and ``--set speed=1.5 2m/s`` refused them. Every text is read one way now: a number,
blanks or none, a unit; blanks inside the number (its sign too) or between a unit's symbols
are refused in the argument's words."""

from __future__ import annotations

from pathlib import Path

import pytest

import legdsl
from legdsl.lang.errors import UsageError

HOPPER = Path(__file__).resolve().parents[2] / "creatures" / "hopper.leg"
pytestmark = pytest.mark.usefixtures("hopper_modules")
BLANKS = "a number is written without blanks inside it"


@pytest.mark.parametrize(
    ("given", "said"),
    [
        ({"set": {"speed": "1.5 2 m/s"}},
         f"set 'speed': '1.5 2 m/s': {BLANKS}; write its digits together, then its unit, e.g. "
         "set={'speed': '1.52 m/s'}"),
        ({"time": "3 00 ms"}, f"time='3 00 ms': {BLANKS}; write its digits together, then its "
         "unit, e.g. time='300 ms'"),
        ({"drop": "1 0 cm"}, f"drop='1 0 cm': {BLANKS}"),
        ({"drop": "1.5 e-2 m"}, f"drop='1.5 e-2 m': {BLANKS}"),
        ({"set": {"speed@0.1 0 s": "1 m/s"}}, f"set 'speed@0.1 0 s': the time after '@': {BLANKS}"),
        ({"set": {"speed": "- 1 m/s"}}, f"set 'speed': '- 1 m/s': {BLANKS}, its sign too"),
        ({"set": {"speed@2 m s": "1 m/s"}}, "set 'speed@2 m s': the time after '@': a unit is "
         "written without blanks inside it, its symbols joined by '*'"),  # it read as 2 ms
    ],
)  # fmt: skip
def test_blanks_inside_a_number_are_refused(tmp_path: Path, given: dict, said: str) -> None:
    creature = legdsl.load(str(HOPPER), generated=str(tmp_path / "generated"))
    with pytest.raises(UsageError) as e:
        creature.run(controller="hop", **{"time": 0.05, **given})
    assert str(e.value).startswith(said), str(e.value)


def test_blanks_between_number_and_unit_are_read(tmp_path: Path) -> None:
    creature = legdsl.load(str(HOPPER), generated=str(tmp_path / "generated"))
    run = creature.run(controller="hop", set={"speed": " 1.5 m / s "}, time="50 ms")
    assert run.info["inputs"]["speed"] == 1.5
    assert run.info["options"]["duration"] == 0.05
    for kw in ({"start": "0 1 s"}, {"min_stance": "2 0 ms"}):
        with pytest.raises(UsageError, match=BLANKS):
            run.metrics(**kw)


def test_a_switch_time_with_blanks_in_its_number_is_refused(tmp_path: Path) -> None:
    """switch={'0.1 0 s': ...} ran the switch at 0.10 s (run_options dropped the blanks)."""
    creature = legdsl.load(str(HOPPER), generated=str(tmp_path / "generated"))
    with pytest.raises(UsageError, match=rf"^run\(\): switch=\{{'0.1 0 s': ...\}}: {BLANKS}"):
        creature.run(controller="hop", switch={"0.1 0 s": "hop"}, time=0.3)


def test_a_time_option_of_the_commands_with_blanks_in_its_number_is_refused() -> None:
    """read_seconds (legdsl metrics --min-stance, a sweep's times) dropped the blanks too:
    '1 0 ms' read as 10 ms."""
    from legdsl.pipeline.options import read_seconds

    assert read_seconds("--min-stance", " 500 ms ") == 0.5
    with pytest.raises(UsageError, match=rf"^--min-stance '1 0 ms': {BLANKS}; .* '10 ms'$"):
        read_seconds("--min-stance", "1 0 ms")
