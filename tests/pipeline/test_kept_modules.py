"""Generated modules kept in legdsl's cache (legdsl.codegen.kept): a creature compiled once is
copied, byte for byte, wherever its modules are missing; anything a compile prints from that
changed (the file, its path, legdsl's own code) compiles again; a damaged entry or a cache that
cannot be written only compiles."""

from __future__ import annotations

import io
import os
import shutil
import zlib
from pathlib import Path

import pytest
from conftest import CREATURES, GENERATED
from runtime_helpers import COPIED

from legdsl.codegen import kept
from legdsl.codegen.c import cache
from legdsl.pipeline import generated as generated_modules
from legdsl.pipeline.session import RunSession


@pytest.fixture
def own_cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """An empty cache of this test's own (the session's is shared by every test)."""
    folder = tmp_path / "cache"
    monkeypatch.setenv("LEGDSL_CACHE", str(folder))
    return folder


@pytest.fixture
def hopper(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """The shipped hopper copied into a folder of its own, which is the working directory
    (so the generated headers name it ``hopper.leg``, as they would the shipped one's)."""
    folder = tmp_path / "work"
    folder.mkdir()
    shutil.copy(CREATURES / "hopper.leg", folder / "hopper.leg")
    monkeypatch.chdir(folder)
    return folder / "hopper.leg"


def _load(source: Path, folder: Path) -> str:
    """Load ``source``'s modules into ``folder`` (writing them); what the load said."""
    log = io.StringIO()
    RunSession.from_file(source, generated=folder, log=log).control("hop")
    return log.getvalue()


def _tree(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())}


def _no_compiles(monkeypatch: pytest.MonkeyPatch) -> None:
    def refused(*args: object, **kwargs: object) -> None:
        raise AssertionError("compiled, though the cache holds the modules")

    monkeypatch.setattr(generated_modules, "_compiled", refused)


def test_a_creature_compiled_once_is_copied_byte_for_byte(
    own_cache: Path, hopper: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    said = _load(hopper, tmp_path / "first")
    assert "dynamics.py is missing; compiling" in said and COPIED not in said
    assert len(list((own_cache / cache.MODULES).glob("*.z"))) == 1
    _no_compiles(monkeypatch)
    said = _load(hopper, tmp_path / "second")
    assert f"dynamics.py is missing; {hopper} {COPIED}" in said
    assert _tree(tmp_path / "second" / "hopper") == _tree(tmp_path / "first" / "hopper")
    # the golden files, which name creatures/hopper.leg where these name hopper.leg
    for name, text in _tree(tmp_path / "second" / "hopper").items():
        shipped = (GENERATED / "hopper" / name).read_bytes()
        if name != "SHA256SUMS":
            assert text == shipped.replace(b"creatures/hopper.leg", b"hopper.leg"), name


def test_what_a_compile_prints_from_names_the_entry(
    own_cache: Path, hopper: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    _load(hopper, tmp_path / "first")
    # a line more at the top: the same dynamics, but every comment naming a line is another
    hopper.write_text("# a comment\n" + hopper.read_text())
    assert "; compiling" in _load(hopper, tmp_path / "moved")
    # another path in the headers
    other = hopper.with_name("other.leg")
    shutil.copy(hopper, other)
    assert "; compiling" in _load(other, tmp_path / "renamed")
    # another legdsl: its own files hash differently
    monkeypatch.setattr(kept, "_compiler", lambda: "another compiler")
    assert "; compiling" in _load(hopper, tmp_path / "edited legdsl")
    assert len(list((own_cache / cache.MODULES).glob("*.z"))) == 4
    moved = (tmp_path / "moved" / "hopper" / "control_hop.c").read_text()
    assert moved != (tmp_path / "first" / "hopper" / "control_hop.c").read_text()


@pytest.mark.parametrize(
    "damage", ["cut short", "a byte changed", "sealed but not an entry", "sealed, not files"]
)
def test_a_damaged_entry_is_compiled_again_and_kept_whole(
    damage: str, own_cache: Path, hopper: Path, tmp_path: Path
) -> None:
    _load(hopper, tmp_path / "first")
    (entry,) = (own_cache / cache.MODULES).glob("*.z")
    whole = entry.read_bytes()
    if damage == "cut short":
        entry.write_bytes(whole[: len(whole) // 2])
    elif damage == "a byte changed":
        entry.write_bytes(whole[:100] + bytes([whole[100] ^ 1]) + whole[101:])
    elif damage == "sealed but not an entry":
        entry.write_bytes(b"not compressed")
        cache.seal(entry)
    else:
        entry.write_bytes(zlib.compress(b'[["dynamics.py", 42], 7]'))
        cache.seal(entry)
    assert "; compiling" in _load(hopper, tmp_path / "second")
    assert entry.read_bytes() == whole
    assert _tree(tmp_path / "second" / "hopper") == _tree(tmp_path / "first" / "hopper")


def test_another_creatures_modules_in_an_entry_are_compiled_anew(
    own_cache: Path, hopper: Path, tmp_path: Path
) -> None:
    """An entry holding another creature's modules, sealed (copied over by hand, a mix-up): they
    were copied in at every run, found stale, and the run ended in an internal error."""
    _load(hopper, tmp_path / "first")
    (entry,) = (own_cache / cache.MODULES).glob("*.z")
    whole = entry.read_bytes()
    shutil.copy(CREATURES / "kangaroo.leg", hopper.with_name("kangaroo.leg"))
    _load(hopper.with_name("kangaroo.leg"), tmp_path / "roo")
    (other,) = set((own_cache / cache.MODULES).glob("*.z")) - {entry}
    shutil.copy(other, entry)  # the kangaroo's, sealed, under the hopper's key
    assert "; compiling" in _load(hopper, tmp_path / "second")
    assert entry.read_bytes() == whole  # kept anew, the hopper's own
    assert _tree(tmp_path / "second" / "hopper") == _tree(tmp_path / "first" / "hopper")


def test_a_cache_in_a_file_only_compiles(
    tmp_path: Path, hopper: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """LEGDSL_CACHE naming a file: every write there fails, and the modules are compiled."""
    blocker = tmp_path / "a file"
    blocker.write_text("")
    monkeypatch.setenv("LEGDSL_CACHE", str(blocker))
    assert "; compiling" in _load(hopper, tmp_path / "first")
    assert "; compiling" in _load(hopper, tmp_path / "second")
    assert _tree(tmp_path / "second" / "hopper") == _tree(tmp_path / "first" / "hopper")


def test_kept_modules_are_trimmed_least_recently_used_first(
    own_cache: Path, hopper: Path, tmp_path: Path
) -> None:
    _load(hopper, tmp_path / "first")
    (entry,) = (own_cache / cache.MODULES).glob("*.z")
    older = entry.with_name("0" * 64 + ".json.z")
    shutil.copy(entry, older)
    os.utime(older, (1, 1))
    leftover = entry.with_name(".killed.new-1-ab.z")
    leftover.write_bytes(b"half")
    os.utime(leftover, (1, 1))
    cache.trim(own_cache, keep=entry, most=entry.stat().st_size)
    assert sorted(p.name for p in entry.parent.iterdir()) == [entry.name]
