"""The Python API's mistakes are ``UsageError``s saying what to write (docs/api.md: "A mistake
is a UsageError raised before anything runs"), not a TypeError from deep inside."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import legdsl
from legdsl.lang.errors import UsageError

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def hopper(generated: Path) -> legdsl.Creature:
    return legdsl.load(ROOT / "creatures" / "hopper.leg", generated=generated)


RUN_MISTAKES: list[tuple[dict[str, Any], str]] = [
    ({"set": {"speed": None}}, "give a value with its unit as text"),
    ({"set": {"speed": [1]}}, "give a value with its unit as text"),
    ({"set": ["speed=1m/s"]}, "set= maps names to values"),
    ({"set": "speed=1m/s"}, "set= maps names to values"),
    ({"set": {3: "1 m/s"}}, "set 3: a name is a text"),
    ({"time": True}, "time= is seconds"),
    ({"time": [1]}, "time= is seconds"),
    ({"time": "2 kg"}, r"time='2 kg': time= is a time \(s\).*write e.g. time='2 s'"),
    ({"time": "x"}, "is not a number"),
]


@pytest.mark.parametrize(("kwargs", "message"), RUN_MISTAKES, ids=[str(k) for k, _ in RUN_MISTAKES])
def test_a_wrong_run_argument_is_a_usage_error(
    hopper: legdsl.Creature, kwargs: dict[str, Any], message: str
) -> None:
    with pytest.raises(UsageError, match=message):
        hopper.run(controller="hop", **kwargs)


def test_time_takes_a_unit(hopper: legdsl.Creature) -> None:
    run = hopper.run(controller="hop", time="50 ms")
    assert run.info["options"]["duration"] == pytest.approx(0.05)


COPIES_MISTAKES: list[tuple[Any, dict[str, Any], str]] = [
    (2.5, {}, "give their number as a whole number"),
    ("2", {}, "give their number as a whole number"),
    (True, {}, "give their number as a whole number"),
    (2, {"speed": [1, 2]}, r"their unit as a pair, e.g. \{'speed': \(values, 'm/s'\)\}"),
    (2, {"speed": ([1, 2], "m/s", 3)}, "their unit as a pair"),
    (2, {"speed": ([1, 2], 3)}, "their unit as a pair"),
    (2, {"speed": (["a", "b"], "m/s")}, "its values are not all numbers"),
    (2, {"speed": ([1, None], "m/s")}, "every value must be finite"),
]


@pytest.mark.parametrize(("n", "vary", "message"), COPIES_MISTAKES,
                         ids=[f"{n!r}-{v}" for n, v, _ in COPIES_MISTAKES])  # fmt: skip
def test_wrong_copies_are_a_usage_error(
    hopper: legdsl.Creature, n: Any, vary: dict[str, Any], message: str
) -> None:
    with pytest.raises(UsageError, match=message):
        hopper.run_copies(n, "hop", vary=vary, time=0.05)


@pytest.mark.parametrize("threads", [0, -1, 1.5, True, "2"])
def test_threads_are_a_whole_number_of_one_or_more(hopper: legdsl.Creature, threads: Any) -> None:
    with pytest.raises(UsageError, match="a whole number, 1 or more"):
        hopper.run_copies(2, "hop", time=0.05, threads=threads)
    with pytest.raises(UsageError, match="a whole number, 1 or more"):
        list(hopper.run_many([{"controller": "hop", "time": 0.05}], threads=threads))


@pytest.mark.parametrize(("start", "end"), [(-1.0, None), (float("nan"), None), (0.0, -2.0)])
def test_a_metrics_window_before_the_run_is_a_usage_error(
    hopper: legdsl.Creature, start: float, end: float | None
) -> None:
    from legdsl.analysis.metrics import MetricsError, compute_metrics

    run = hopper.run(controller="hop", time=1.0)
    with pytest.raises(UsageError, match="0 or more"):
        run.metrics(start=start, end=end)
    with pytest.raises(MetricsError, match="give a time of 0 s or more"):  # beneath the API
        compute_metrics(run.trajectory, t_from=start, t_to=end)


OPTION_MISTAKES: list[tuple[dict[str, Any], str]] = [
    ({"record_rate": "100 m"}, r"record_rate= is a frequency .*, but 100m is a length"),
    ({"drop": "1 s"}, r"drop= is a length .*, but 1s is a time.*drop='1 m'"),
    ({"fall_height": "0.3 kg"}, r"fall_height= is a length .*, but 0.3kg is a mass"),
    ({"fall_tilt": "30 m"}, r"fall_tilt= is an angle .*, but 30m is a length"),
    (
        {"fall_tilt": 60},
        r"fall_tilt=60 \(radians: 3438 deg\) is past upside down .* fall_tilt='60 deg'",
    ),
    (
        {"fall_tilt": True},
        r"fall_tilt= is a number in SI units, or a text with its unit \(e.g. fall_tilt=.60 deg.\), not True",
    ),
    (
        {"dt": True},
        r"dt= is a number in SI units, or a text with its unit \(e.g. dt=.0.4 ms.\), not True",
    ),
    ({"switch": {None: "hop"}}, r"switch= maps times to controllers"),
    ({"controler": "hop"}, r"no option 'controler'.*did you mean 'controller'\?"),
    ({"sett": {"speed": "1 m/s"}}, r"did you mean 'set'\?"),
]


@pytest.mark.parametrize(("kwargs", "message"), OPTION_MISTAKES,
                         ids=[str(k) for k, _ in OPTION_MISTAKES])  # fmt: skip
def test_a_wrong_option_is_a_usage_error(
    hopper: legdsl.Creature, kwargs: dict[str, Any], message: str
) -> None:
    """A text for a number option was a TypeError from math.isfinite, an int time in switch=
    an AttributeError, and a typo of controller= was taken for control_dt."""
    with pytest.raises(UsageError, match=message):
        hopper.run(**{"controller": "hop", "time": 0.05, **kwargs})


def test_options_written_with_their_units_are_read_as_legdsl_run_reads_them(
    hopper: legdsl.Creature,
) -> None:
    """fall_tilt=60 ran with a limit of 60 rad (never reached) and fall_tilt="60 deg" was
    refused, while time="500 ms" was taken."""
    with_units = hopper.run(controller="hop", time="0.1 s", dt="0.4 ms", fall_tilt="60 deg",
                            record_rate="1 kHz", drop="1 cm")  # fmt: skip
    in_si = hopper.run(controller="hop", time=0.1, dt=4e-4, fall_tilt=math.radians(60),
                       record_rate=1000.0, drop=0.01)  # fmt: skip
    assert np.array_equal(with_units.trajectory.q, in_si.trajectory.q)
    assert len(in_si.trajectory.q) > 80  # recorded at 1 kHz (every third 0.4 ms step)


def test_wrong_arguments_beside_a_run_are_usage_errors(
    hopper: legdsl.Creature, tmp_path: Path
) -> None:
    """Each was a TypeError (expected str, bytes or os.PathLike; 'int' is not iterable)."""
    source = ROOT / "creatures" / "hopper.leg"
    with pytest.raises(UsageError, match="creature= is the name of a creature"):
        legdsl.load(source, creature=3)  # type: ignore[arg-type]
    with pytest.raises(UsageError, match="generated= is the directory"):
        legdsl.load(source, generated=3)  # type: ignore[arg-type]
    run = hopper.run(controller="hop", time=0.05)
    with pytest.raises(UsageError, match=r"groups= is a dict .* or a list of texts"):
        run.metrics(groups=3)  # type: ignore[arg-type]
    with pytest.raises(UsageError, match="leg= is the name of a leg"):
        run.metrics(leg=3)  # type: ignore[arg-type]
    for call in (run.save, run.plot, run.animate):
        with pytest.raises(UsageError, match=r"give a path \(a text or a pathlib.Path\)"):
            call(3)  # type: ignore[operator]
    with pytest.raises(UsageError, match=r"open_run\(\): give a path"):
        legdsl.open_run(run.save(tmp_path / "run"), source=3)  # type: ignore[arg-type]
    with pytest.raises(UsageError, match="progress= is a function"):
        hopper.run_copies(2, "hop", time=0.05, progress=3)  # type: ignore[arg-type]
