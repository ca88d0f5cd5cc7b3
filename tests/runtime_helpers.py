"""Helpers for runtime tests: compile a .leg text into a temporary generated tree and simulate it."""

from __future__ import annotations

from pathlib import Path
from types import ModuleType

from legdsl.check.source import check_model
from legdsl.ir.model import Model
from legdsl.pipeline.run import load_dynamics
from legdsl.sim.simulate import RunOptions, RunResult, Simulation

_CACHE: dict[str, tuple[Model, ModuleType]] = {}


def compile_text(text: str, tmp: Path, name: str) -> tuple[Model, ModuleType]:
    """Check and compile ``text`` (cached per text, so a module compiles once per test session)."""
    if text in _CACHE:
        return _CACHE[text]
    tmp.mkdir(parents=True, exist_ok=True)
    source = tmp / f"{name}.leg"
    source.write_text(text)
    model = check_model(source)
    dynamics = load_dynamics(model, source, tmp / "generated")
    _CACHE[text] = (model, dynamics)
    return model, dynamics


def run(model: Model, dynamics: ModuleType, **options: object) -> tuple[Simulation, RunResult]:
    sim = Simulation(model, dynamics, RunOptions(**options))  # type: ignore[arg-type]
    return sim, sim.run()
