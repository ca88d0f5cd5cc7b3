"""The package reads as the pipeline: each stage imports only itself and the stages before it.

Every ``import`` in ``src/legdsl`` is read from the source (also those inside functions), so a
lazy import cannot hide a dependency that runs against the flow, and no two modules may import
each other, directly or round a longer cycle.
"""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = ROOT / "src" / "legdsl"

# The stages, in pipeline order. The package root (``legdsl/__init__.py``: the version, and
# ``legdsl/files.py``: writing files whole; ``legdsl/figures.py``: numbers as printed;
# ``legdsl/signals.py``: Ctrl-C held back) sits below them all; ``cli`` and ``__main__`` on top.
STAGES = (
    "lang",  # text -> syntax tree; units; the error types
    "ir",  # the checked model and controller IR
    "check",  # syntax tree -> IR
    "lower",  # IR -> sympy (dynamics, kinematics, control laws)
    "codegen",  # sympy -> printed modules, one sub-package per target
    "sim",  # the runtime: actuators, contact, sensors, state machine, integration
    "analysis",  # metrics and plots of a run
    "pipeline",  # the compile driver and the run session
    "export",  # files for other programs and people: MJCF, glTF, player, video
    "api",  # the public Python API: legdsl.load(...).run(...)
    "cli",
)
TOP = {
    "__init__": -1,
    "files": -1,
    "figures": -1,
    "signals": -1,
    "cli": STAGES.index("cli"),
    "__main__": STAGES.index("cli"),
}
# The package root sits below every stage (they read its __version__), yet it is the face of
# the public API: it may import ``legdsl.api``, lazily (module __getattr__), with Ctrl-C held
# back (``legdsl.signals``), and nothing else.
ROOT_MAY_IMPORT = ("legdsl.api", "legdsl.signals")


def module_name(path: Path, package: Path = PACKAGE) -> str:
    parts = list(path.relative_to(package.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def stage_of(module: str) -> int:
    """The stage index of ``legdsl.X...``."""
    parts = module.split(".")
    if len(parts) == 1:
        return TOP["__init__"]
    if parts[1] in TOP:
        return TOP[parts[1]]
    return STAGES.index(parts[1])


def imports_of(path: Path, package: Path = PACKAGE) -> list[tuple[str, int]]:
    """The ``legdsl`` modules a file imports, with the line of each import."""
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    here = module_name(path, package).split(".")
    if path.name != "__init__.py":
        here = here[:-1]  # the package a module's relative imports start from
    found: list[tuple[str, int]] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found += [(a.name, node.lineno) for a in node.names if a.name.startswith("legdsl")]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = here[: len(here) - node.level + 1]
                target = ".".join([*base, *([node.module] if node.module else [])])
            else:
                target = node.module or ""
            if not target.startswith("legdsl"):
                continue
            # ``from legdsl.lang import ast`` imports the module legdsl.lang.ast
            for alias in node.names:
                sub = f"{target}.{alias.name}"
                is_module = (package.parent / Path(*sub.split("."))).with_suffix(".py").is_file()
                found.append((sub if is_module else target, node.lineno))
    return found


def flow_violations(package: Path = PACKAGE) -> list[str]:
    """One line per import that runs against the pipeline, naming both files."""
    out = []
    for path in sorted(package.rglob("*.py")):
        source = module_name(path, package)
        for target, line in imports_of(path, package):
            if source == "legdsl" and target in ROOT_MAY_IMPORT:
                continue
            if stage_of(target) > stage_of(source):
                rel = path.relative_to(package.parent)
                rel = f"src/{rel}" if package.parent.name == "src" else rel
                out.append(
                    f"{rel}:{line} imports {target}: stage '{_stage_word(source)}' may not "
                    f"import from the later stage '{_stage_word(target)}' (the flow is "
                    f"{' -> '.join(STAGES)})"
                )
    return out


def cycles(package: Path = PACKAGE) -> list[list[str]]:
    """Import cycles between modules (strongly connected components of two or more)."""
    graph: dict[str, set[str]] = {}
    for path in sorted(package.rglob("*.py")):
        source = module_name(path, package)
        graph.setdefault(source, set())
        for target, _ in imports_of(path, package):
            if target != source and not source.startswith(target + "."):
                graph[source].add(target)
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    found: list[list[str]] = []

    def visit(node: str) -> None:  # Tarjan's algorithm
        index[node] = low[node] = len(index)
        stack.append(node)
        for nxt in sorted(graph.get(node, ())):
            if nxt not in index:
                visit(nxt)
                low[node] = min(low[node], low[nxt])
            elif nxt in stack:
                low[node] = min(low[node], index[nxt])
        if low[node] == index[node]:
            component = []
            while True:
                top = stack.pop()
                component.append(top)
                if top == node:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for node in sorted(graph):
        if node not in index:
            visit(node)
    return found


def _stage_word(module: str) -> str:
    s = stage_of(module)
    return "legdsl (the package root)" if s < 0 else STAGES[s]


def test_every_package_is_a_stage() -> None:
    for child in sorted(PACKAGE.iterdir()):
        if child.is_dir() and (child / "__init__.py").is_file():
            assert child.name in STAGES, f"{child}: a package that is not a pipeline stage"
        elif child.suffix == ".py":
            assert child.stem in TOP, f"{child}: a module outside the stage packages"


def test_imports_go_down_the_pipeline() -> None:
    bad = flow_violations()
    assert not bad, "imports against the pipeline:\n" + "\n".join(bad)


def test_a_run_of_fresh_modules_imports_no_sympy() -> None:
    """Running generated modules that are fresh needs no symbolic algebra: sympy (some 0.4 s
    to import) is the compiler's, and the explanation of a control law that failed."""
    code = (
        "import sys\n"
        "from pathlib import Path\n"
        "from legdsl.pipeline.session import RunSession\n"
        "from legdsl.sim.run_loop import RunOptions\n"
        f"session = RunSession.from_file(Path({str(ROOT / 'creatures' / 'hopper.leg')!r}),"
        f" generated=Path({str(ROOT / 'generated')!r}))\n"
        "session.run('hop', [], options=RunOptions(duration=0.01), backend='python')\n"
        "print(sorted(m for m in sys.modules if m.split('.')[0] in ('sympy', 'jinja2')))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]", out.stdout + out.stderr


def test_no_import_cycles() -> None:
    found = cycles()
    assert not found, "import cycles:\n" + "\n".join(" <-> ".join(c) for c in found)


def test_an_upward_import_is_named_with_both_files(tmp_path: Path) -> None:
    """The check itself: a lexer that imports the runtime is reported with both files."""
    package = tmp_path / "legdsl"
    for stage in ("lang", "sim"):
        (package / stage).mkdir(parents=True)
        (package / stage / "__init__.py").write_text("")
    (package / "__init__.py").write_text("")
    (package / "sim" / "contact.py").write_text("X = 1\n")
    (package / "lang" / "lexer.py").write_text(
        "def f():\n    from legdsl.sim.contact import X\n    return X\n"
    )
    (bad,) = flow_violations(package)
    assert bad.startswith("legdsl/lang/lexer.py:2 imports legdsl.sim.contact:")
    assert "stage 'lang' may not import from the later stage 'sim'" in bad


@pytest.mark.parametrize("first", ["a", "b"])
def test_a_cycle_is_found(tmp_path: Path, first: str) -> None:
    package = tmp_path / "legdsl"
    (package / "check").mkdir(parents=True)
    (package / "__init__.py").write_text("")
    (package / "check" / "__init__.py").write_text("")
    other = "b" if first == "a" else "a"
    (package / "check" / f"{first}.py").write_text(f"from legdsl.check import {other}\n")
    (package / "check" / f"{other}.py").write_text(f"from . import {first}\n")
    assert cycles(package) == [["legdsl.check.a", "legdsl.check.b"]]
