"""Random calls of the public Python API (docs/api.md) on the shipped creatures, as people
outside the team make them, right and wrong, drawn from a seeded generator: ``legdsl.load``
(of the right file, or a missing one, a wrong creature name, a wrong ``generated=``),
``Creature.run`` with drawn ``controller``, ``set`` (texts with units, ``Quantity`` values,
numpy and plain numbers, changes ``NAME@T``), ``switch``, ``scene``, ``time`` and options
(``dt``, ``integrator``, ``control_dt``, ``record_rate``, ``fall_height``, ``fall_tilt``,
``drop``) written as texts with units, Quantities, numpy scalars or numbers, and wrongly: a
wrong unit, a wrong type (list, dict, None, bool, bytes, complex), NaN or infinity, zero or
negative, a misspelt name, an unknown controller; then the run's samples (``run[NAME]``, an
unknown name), ``run.metrics`` over a drawn window, ``run.save`` and ``legdsl.open_run``, and
now and then ``run_copies``. Runs are short (0.1 to 0.4 s).

Each call must either succeed, its run the same as ``legdsl run``'s with the same settings
(byte-identical trajectory arrays, for a drawn share of the cases), or raise ``UsageError``
(``LegError`` for a ``.leg`` mistake, ``KeyError``/``IndexError`` for a missing series or
copy, as documented) with a one-line message (or file:line:col and its caret) that is no
internal error and shows no Python object's repr; a value that is nonsense must not run.

``LEGDSL_RANDOM_API=N`` checks N draws (default ``CI_DRAWS``) from seed
``LEGDSL_RANDOM_API_SEED``, +1, ...; a failure names its seed and the command to repeat it.
"""

from __future__ import annotations

import functools
import math
import os
import shlex
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from runtime_helpers import legdsl_in_process
from seeded import told_with_seed
from set_values import in_unit, models, number

import legdsl
from legdsl.analysis.results import MetricsError
from legdsl.api import LegdslWarning, Quantity
from legdsl.lang.errors import LegError, UsageError
from legdsl.lang.units import parse_unit

ROOT = Path(__file__).resolve().parents[2]
SHIPPED = sorted((ROOT / "creatures").glob("*.leg"))
CI_DRAWS = 1
COUNT = int(os.environ.get("LEGDSL_RANDOM_API", CI_DRAWS))
FIRST_SEED = int(os.environ.get("LEGDSL_RANDOM_API_SEED", "0"))
ALLOWED = (UsageError, LegError, MetricsError)
# what a message for a person never shows: Python's own words for its objects
REPRS = ("Quantity(", " object at 0x", "internal error", "Traceback", "dim=(")


@dataclass
class Value:
    """One drawn argument: what Python is given, the CLI's text for it (None: no CLI form),
    and whether it is nonsense that must be refused."""

    given: Any
    cli: str | None
    wrong: bool = False


# each option: its SI unit, a sensible range (SI), and the least it takes
OPTIONS = {
    "dt": ("s", (2e-4, 1e-3), "positive", "--dt"),
    "control_dt": ("s", (1e-3, 5e-3), "positive", "--control-dt"),
    "record_rate": ("Hz", (50.0, 500.0), "nonnegative", "--record-rate"),
    "fall_height": ("m", (0.0, 0.05), "nonnegative", "--fall-height"),
    "fall_tilt": ("rad", (0.5, 3.0), "positive", "--fall-tilt"),
    "drop": ("m", (0.0, 0.1), "nonnegative", "--drop"),
}
SHOWN = {"s": ("ms", 1e-3), "Hz": ("Hz", 1.0), "m": ("cm", 1e-2), "rad": ("deg", math.pi / 180)}
WRONG_TYPES: list[Any] = [[1.0], {"a": 1}, None, True, b"1", 1j, np.bool_(True)]


def _option_value(rng: np.random.Generator, key: str, may_be_wrong: bool) -> Value:
    unit, (lo, hi), least, _ = OPTIONS[key]
    x = float(rng.uniform(lo, hi))
    shown, scale = SHOWN[unit]
    cli = f"{x!r}{unit}"
    form = int(rng.choice(range(10) if may_be_wrong else [0, 1, 2, 3, 4, 9]))
    if form <= 2:
        return Value(f"{number(x / scale)} {shown}", f"{number(x / scale)}{shown}")
    if form == 3:
        return Value(np.float64(x), cli)
    if form == 4:
        return Value(Quantity(x, parse_unit(unit)[1]), cli)
    if form == 5:  # a wrong unit
        return Value(f"{number(x)} kg", None, True)
    if form == 6:
        bad = WRONG_TYPES[int(rng.integers(len(WRONG_TYPES)))]
        return Value(bad, None, bad is not None)  # None is the file's (or the runner's)
    if form == 7:
        return Value(float(rng.choice([math.nan, math.inf, -math.inf])), None, True)
    if form == 8:
        if least == "positive":
            return Value(float(rng.choice([0.0, -x])), None, True)
        return Value(-x if x > 0 else -1.0, None, True)
    return Value(x, cli)


def _setting(
    rng: np.random.Generator, name: str, default: Quantity, end: float, may_be_wrong: bool
) -> tuple:
    """A ``set=`` entry: its key, its Value."""
    factor = float(rng.choice([0.5, 0.9, 1.0, 1.2, 2.0]))
    x = (default.value or 0.5) * factor
    key = name
    at = ""
    if rng.random() < 0.15:
        at = f"@{number(float(rng.uniform(0, end)))}s"
        key = f"{name}@{at[1:-1]} s"
    form = int(rng.choice(range(9) if may_be_wrong else [0, 1, 2, 3, 4, 5]))
    if form <= 3:
        text = in_unit(x, default.dim, " ")
        v = Value(text, text.replace(" ", ""))
    elif form == 4:
        v = Value(Quantity(x, default.dim), f"{x!r}{default.unit}")
    elif form == 5:  # a number: right only for a quantity without a unit
        v = Value(np.float64(x) if rng.random() < 0.5 else x, repr(x), bool(default.unit))
    elif form == 6:
        v = Value(f"{number(x)} kg*s" if default.unit else f"{number(x)} m", None, True)
    elif form == 7:
        bad = WRONG_TYPES[int(rng.integers(len(WRONG_TYPES)))]
        v = Value(bad, None, True)
    else:
        v = Value(f"{rng.choice(['nan', 'inf', '-inf'])} {default.unit}".strip(), None, True)
    if v.cli is not None:
        v.cli = f"{name}={v.cli}{at.replace(' ', '')}"
    return key, v


@dataclass
class Case:
    source: Path
    creature: str | None
    kwargs: dict[str, Any] = field(default_factory=dict)
    cli: list[str] = field(default_factory=list)  # legdsl run's words after FILE
    wrong: list[str] = field(default_factory=list)  # what is nonsense in it
    compare: bool = False
    metrics: dict[str, Any] = field(default_factory=dict)
    copies: bool = False

    def shown(self) -> str:
        said = f"legdsl.load({str(self.source.relative_to(ROOT))!r}, creature={self.creature!r})"
        said += f".run(**{self.kwargs!r})"
        cli = shlex.join(["legdsl", "run", str(self.source.relative_to(ROOT)), *self.cli])
        return f"{said}\nas the CLI: {cli}\nwrong: {self.wrong}\nmetrics: {self.metrics!r}"


def draw(seed: int) -> Case:
    rng = np.random.default_rng([seed, 47])
    source = Path(rng.choice(SHIPPED))
    all_models = models(source)
    model = all_models[int(rng.integers(len(all_models)))]
    case = Case(source, model.name if len(all_models) > 1 else None)
    if case.creature:
        case.cli += ["--creature", case.creature]
    end = float(rng.uniform(0.1, 0.4))
    mistaken = rng.random() < 0.5  # else every value drawn right (a number without a unit aside)
    wrong = lambda: mistaken and rng.random() < 0.3  # noqa: E731
    form = int(rng.integers(6) if wrong() else rng.integers(4))
    time: Value = [
        Value(end, f"{end!r}s"),
        Value(f"{number(end * 1000)} ms", f"{number(end * 1000)}ms"),
        Value(np.float32(end), f"{float(np.float32(end))!r}s"),
        Value(Quantity(end, parse_unit("s")[1]), f"{end!r}s"),
        Value(float(rng.choice([math.nan, math.inf, -1.0, 0.0])), None, True),
        Value(str(rng.choice(["1 m", "soon", ""])), None, True),
    ][form]
    case.kwargs["time"] = time.given
    case.cli += ["--time", time.cli] if time.cli else []
    case.wrong += ["time"] * time.wrong
    infos = legdsl_creature(source, case.creature).controllers
    names = list(infos)
    running = None
    if model.scenes and rng.random() < 0.2:
        scene = model.scenes[int(rng.integers(len(model.scenes)))]
        case.kwargs["scene"], case.cli = scene.name, [*case.cli, "--scene", scene.name]
        running = scene.controller
    elif names and rng.random() < 0.85:
        running = str(rng.choice(names))
        if wrong() and rng.random() < 0.2:
            running += "x"  # misspelt
            case.wrong.append("controller")
        case.kwargs["controller"] = running
        case.cli += ["--controller", running]
    else:
        case.kwargs["controller"] = None
    if running in infos:
        info = infos[running]
        every = {**info.inputs, **info.params}
        chosen = rng.choice(
            sorted(every), size=min(len(every), int(rng.integers(0, 3))), replace=False
        )
        settings = {}
        for name in chosen:
            key, v = _setting(rng, str(name), every[str(name)], end, wrong())
            if "@" in key and name not in info.inputs:
                key = str(name)  # only an input changes during a run
                v.cli = v.cli.split("@")[0] if v.cli else None
            settings[key] = v.given
            case.cli += ["--set", v.cli] if v.cli else []
            case.wrong += [f"set {key}"] * v.wrong
        if settings:
            case.kwargs["set"] = settings
        if rng.random() < 0.15 and len(names) > 1:
            other = str(rng.choice(names))
            when = number(float(rng.uniform(0.02, end)))
            case.kwargs["switch"] = {f"{when} s": other}
            case.cli += ["--switch", f"{when}s={other}"]
    for key in rng.choice(sorted(OPTIONS), size=int(rng.integers(0, 4)), replace=False):
        v = _option_value(rng, str(key), wrong())
        case.kwargs[str(key)] = v.given
        case.cli += [OPTIONS[str(key)][3], v.cli] if v.cli else []
        case.wrong += [str(key)] * v.wrong
    if wrong() and rng.random() < 0.2:
        case.kwargs[str(rng.choice(["dtt", "integrater", "recordrate", "times"]))] = 1
        case.wrong.append("misspelt option")
    if rng.random() < 0.2:
        integrator = str(
            rng.choice(["rk4", "euler", "rk5", "RK4"] if wrong() else ["rk4", "euler"])
        )
        case.kwargs["integrator"] = integrator
        case.cli += ["--integrator", integrator]
        case.wrong += ["integrator"] * (integrator not in ("rk4", "euler"))
    case.compare = rng.random() < 0.4
    start = float(rng.uniform(0, end))
    case.metrics = {
        "start": [start, f"{number(start * 1000)} ms", np.float64(start)][int(rng.integers(3))]
    }
    if rng.random() < 0.5:
        case.metrics["end"] = float(rng.uniform(0, end * 1.2))
    if rng.random() < 0.2:
        case.metrics[str(rng.choice(["start", "end"]))] = WRONG_TYPES[
            int(rng.integers(len(WRONG_TYPES)))
        ]
    case.copies = bool(running in infos and rng.random() < 0.15)
    return case


@functools.cache
def _loaded(source: Path, creature: str | None, generated: Path) -> Any:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", LegdslWarning)
        return legdsl.load(source, creature=creature, generated=generated)


_GENERATED: list[Path] = []


def legdsl_creature(source: Path, creature: str | None) -> Any:
    return _loaded(source, creature, _GENERATED[0])


def _told(e: BaseException) -> str:
    """The message of a refusal: checked to be one for a person."""
    assert isinstance(e, ALLOWED), f"{type(e).__name__} from inside: {e}"
    said = str(e)
    assert not any(r in said for r in REPRS), f"not for a person: {said}"
    lines = [x for x in said.splitlines() if x.strip()]
    assert len(lines) == 1 or any(x.strip().startswith("^") for x in lines), said
    return said


def _same_arrays(a: Path, b: Path) -> None:
    with np.load(a / "trajectory.npz") as pa, np.load(b / "trajectory.npz") as pb:
        assert pa.files == pb.files
        for name in pa.files:
            assert pa[name].tobytes() == pb[name].tobytes(), f"{name} differs"


def _wrong_loads(rng: np.random.Generator, case: Case, folder: Path, generated: Path) -> None:
    """A load of a missing file, a wrong creature, a wrong ``generated=``: refused, told."""
    wrong = [
        lambda: legdsl.load(folder / "missing.leg", generated=generated),
        lambda: legdsl.load(case.source, creature="nobody", generated=generated),
        lambda: legdsl.load(case.source, creature=case.creature, generated=case.source),
        lambda: legdsl.load(case.source, creature=case.creature, generated=3),
        lambda: legdsl.load(str(ROOT / "creatures"), generated=generated),
        lambda: legdsl.load(b"creatures/hopper.leg", generated=generated),
    ]
    for call in rng.choice(wrong, size=2, replace=False):
        with pytest.raises(Exception) as raised:  # noqa: PT011  (_told checks its type)
            call()
        _told(raised.value)


def check_case(seed: int, case: Case, folder: Path, generated: Path) -> str:
    """Check one case; what it came to (``ran``, or the refusal's message)."""
    rng = np.random.default_rng([seed, 48])
    _wrong_loads(rng, case, folder, generated)
    creature = legdsl_creature(case.source, case.creature)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", LegdslWarning)
            run = creature.run(**case.kwargs)
    except Exception as e:  # noqa: BLE001  (_told checks its type)
        return _told(e)
    assert not case.wrong, f"ran with nonsense ({', '.join(case.wrong)}): {run!r}"
    com = run["com.x"]
    assert len(com) == len(run) and not com.flags.writeable
    with pytest.raises(KeyError, match="no series"):
        run[str(rng.choice(["com.w", "q.nothing", "COM.x", ""]))]
    try:
        run.metrics(**case.metrics)
    except Exception as e:  # noqa: BLE001
        _told(e)
    saved = run.save(folder / "api")
    again = legdsl.open_run(saved, generated=generated)
    for name, values in run.samples.items():
        assert again[name].tobytes() == values.tobytes(), f"open_run: {name} differs"
    if case.compare:
        argv = ["run", str(case.source), *case.cli, "--generated", str(generated)]
        code, err = legdsl_in_process([*argv, "--out", str(folder / "cli")])
        assert code in (0, 3, 4), f"the CLI said (exit {code}): {err}"
        _same_arrays(folder / "api", folder / "cli")
    if case.copies:
        _check_copies(case, creature, run)
    return "ran"


def _check_copies(case: Case, creature: Any, run: Any) -> None:
    """Two copies of the run: each as ``run`` gives it (vary= nothing, so both alike)."""
    keys = ("controller", "set", "time", *OPTIONS, "integrator")
    kwargs = {k: v for k, v in case.kwargs.items() if k in keys}
    if "switch" in case.kwargs or "scene" in case.kwargs:
        return
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", LegdslWarning)
        copies = creature.run_copies(2, **kwargs)
    assert len(copies) == 2
    for name, values in run.samples.items():
        assert copies[1][name].tobytes() == values.tobytes(), f"copy 1: {name} differs"
    with pytest.raises(IndexError):
        copies[2]


SEEDS = range(FIRST_SEED, FIRST_SEED + COUNT)


@pytest.mark.parametrize("seed", SEEDS)
def test_random_api_calls_run_or_say_why(seed: int, tmp_path: Path, generated: Path) -> None:
    _GENERATED[:] = [generated]
    case = draw(seed)
    rerun = f"LEGDSL_RANDOM_API_SEED={seed} LEGDSL_RANDOM_API=1"
    with told_with_seed(f"random API calls of seed {seed}", rerun, case.shown):
        check_case(seed, case, tmp_path, generated)


# Found by probing the API as the draws do (each failed before its fix):


def test_found_a_run_of_more_steps_than_the_c_loop_counts_is_refused(generated: Path) -> None:
    """time=1e300 ended at its start with status ok on the C backend (its int64 step count
    wrapped) and ran for ever on Python's; dt=1e-300 was ZeroDivisionError (the stiffness
    check divides by dt squared); control_dt=1e300 wrapped as the run did."""
    hopper = _loaded(ROOT / "creatures" / "hopper.leg", None, generated)
    for kwargs, said in [
        ({"time": 1e300}, "more than a run can count"),
        ({"time": 0.1, "dt": 1e-300}, "too small to compute with"),
        ({"time": 0.1, "dt": 1e-100}, "more than a run can count"),
        ({"time": 0.1, "control_dt": 1e300}, "more than a run can count"),
    ]:
        with pytest.raises(UsageError, match=said):
            hopper.run(controller="hop", **kwargs)


def test_found_a_whole_number_too_large_for_a_double_is_told(generated: Path) -> None:
    """dt=10**400 (and time=, set= values, metrics' start=) was float()'s OverflowError."""
    hopper = _loaded(ROOT / "creatures" / "hopper.leg", None, generated)
    for kwargs in ({"time": 10**400}, {"time": 0.1, "dt": 10**400},
                   {"time": 0.1, "set": {"kp": 10**400}}):  # fmt: skip
        with pytest.raises(UsageError, match="too large for a double") as raised:
            hopper.run(controller="hop", **kwargs)
        _told(raised.value)
    run = hopper.run(controller="hop", time=0.1)
    with pytest.raises(UsageError, match="too large for a double"):
        run.metrics(start=10**400)


def test_found_a_quantity_is_a_time_or_option_with_its_unit(generated: Path) -> None:
    """A Quantity (as load gives a controller's values) went to set= but was refused as time=,
    an option or a metrics window with its repr (``Quantity(value=0.06, dim=(0, 0, 1, 0))``);
    it is taken with its unit, checked as a text's."""
    hopper = _loaded(ROOT / "creatures" / "hopper.leg", None, generated)
    hop = hopper.controllers["hop"]
    seconds = hop.params["k_speed"]  # 0.06 s
    run = hopper.run(controller="hop", time=Quantity(0.1, seconds.dim),
                     dt=Quantity(4e-4, seconds.dim))  # fmt: skip
    alike = hopper.run(controller="hop", time=0.1, dt=4e-4)
    assert run["com.x"].tobytes() == alike["com.x"].tobytes()
    assert run.metrics(start=seconds).t_from == 0.06
    with pytest.raises(UsageError, match="is a time") as raised:
        hopper.run(controller="hop", time=hop.params["kp"])
    _told(raised.value)


def test_found_a_set_name_not_a_text_is_told_as_the_name(generated: Path) -> None:
    """set={1: '1 m/s'} said its value was wrong ('not '1 m/s''); the name is."""
    hopper = _loaded(ROOT / "creatures" / "hopper.leg", None, generated)
    with pytest.raises(UsageError, match="a name is a text"):
        hopper.run(controller="hop", set={1: "1 m/s"}, time=0.1)


def test_found_a_change_before_the_start_is_refused(generated: Path, tmp_path: Path) -> None:
    """set={'speed@-1s': ...} (and --set speed=1m/s@-1s) ran as if set from the start, while
    --switch -1s=... is refused."""
    hopper = _loaded(ROOT / "creatures" / "hopper.leg", None, generated)
    with pytest.raises(UsageError, match="write --set speed=1m/s"):
        hopper.run(controller="hop", set={"speed@-1 s": "1 m/s"}, time=0.1)
    code, err = legdsl_in_process(["run", str(ROOT / "creatures" / "hopper.leg"), "--controller",
                                   "hop", "--set", "speed=1m/s@-1s", "--generated",
                                   str(generated), "--out", str(tmp_path / "run")])  # fmt: skip
    assert code == 2 and "0 or more" in err


def test_found_copies_of_a_value_too_large_for_a_double_are_told(generated: Path) -> None:
    """run_copies(vary={'speed': ([10**400, 2], 'm/s')}) (or such a q0) was OverflowError."""
    hopper = _loaded(ROOT / "creatures" / "hopper.leg", None, generated)
    with pytest.raises(UsageError, match="vary speed: a value is too large for a double"):
        hopper.run_copies(2, "hop", vary={"speed": ([10**400, 2], "m/s")}, time=0.1)
    with pytest.raises(UsageError, match="q0: a value is too large for a double"):
        hopper.run_copies(2, "hop", q0=[[10**400] * 5] * 2, time=0.1)


def test_found_an_empty_path_is_no_directory(
    generated: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """run.save("") wrote the run into the current directory (``Path("")`` is "."), and
    generated="" would have compiled there."""
    monkeypatch.chdir(tmp_path)
    hopper = _loaded(ROOT / "creatures" / "hopper.leg", None, generated)
    run = hopper.run(controller="hop", time=0.05)
    with pytest.raises(UsageError, match="give a path"):
        run.save("")
    with pytest.raises(UsageError, match="generated= is the directory"):
        legdsl.load(ROOT / "creatures" / "hopper.leg", generated=" ")
    assert not list(tmp_path.iterdir())
