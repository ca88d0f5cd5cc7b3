from __future__ import annotations

import functools
import shutil
import types
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

import pytest

import legdsl  # noqa: F401  before any test module imports sympy: its cache size (legdsl/__init__.py)

if TYPE_CHECKING:
    from legdsl.ir.model import Model
    from legdsl.pipeline.compile import Compiled
    from legdsl.pipeline.session import RunSession

ROOT = Path(__file__).resolve().parents[1]
CREATURES = ROOT / "creatures"
GENERATED = ROOT / "generated"
OUTSIDE = ROOT / "tests" / "good" / "outside"  # creatures written outside the team
SHIPPED = ("kangaroo", "biped", "quadruped", "hopper")
_SHARED: list[Path] = []  # this test process's folder of generated modules kept for the session


@pytest.fixture(scope="session", autouse=True)
def _c_cache(tmp_path_factory: pytest.TempPathFactory) -> Iterator[None]:
    """One cache of compiled C libraries for the session, shared by its xdist workers (their
    base directories are siblings) and the ``legdsl`` processes tests start: each creature's
    library is built once, and never into the user's own cache."""
    import os

    base = tmp_path_factory.getbasetemp()
    shared = base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base
    before = os.environ.get("LEGDSL_CACHE")
    os.environ["LEGDSL_CACHE"] = str(shared / "c-cache")
    yield
    if before is None:
        del os.environ["LEGDSL_CACHE"]
    else:
        os.environ["LEGDSL_CACHE"] = before


@pytest.fixture(scope="session", autouse=True)
def _ctrl_c_as_at_a_terminal() -> Iterator[None]:
    """Ctrl-C handled as at a terminal, though the suite was started as a background job
    (``bash .ci/run &``), which starts every process with SIGINT and SIGQUIT ignored, or under
    ``nohup`` (SIGHUP ignored): the tests that send one, to this process or to a ``legdsl`` it
    starts (which inherits what is ignored), ran on to their ends and failed, and a legdsl told
    to run for 1e9 s ran on after its test, for an hour."""
    import signal

    ignored = [s for s in (signal.SIGINT, signal.SIGQUIT, signal.SIGHUP)
               if signal.getsignal(s) is signal.SIG_IGN]  # fmt: skip
    for sig in ignored:
        signal.signal(sig, signal.default_int_handler if sig == signal.SIGINT else signal.SIG_DFL)
    yield
    for sig in ignored:
        signal.signal(sig, signal.SIG_IGN)


def _project_files() -> dict[str, tuple[int, int]]:
    """Each file of generated/ with its size and time of change, and each top-level entry."""
    found = {str(p.relative_to(ROOT)): (p.stat().st_size, p.stat().st_mtime_ns)
             for p in GENERATED.rglob("*") if p.is_file() and "__pycache__" not in p.parts}  # fmt: skip
    # MuJoCo writes its warnings to MUJOCO_LOG.TXT in the working directory (ignored by git)
    return found | {e.name: (0, 0) for e in ROOT.iterdir() if e.name != "MUJOCO_LOG.TXT"}


@pytest.fixture(scope="session", autouse=True)
def _project_untouched() -> Iterator[None]:
    """No test writes into the project: a ``legdsl run`` of a copied .leg without
    ``--generated`` wrote its modules over the golden generated/biped (the next golden check
    then saw them changed). Told at the session's end, with each changed file's first line,
    which names the test's folder ('from test_NAME_0/biped.leg')."""
    before = _project_files()
    yield
    after = _project_files()
    changed = sorted(name for name in before.keys() | after.keys()
                     if before.get(name) != after.get(name) and not name.startswith("."))  # fmt: skip
    if changed:

        def first_line(name: str) -> str:
            path = ROOT / name
            if not path.is_file():
                return "" if path.exists() else " (removed)"
            return f": {path.read_text(errors='replace').partition(chr(10))[0]}"

        listed = "\n".join(f"  {name}{first_line(name)}" for name in changed[:20])
        pytest.fail(f"tests wrote into the project (give them tmp_path):\n{listed}")


@pytest.fixture(scope="session", autouse=True)
def _shared_generated(tmp_path_factory: pytest.TempPathFactory) -> None:
    """The folder the outside creatures compile into, shared by the xdist workers as the C
    cache is: a creature's sympy lowering (seconds) is done by the first worker to need it
    and found by the others (modules are written whole, under a rename, so a worker never
    reads half of one; two compiling at once both write the same bytes)."""
    import os

    base = tmp_path_factory.getbasetemp()
    shared = base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base
    folder = shared / "shared-generated"
    folder.mkdir(exist_ok=True)
    _SHARED.append(folder)


@functools.cache
def outside_session(file: str) -> RunSession:
    """The session of ``tests/good/outside/FILE``, compiled once in this test process for all
    the tests that run it as written (its sympy lowering takes seconds). A run leaves its
    session as it was; a test that edits the file compiles its own copy."""
    from legdsl.pipeline.session import RunSession

    return RunSession.from_file(OUTSIDE / file, generated=_SHARED[0])


@pytest.fixture(scope="module")
def generated(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A copy of the checked-in generated modules: a stale one is recompiled here, never in the repo."""
    target = tmp_path_factory.mktemp("generated")
    if (ROOT / "generated").is_dir():
        shutil.copytree(ROOT / "generated", target, dirs_exist_ok=True)
    return target


@pytest.fixture
def hopper_modules(tmp_path: Path) -> None:
    """The checked-in hopper modules copied into ``tmp_path / "generated"``, so that a test
    that hands that fresh folder to a command (sweep, tune) finds them there instead of
    compiling them again (the folder then holds what a first compile would have written).
    A file takes it with ``pytestmark = pytest.mark.usefixtures("hopper_modules")``."""
    shutil.copytree(GENERATED / "hopper", tmp_path / "generated" / "hopper", dirs_exist_ok=True)


@pytest.fixture
def creatures_dir() -> Path:
    return CREATURES


def load_module(text: str, name: str) -> types.ModuleType:
    """A generated module from its text, without writing it anywhere."""
    module = types.ModuleType(name)
    exec(compile(text, f"<generated {name}>", "exec"), module.__dict__)
    return module


@functools.cache
def compiled_creature(name: str) -> Compiled:
    """A shipped creature compiled once per test session (compiling takes seconds)."""
    from legdsl.pipeline.compile import compile_model

    return compile_model(CREATURES / f"{name}.leg")


@functools.cache
def shipped_model(name: str) -> Model:
    from legdsl.check.source import check_model

    return check_model(CREATURES / f"{name}.leg")


@functools.cache
def shipped_dynamics(name: str) -> types.ModuleType:
    """The checked-in golden module: the numeric tests back the goldens (test_goldens keeps
    them equal to what the compiler prints now)."""
    return load_module((GENERATED / name / "dynamics.py").read_text(encoding="utf-8"), name)


def compile_text(tmp_path: Path, text: str) -> tuple[Model, types.ModuleType]:
    """Compile .leg text written to a temporary file; the model and the loaded dynamics module."""
    from legdsl.pipeline.compile import compile_model

    path = tmp_path / "creature.leg"
    path.write_text(text, encoding="utf-8")
    compiled = compile_model(path)
    return compiled.model, load_module(compiled.text("dynamics.py"), compiled.name)


@pytest.fixture
def drawn(monkeypatch: pytest.MonkeyPatch) -> list[Any]:
    """The matplotlib figures saved during the test, in order (the drawing functions close
    them after saving, so a test reads their axes here)."""
    from matplotlib.figure import Figure

    figures: list[Any] = []
    save = Figure.savefig

    def keep(self: Figure, *args: object, **kwargs: object) -> None:
        figures.append(self)
        save(self, *args, **kwargs)

    monkeypatch.setattr(Figure, "savefig", keep)
    return figures
