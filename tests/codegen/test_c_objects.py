"""The cache keeps each translation unit's object: a creature's other controller compiles its
``control.c`` alone and links; a creature of sizes built before compiles its own C alone; a
damaged object is compiled again; the trim takes objects too."""

from __future__ import annotations

import ctypes
from pathlib import Path
from typing import Any

import pytest
from runtime_helpers import needs_c_compiler

from legdsl.codegen.c import build, cache

GENERATED = Path(__file__).resolve().parents[2] / "generated"


def compiled_units(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """The units the compiler is started on, as builds go."""
    units: list[str] = []
    start = build._start

    def noted(command: list[str], compiler: build.Compiler, work: str, started: list[Any]) -> Any:
        if "-c" in command:
            units.append(Path(command[-1]).name)
        return start(command, compiler, work, started)

    monkeypatch.setattr(build, "_start", noted)
    return units


@needs_c_compiler
def test_another_controller_of_a_creature_compiles_its_control_alone(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("LEGDSL_CACHE", str(tmp_path))
    units = compiled_units(monkeypatch)
    hop = build.build("hopper", build.sources(GENERATED / "hopper", "hop"))
    assert sorted(units) == sorted(build.UNITS)
    units.clear()
    none = build.build("hopper", build.sources(GENERATED / "hopper"))
    assert units == ["control.c"]
    assert hop.path != none.path and not none.cached
    for library in (hop, none):
        ctypes.CDLL(str(library.path))
    units.clear()  # a library trimmed away: linked again from the objects kept
    hop.path.unlink()
    again = build.build("hopper", build.sources(GENERATED / "hopper", "hop"))
    assert units == [] and again.path == hop.path
    ctypes.CDLL(str(again.path))


@needs_c_compiler
def test_a_creature_of_sizes_built_before_compiles_its_own_units_alone(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The runtime's units include the creature's sizes alone (legdsl_sizes.h): a heavier
    hopper links the hopper's step.c, machine.c and batch.c; the quadruped compiles its own."""
    from legdsl.pipeline.session import RunSession

    heavy = tmp_path / "heavy.leg"
    text = (GENERATED.parent / "creatures" / "hopper.leg").read_text()
    heavy.write_text(text.replace("mass 10 kg", "mass 12 kg", 1))
    RunSession.from_file(heavy, generated=tmp_path / "gen").control("hop")
    monkeypatch.setenv("LEGDSL_CACHE", str(tmp_path / "cache"))
    build.build("hopper", build.sources(GENERATED / "hopper", "hop"))
    units = compiled_units(monkeypatch)
    library = build.build("hopper", build.sources(tmp_path / "gen" / "hopper", "hop"))
    assert sorted(units) == ["control.c", "dynamics.c", "dynamics_some.c"]
    ctypes.CDLL(str(library.path))
    units.clear()
    build.build("quadruped", build.sources(GENERATED / "quadruped"))
    assert sorted(units) == sorted(build.UNITS)


@needs_c_compiler
def test_a_damaged_object_is_compiled_again(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("LEGDSL_CACHE", str(tmp_path))
    files = build.sources(GENERATED / "hopper", "hop")
    first = build.build("hopper", files)
    whole = first.path.read_bytes()
    (kept,) = (tmp_path / cache.OBJECTS).glob("dynamics.c-*.o")
    data = bytearray(kept.read_bytes())
    data[200] ^= 1
    kept.write_bytes(bytes(data))
    first.path.unlink()
    units = compiled_units(monkeypatch)
    again = build.build("hopper", files)
    assert units == ["dynamics.c"]
    assert again.path.read_bytes() == whole  # the same library as the first build
    assert cache.unsealed(kept) is not None  # and the object kept whole again


@needs_c_compiler
def test_another_entrys_object_or_library_copied_over_one_is_built_again(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Each cached object was checked against its own seal alone: the kangaroo's dynamics.c
    object copied over the hopper's (whole, sealed) linked into a hopper library that crashed
    every run (SIGSEGV, exit 139). The seal names the file it was kept as, whose name is the
    hash of what it was built from: another's is compiled again, and so is another library."""
    monkeypatch.setenv("LEGDSL_CACHE", str(tmp_path))
    files = build.sources(GENERATED / "hopper", "hop")
    first = build.build("hopper", files)
    whole = first.path.read_bytes()
    other = build.build("kangaroo", build.sources(GENERATED / "kangaroo", "hop"))
    for unit in ("dynamics.c", "dynamics_some.c"):
        (hoppers,) = [
            kept
            for kept in (tmp_path / cache.OBJECTS).glob(f"{unit}-*.o")
            if kept.name == f"{unit}-{build.unit_key(unit, files, build.find_compiler())}.o"
        ]
        (kangaroos,) = set((tmp_path / cache.OBJECTS).glob(f"{unit}-*.o")) - {hoppers}
        hoppers.write_bytes(kangaroos.read_bytes())
    first.path.unlink()
    units = compiled_units(monkeypatch)
    again = build.build("hopper", files)
    assert sorted(units) == ["dynamics.c", "dynamics_some.c"]
    assert again.path.read_bytes() == whole
    first.path.write_bytes(other.path.read_bytes())  # a library alike
    assert not cache.sealed(first.path)
    assert not build.build("hopper", files).cached and first.path.read_bytes() == whole


@needs_c_compiler
def test_the_trim_takes_the_least_recently_used_objects_too(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("LEGDSL_CACHE", str(tmp_path))
    library = build.build("hopper", build.sources(GENERATED / "hopper", "hop")).path
    cache.trim(tmp_path, keep=library, most=library.stat().st_size)
    assert list((tmp_path / cache.OBJECTS).iterdir()) == [] and library.is_file()


@needs_c_compiler
def test_the_same_creature_printed_from_another_file_reuses_its_objects(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A copy of the file (or the tuned file ``legdsl tune`` writes): its generated C differs in
    the comments that name the file, not in code, so only the controller, whose comments name
    the file throughout, compiles again."""
    from legdsl.pipeline.session import RunSession

    copy = tmp_path / "copy.leg"
    copy.write_text((GENERATED.parent / "creatures" / "hopper.leg").read_text())
    RunSession.from_file(copy, generated=tmp_path / "gen").control("hop")
    monkeypatch.setenv("LEGDSL_CACHE", str(tmp_path / "cache"))
    build.build("hopper", build.sources(GENERATED / "hopper", "hop"))
    units = compiled_units(monkeypatch)
    other = build.build("hopper", build.sources(tmp_path / "gen" / "hopper", "hop"))
    assert units == ["control.c"]
    ctypes.CDLL(str(other.path))
