"""A C compiler that is missing, is not a compiler, or cannot build: one line that says what to
do, and the Python backend under ``--backend auto``; never a traceback, an exit 70 or a notice
that blames the cache."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from conftest import CREATURES, GENERATED

from legdsl.cli import main
from legdsl.sim import c_library


def _script(tmp_path: Path, name: str, text: str) -> str:
    path = tmp_path / name
    path.write_text("#!/bin/sh\n" + text)
    path.chmod(0o755)
    return str(path)


def _run(tmp_path: Path, backend: str) -> list[str]:
    return ["run", str(CREATURES / "hopper.leg"), "--controller", "hop", "--time", "0.05",
            "--generated", str(GENERATED), "--out", str(tmp_path / "run"),
            "--backend", backend]  # fmt: skip


def _falls_back(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> str:
    """``--backend auto`` runs on, in Python, with the notice: its stderr."""
    assert main(_run(tmp_path, "auto")) == 0
    err = capsys.readouterr().err
    assert "running on the Python backend" in err, err
    return err


@pytest.fixture
def fresh(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    for known in ("_LOADED", "_BY_STAT", "_TRUSTED"):  # as in a new process: nothing loaded yet
        monkeypatch.setattr(c_library, known, {})
    monkeypatch.setenv("LEGDSL_CACHE", str(tmp_path / "cache"))


CASES = {
    "missing": ("/nonexistent/cc", "LEGDSL_CC=/nonexistent/cc: no such program"),
    "options": ("gcc -O0", "LEGDSL_CC=gcc -O0: no such program (name the program alone, "),
    "false": ("/bin/false", "LEGDSL_CC=/bin/false: '/bin/false --version' failed"),
    "true": (
        "/bin/true",
        "/bin/true (LEGDSL_CC) cannot build a C library here (exit 0, no library written)",
    ),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_a_compiler_that_is_not_one_is_named_with_the_fix(
    case: str,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
    fresh: None,
) -> None:
    cc, said = CASES[case]
    if not Path(cc).exists() and case not in ("missing", "options"):
        pytest.skip(f"no {cc} here")
    monkeypatch.setenv("LEGDSL_CC", cc)
    err = _falls_back(tmp_path, capsys)
    assert said in err and "LEGDSL_CC" in err and "cannot build or load the C library in" not in err
    assert main(_run(tmp_path, "c")) == 2
    err = capsys.readouterr().err
    assert said in err and "use --backend python" in err and "Traceback" not in err, err
    assert len(err.strip().splitlines()) == 1


def test_a_compiler_that_fails_is_the_users_to_fix_not_an_internal_error(
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
    fresh: None,
) -> None:
    """It answers --version but builds nothing (a licence server down, a broken wrapper)."""
    cc = _script(
        tmp_path, "cc", '[ "$1" = --version ] && echo "cc 1.0" && exit 0\n'
        'echo "fatal: licence expired" >&2; exit 1\n',
    )  # fmt: skip
    monkeypatch.setenv("LEGDSL_CC", cc)
    err = _falls_back(tmp_path, capsys)
    assert f"{cc} (LEGDSL_CC) cannot build a C library here (fatal: licence expired)" in err, err
    assert main(_run(tmp_path, "c")) == 2
    err = capsys.readouterr().err
    assert "fatal: licence expired" in err and "Traceback" not in err, err
    assert [p.name for p in (tmp_path / "cache").iterdir()] == []  # no leftover probe or sources


@pytest.mark.skipif(shutil.which("gcc") is None, reason="needs gcc")
def test_a_compiler_without_its_headers_is_told_to_install_them(
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
    fresh: None,
) -> None:
    cc = _script(tmp_path, "cc", 'exec gcc -nostdinc "$@"\n')
    monkeypatch.setenv("LEGDSL_CC", cc)
    assert main(_run(tmp_path, "c")) == 2
    err = capsys.readouterr().err
    assert f"{cc} (LEGDSL_CC) cannot build a C library here (probe.c:1:" in err, err
    assert "libc6-dev" in err and "Traceback" not in err


@pytest.mark.skipif(shutil.which("g++") is None, reason="needs g++")
def test_a_cpp_driver_compiles_the_library_as_c(
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
    fresh: None,
) -> None:
    """g++ took the .c files for C++: mangled names, and an internal error on load."""
    monkeypatch.setenv("LEGDSL_CC", "g++")
    assert main(_run(tmp_path, "c")) == 0, capsys.readouterr().err


@pytest.mark.skipif(shutil.which("gcc") is None, reason="needs gcc")
def test_a_library_without_legdsls_symbols_is_refused_and_removed(
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
    fresh: None,
) -> None:
    import subprocess

    from legdsl.codegen.c.build import Built

    (tmp_path / "other.c").write_text("int something_else(void) { return 1; }\n")
    other = tmp_path / "cache" / "other.so"
    other.parent.mkdir()
    subprocess.run(
        ["gcc", "-shared", "-fPIC", "-o", str(other), str(tmp_path / "other.c")], check=True
    )
    monkeypatch.setattr(c_library, "build", lambda name, files, **told: Built(other, True, 0.0))
    assert main(_run(tmp_path, "c")) == 2
    err = capsys.readouterr().err
    assert "lacks legdsl's symbols" in err and "set LEGDSL_CC to a C compiler" in err, err
    assert "internal error" not in err and not other.exists()


def test_trimming_skips_what_it_cannot_remove(tmp_path: Path) -> None:
    """A shared cache holds other users' libraries: one that cannot be removed is left, and
    the build that trims does not fail for it (else its run fell back to Python)."""
    import os

    from legdsl.codegen.c.cache import trim

    (tmp_path / "stuck.so").mkdir()  # unlink() refuses it, as it refuses another's file
    (tmp_path / "stuck.so" / "x").write_bytes(b"x" * 3000)
    for k, name in enumerate(["old.so", "keep.so"]):
        (tmp_path / name).write_bytes(b"x" * 1000)
        os.utime(tmp_path / name, (1000 + k, 1000 + k))
    os.utime(tmp_path / "stuck.so", (0, 0))  # the least recently used
    trim(tmp_path, keep=tmp_path / "keep.so", most=10)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["keep.so", "stuck.so"]


@pytest.mark.skipif(shutil.which("gcc") is None, reason="needs gcc")
def test_a_compiler_killed_out_of_memory_is_not_an_internal_error(
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
    fresh: None,
) -> None:
    """The probe's tiny library builds; the big dynamics.c is what the kernel kills."""
    cc = _script(
        tmp_path, "cc", 'for a in "$@"; do case "$a" in *dynamics.c) kill -9 $$;; esac; done\n'
        'exec gcc "$@"\n',
    )  # fmt: skip
    monkeypatch.setenv("LEGDSL_CC", cc)
    err = _falls_back(tmp_path, capsys)
    assert f"{cc} was killed (SIGKILL) building the C of hopper-hop, most likely out" in err, err


@pytest.mark.skipif(shutil.which("gcc") is None, reason="needs gcc")
def test_a_compiler_short_of_memory_is_told_as_a_limit(
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
    fresh: None,
) -> None:
    """cc1 out of memory (ulimit -v), or killed by SIGXFSZ (ulimit -f): it was "the C compiler
    refused the C legdsl generated ... (a bug in legdsl)", and exit 70 with --backend c."""
    cc = _script(
        tmp_path, "cc", 'for a in "$@"; do case "$a" in *dynamics.c) ulimit -v 30000;; esac; done\n'
        'exec gcc "$@"\n',
    )  # fmt: skip
    monkeypatch.setenv("LEGDSL_CC", cc)
    err = _falls_back(tmp_path, capsys)
    assert f"{cc} died building the C of hopper-hop (" in err, err  # what cc1 said of it
    assert "(ulimit -f) or memory (ulimit -v)" in err and "bug" not in err


@pytest.mark.skipif(shutil.which("gcc") is None, reason="needs gcc")
def test_objects_a_broken_compiler_wrote_are_not_kept(
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
    fresh: None,
) -> None:
    """A wrapper that once wrote garbage objects with exit 0: they were kept, and every build
    after the compiler was mended linked them again and blamed legdsl, for good."""
    broken = tmp_path / "BROKEN"
    cc = _script(
        tmp_path, "cc", f'if [ -f {broken} ]; then for a in "$@"; do case "$a" in *dynamics.c)\n'
        '  for o in "$@"; do case "$o" in *.o) head -c 3000 /dev/urandom > "$o";; esac; done\n'
        '  exit 0;; esac; done; fi\nexec gcc "$@"\n',
    )  # fmt: skip
    monkeypatch.setenv("LEGDSL_CC", cc)
    broken.touch()
    _falls_back(tmp_path, capsys)
    broken.unlink()  # mended
    for known in ("_LOADED", "_BY_STAT", "_TRUSTED"):
        monkeypatch.setattr(c_library, known, {})
    assert main(_run(tmp_path, "c")) == 0, capsys.readouterr().err


def test_a_cache_given_with_a_tilde_is_in_the_home_directory(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """LEGDSL_CACHE=~/x from a settings file no shell expanded: not a folder '~' here."""
    from legdsl.files import cache_dir

    monkeypatch.setenv("HOME", str(tmp_path))
    monkeypatch.setenv("LEGDSL_CACHE", "~/legdsl-cache")
    assert cache_dir() == tmp_path / "legdsl-cache"
    monkeypatch.delenv("LEGDSL_CACHE")
    monkeypatch.setenv("XDG_CACHE_HOME", "~/.cache")
    assert cache_dir() == tmp_path / ".cache" / "legdsl"


def test_a_relative_xdg_cache_home_is_ignored(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """XDG_CACHE_HOME=relx made a cache in each directory a command ran in (./relx/legdsl/):
    the XDG spec says a relative path is to be ignored."""
    from legdsl.files import cache_dir

    monkeypatch.setenv("HOME", str(tmp_path))
    monkeypatch.delenv("LEGDSL_CACHE", raising=False)
    for relative in ("relx", "./relx", "relx/a"):
        monkeypatch.setenv("XDG_CACHE_HOME", relative)
        assert cache_dir() == tmp_path / ".cache" / "legdsl"
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert cache_dir() == tmp_path / "xdg" / "legdsl"


def test_with_no_home_the_run_says_where_to_keep_the_library(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str], fresh: None
) -> None:
    """No HOME and a user the system does not know (a container's bare uid): ``Path.home()``
    raises RuntimeError, which was "internal error (RuntimeError: Could not determine home
    directory.)". Now ``auto`` runs in Python with the notice and ``c`` says what to set."""

    def no_home() -> Path:
        raise RuntimeError("Could not determine home directory.")

    monkeypatch.delenv("LEGDSL_CACHE")
    monkeypatch.delenv("XDG_CACHE_HOME", raising=False)
    monkeypatch.setattr(Path, "home", staticmethod(no_home))
    err = _falls_back(tmp_path, capsys)
    assert "no cache directory: HOME is not set and this user has no home directory" in err, err
    assert main(_run(tmp_path, "c")) == 2
    err = capsys.readouterr().err
    assert "set LEGDSL_CACHE (or HOME) to a directory you can write, or use --backend python" in err


def test_the_sources_of_a_killed_build_are_removed_in_time(tmp_path: Path) -> None:
    import os

    from legdsl.codegen.c.cache import LEFTOVER_SECONDS, trim

    for name in (".hopper-src-abc", ".probe-xyz", ".kangaroo-src-new"):
        (tmp_path / name).mkdir()
        (tmp_path / name / "dynamics.c").write_text("/* ... */")
    old = os.stat(tmp_path).st_mtime - LEFTOVER_SECONDS - 60
    for name in (".hopper-src-abc", ".probe-xyz"):
        os.utime(tmp_path / name, (old, old))
    (tmp_path / "keep.so").write_bytes(b"x")
    trim(tmp_path, keep=tmp_path / "keep.so")
    assert sorted(p.name for p in tmp_path.iterdir()) == [".kangaroo-src-new", "keep.so"]


def _edit(generated: Path, file: str, old: str, new: str) -> None:
    """Edit a generated file by hand, and its checksum with it (so no compile is triggered)."""
    import hashlib

    path = generated / file
    path.write_text(path.read_text().replace(old, new, 1))
    sums = generated / "SHA256SUMS"
    digest = hashlib.sha256(path.read_bytes()).hexdigest()
    sums.write_text("".join(
        f"{digest}  {file}\n" if line.endswith(f"  {file}") else line + "\n"
        for line in sums.read_text().splitlines()
    ))  # fmt: skip


@pytest.mark.parametrize(
    ("new", "said"),
    [("return @(", "error: stray '@' in program"), ("retrun (", "undefined symbol: retrun")],
)
def test_generated_c_edited_by_hand_that_cannot_build_is_the_users_to_fix(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], fresh: None, new: str, said: str
) -> None:
    if c_library.available() is not None:
        pytest.skip(f"needs a C compiler: {c_library.available()}")
    generated = tmp_path / "gen"
    shutil.copytree(GENERATED / "hopper", generated / "hopper")
    _edit(generated / "hopper", "control_hop.c", "return (", new)
    argv = _run(tmp_path, "c")
    argv[argv.index("--generated") + 1] = str(generated)
    assert main(argv) == 2
    err = capsys.readouterr().err.replace("\u2018", "'").replace("\u2019", "'")
    assert (
        f"legdsl: the C library cannot be built from {generated}/hopper/control_hop.c, which "
        f"differs from what legdsl generates from {CREATURES / 'hopper.leg'} (edited by hand?): "
    ) in err, err
    assert said in err and err.rstrip().endswith(
        f"; run 'legdsl compile {CREATURES / 'hopper.leg'} -o {generated}' to write it again"
    )
    if "error:" in said:  # located in the file edited, not in the build's deleted copy control.c
        assert f"(edited by hand?): {generated}/hopper/control_hop.c:" in err, err


def test_the_api_is_warned_when_the_python_backend_runs_in_cs_place(
    monkeypatch: pytest.MonkeyPatch, fresh: None
) -> None:
    """The API's caller, who has no stderr notice, was given the Python backend without a word
    (a run tens of times slower)."""
    import legdsl.api as api

    monkeypatch.setenv("LEGDSL_CC", "/nonexistent/cc")
    hopper = api.load(CREATURES / "hopper.leg", generated=GENERATED)
    with pytest.warns(api.LegdslWarning, match="no such program.*: running on the Python backend"):
        run = hopper.run(controller="hop", time=0.05)
    assert run.status == "ok"


@pytest.mark.skipif(shutil.which("gcc") is None, reason="needs gcc")
def test_legdsls_own_c_refused_runs_on_in_python_and_is_one_line_with_backend_c(
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
    fresh: None,
) -> None:
    """A compiler that builds the probe but refuses the generated C (a bug of legdsl's C, or
    of that compiler): ``auto`` ran nothing ("internal error" with the compiler's whole
    output); now it runs in Python with the compiler's error as its notice, and ``--backend
    c`` stops with that one line (exit 70)."""
    cc = _script(
        tmp_path, "cc", 'for a in "$@"; do case "$a" in *dynamics.c) '
        'echo "dynamics.c:7:3: error: no such thing as this" >&2; exit 1;; esac; done\n'
        'exec gcc "$@"\n',
    )  # fmt: skip
    monkeypatch.setenv("LEGDSL_CC", cc)
    err = _falls_back(tmp_path, capsys)
    said = "dynamics.c:7:3: error: no such thing as this"
    assert f"the C compiler refused the C legdsl generated in {GENERATED / 'hopper'}: {said}" in err
    assert "(a bug in legdsl; please report it): running on the Python backend" in err, err
    assert main(_run(tmp_path, "c")) == 70
    err = capsys.readouterr().err
    assert said in err and "Traceback" not in err and len(err.strip().splitlines()) == 1, err


@pytest.mark.skipif(shutil.which("gcc") is None, reason="needs gcc")
def test_a_library_under_another_controllers_name_is_built_again(tmp_path: Path) -> None:
    """The pace's library copied over the trot's in the cache (a mix-up, its seal whole) was
    loaded by its name: a 'trot' run that was neither, exit 0. Its stamps are checked now.
    (Each run a process of its own: a process's loader keeps what it loaded by name.)"""
    import os
    import subprocess
    import sys

    env = {**os.environ, "LEGDSL_CACHE": str(tmp_path / "cache")}

    def run(controller: str, out: str) -> bytes:
        argv = ["run", str(CREATURES / "quadruped.leg"), "--controller", controller, "--time",
                "0.1", "--backend", "c", "--generated", str(GENERATED), "--out", str(tmp_path / out)]  # fmt: skip
        done = subprocess.run([sys.executable, "-m", "legdsl", *argv], env=env, capture_output=True)
        assert done.returncode == 0, done.stderr
        return (tmp_path / out / "trajectory.npz").read_bytes()

    trot = run("trot", "trot")
    run("pace", "pace")
    (trot_lib,) = (tmp_path / "cache").glob("quadruped-trot-*.so")
    (pace_lib,) = (tmp_path / "cache").glob("quadruped-pace-*.so")
    shutil.copy(pace_lib, trot_lib)
    assert run("trot", "again") == trot


def test_no_compiler_found_says_why_each_was_passed_over(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A cc on the PATH that always fails was "no C compiler found", as if there were none."""
    from legdsl.codegen.c import build

    _script(tmp_path, "cc", "exit 1\n")
    monkeypatch.setenv("PATH", str(tmp_path))
    monkeypatch.delenv("LEGDSL_CC", raising=False)
    build._compiler.cache_clear()
    try:
        said = build.no_compiler()
    finally:
        build._compiler.cache_clear()
    assert said == (f"no C compiler found (cc, gcc or clang; or set LEGDSL_CC): "
                    f"'{tmp_path / 'cc'} --version' failed (exit 1)")  # fmt: skip


def test_a_cache_that_may_not_run_programs_is_told_so(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A cache on a noexec mount was told only as the loader's "failed to map segment"."""
    from legdsl.pipeline.backend import _cache_fix

    monkeypatch.setenv("LEGDSL_CACHE", str(tmp_path))
    refused = OSError(f"{tmp_path}/x.so: failed to map segment from shared object")
    assert _cache_fix(refused).startswith("its file system may not run programs (mounted noexec?)")


@pytest.mark.skipif(shutil.which("gcc") is None, reason="needs gcc")
def test_with_no_path_the_compiler_found_on_the_default_one_finds_its_linker_there(
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
    fresh: None,
) -> None:
    """``env -u PATH legdsl run`` (cron, env={}): legdsl found /bin/cc on the default search
    path, ran it with no PATH, and gcc found no 'ld': "install a C compiler", said of gcc."""
    monkeypatch.delenv("PATH")
    assert main(_run(tmp_path, "c")) == 0
    err = capsys.readouterr().err
    assert "legdsl: built " in err and "cannot build" not in err, err


@pytest.mark.skipif(shutil.which("gcc") is None, reason="needs gcc")
def test_a_compiler_without_its_assembler_on_path_is_told_that_not_to_install_one(
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
    fresh: None,
) -> None:
    alone = tmp_path / "bin"  # gcc, and not the 'as' and 'ld' it runs from PATH
    alone.mkdir()
    (alone / "cc").symlink_to(str(shutil.which("gcc")))
    monkeypatch.setenv("PATH", str(alone))
    monkeypatch.setenv("LEGDSL_CC", str(alone / "cc"))
    assert main(_run(tmp_path, "c")) == 2
    err = capsys.readouterr().err
    assert f"; put the folder of 'as' (binutils) on PATH, which is {alone}; " in err, err
    assert "install" not in err
