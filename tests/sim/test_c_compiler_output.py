"""What a C compiler writes, and what legdsl believes of it: a library cut short (a SIGBUS on
load, sealed in the cache for good), garbage, chatter on its standard output, a compiler run
on every cached run, a directory or a file without execute permission as LEGDSL_CC."""

from __future__ import annotations

import os
import shutil
import signal
from pathlib import Path

import pytest
from conftest import GENERATED

from legdsl.codegen.c import build, compiler
from legdsl.codegen.c.cache import elf_problem, seal, unsealed

needs_cc = pytest.mark.skipif(build.find_compiler() is None, reason="no C compiler")


def _wrapper(tmp_path: Path, name: str, after: str, before: str = "") -> str:
    """A compiler that runs the real one, then does ``after`` to its ``-o`` output."""
    real = shutil.which("cc") or shutil.which("gcc")
    path = tmp_path / name
    path.write_text(
        "#!/bin/bash\n" + before + 'out=""; prev=""\n'
        'for a in "$@"; do [ "$prev" = "-o" ] && out="$a"; prev="$a"; done\n'
        f'[ "$1" = "--version" ] && exec {real} "$@"\n'
        f'{real} "$@" || exit $?\n' + after + "\nexit 0\n"
    )
    path.chmod(0o755)
    return str(path)


@pytest.fixture
def fresh(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("LEGDSL_CACHE", str(tmp_path / "cache"))
    build._compiler.cache_clear()
    build.native.cache_clear()
    yield
    build._compiler.cache_clear()
    build.native.cache_clear()


@needs_cc
def test_a_library_cut_short_is_the_compilers_failure_and_never_sealed(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, fresh: None
) -> None:
    """A compiler (a wrapper, a full disk it says nothing of) that left a library of 3000
    bytes: sealed as it was, loading it was a SIGBUS in this and every later run."""
    cut = 'if [[ "$*" == *-shared* ]]; then truncate -s 3000 "$out"; fi'
    monkeypatch.setenv("LEGDSL_CC", _wrapper(tmp_path, "cut_cc", cut))
    files = build.sources(GENERATED / "hopper", "hop")
    with pytest.raises(build.CompilerUnusable) as told:
        build.build("hopper", files)
    said = str(told.value)
    assert "(LEGDSL_CC) wrote no loadable library for hopper (cut short: 3000 bytes" in said, said
    assert "set LEGDSL_CC to a working C compiler" in said, said
    assert not list((tmp_path / "cache").glob("*.so"))


@needs_cc
def test_a_sealed_library_cut_short_in_the_cache_is_built_again(
    tmp_path: Path, fresh: None
) -> None:
    files = build.sources(GENERATED / "hopper", "hop")
    whole = build.build("hopper", files).path
    assert elf_problem(whole.read_bytes()) is None
    data = whole.read_bytes()
    whole.write_bytes(data[:3000])
    seal(whole)  # what an older legdsl kept: the seal of whatever the compiler wrote
    assert "cut short: 3000 bytes" in str(elf_problem(data[:3000]))
    again = build.build("hopper", files)
    assert not again.cached and again.path == whole
    assert elf_problem(unsealed(whole) or b"") is None


def test_elf_problem_reads_the_headers_not_just_the_magic() -> None:
    assert elf_problem(b"\x7fELF") == "not an ELF file"
    assert elf_problem(os.urandom(5000)) == "not an ELF file"
    assert elf_problem(b"\x7fELF\x02\x01\x01" + bytes(20)) is not None


@needs_cc
def test_the_compilers_chatter_is_not_the_runs_output(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capfd: pytest.CaptureFixture[str], fresh: None
) -> None:
    """A wrapper's 'compiling...' on its standard output landed in the run's summary (and,
    piped to head, the wrapper died of SIGPIPE, blamed on ulimits)."""
    chatty = _wrapper(tmp_path, "chatty_cc", "", before='echo "chatty: compiling"\n')
    monkeypatch.setenv("LEGDSL_CC", chatty)
    build.build("hopper", build.sources(GENERATED / "hopper", "hop"))
    out = capfd.readouterr().out
    assert "chatty" not in out, out
    fails = '[[ " $* " == *" -c "* ]] && { echo "chatty: no"; exit 1; }'  # the probe builds
    refusing = _wrapper(tmp_path, "refusing_cc", fails)
    monkeypatch.setenv("LEGDSL_CC", refusing)
    build._compiler.cache_clear()
    with pytest.raises(build.BuildFailed) as told:
        build.build("hopper", build.sources(GENERATED / "hopper", "hop"))
    assert "chatty: no" in str(told.value)
    assert "chatty" not in capfd.readouterr().out


def test_sigpipe_is_not_blamed_on_a_limit(tmp_path: Path) -> None:
    cc = build.Compiler("/usr/bin/cc", "cc 1")
    with pytest.raises(build.CompilerUnusable) as told:
        build._check(-signal.SIGPIPE, ["cc"], "", "hopper", cc)
    assert "SIGPIPE" in str(told.value) and "ulimit" not in str(told.value)


def test_a_directory_or_a_file_not_executable_is_said_so(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, fresh: None
) -> None:
    plain = tmp_path / "noexec_cc"
    plain.write_text('#!/bin/sh\nexec gcc "$@"\n')
    plain.chmod(0o644)
    for given, said in ((tmp_path, "a directory, not a program"), (plain, "not executable")):
        monkeypatch.setenv("LEGDSL_CC", str(given))
        build._compiler.cache_clear()
        told = build.no_compiler()
        assert told is not None and f"LEGDSL_CC={given}: {said}" in told, told
        assert "no such program" not in told


@needs_cc
def test_garbage_is_no_loadable_library_of_the_legdsl_cc_set(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, fresh: None
) -> None:
    garbage = _wrapper(
        tmp_path, "garbage_cc", '[ -n "$out" ] && head -c 5000 /dev/urandom > "$out"'
    )
    monkeypatch.setenv("LEGDSL_CC", garbage)
    (tmp_path / "cache").mkdir()
    said = build.probe(build.find_compiler(), tmp_path / "cache")  # type: ignore[arg-type]
    assert said is not None and "(exit 0, no loadable library written)" in said, said
    assert f"{garbage} (LEGDSL_CC)" in said and "libc6-dev" not in said, said


@needs_cc
def test_a_cached_run_runs_no_compiler_until_the_compiler_changes(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, fresh: None
) -> None:
    """``cc --version`` and ``cc -march=native -dM -E`` ran in every new process, a library
    cached or not: their answers are kept in the cache under the compiler's identity."""
    monkeypatch.delenv("LEGDSL_CC", raising=False)
    first = build.find_compiler()
    assert first is not None and first.identity
    answers = (first.version, build.native(first))
    ran: list[list[str]] = []
    real = compiler._probe_run

    def noted(command: list[str], *args: object, **kw: object) -> object:
        ran.append(command)
        return real(command, *args, **kw)  # type: ignore[arg-type]

    monkeypatch.setattr(compiler, "_probe_run", noted)
    build._compiler.cache_clear()  # a new process
    build.native.cache_clear()
    again = build.find_compiler()
    assert again is not None and (again.version, build.native(again)) == answers
    assert ran == []
    build._compiler.cache_clear()  # the compiler replaced (upgraded): asked again
    build.native.cache_clear()
    monkeypatch.setattr(compiler, "_identity", lambda path: first.identity + "-upgraded")
    build.native(build.find_compiler())  # type: ignore[arg-type]
    assert [command[1] for command in ran] == ["--version", "-march=native"]


def test_a_compilers_identity_changes_with_its_file(tmp_path: Path) -> None:
    program = tmp_path / "cc"
    program.write_bytes(b"\x7fELF" + bytes(100))
    one = compiler._identity(str(program))
    os.utime(program, ns=(1, 1))
    assert one and compiler._identity(str(program)) not in ("", one)
    program.write_bytes(b"#!/bin/sh\nexec gcc\n")  # a script may run any compiler: not kept
    assert compiler._identity(str(program)) == ""


@needs_cc
def test_deleting_the_cache_directory_is_safe(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, fresh: None
) -> None:
    """docs/runtime.md says the cache may be deleted: all in it is built again when needed."""
    monkeypatch.delenv("LEGDSL_CC", raising=False)
    files = build.sources(GENERATED / "hopper", "hop")
    first = build.build("hopper", files)
    assert (tmp_path / "cache" / "compilers").is_dir()
    shutil.rmtree(tmp_path / "cache")
    build._compiler.cache_clear()  # a new process
    build.native.cache_clear()
    again = build.build("hopper", files)
    assert not again.cached and again.path == first.path and again.path.is_file()
    assert (tmp_path / "cache" / "compilers").is_dir()
    assert build.build("hopper", files).cached
