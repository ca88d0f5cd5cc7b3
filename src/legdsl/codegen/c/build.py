"""Build the C of a creature into a shared library, cached, and say where it is.

The library of a creature is its ``generated/NAME/dynamics.c`` and ``dynamics.h`` compiled
with the runtime in ``runtime/`` (``step.c``: actuators, ground, integrators, the run loop;
``batch.c``: many copies of a run; ``legdsl_math.h``), each translation unit in a compiler
process of its own, all at once, then linked, by the system C compiler, found at run time:
``$LEGDSL_CC`` if set, else the first of ``cc``, ``gcc``, ``clang`` on the PATH.

Flags: ``-O3 -std=c99 -fno-fast-math -ffp-contract=off -fno-tree-vectorize
-fno-semantic-interposition -fPIC -shared``, and ``-march=native`` where the compiler takes it.
``-ffp-contract=off`` keeps gcc and clang from fusing ``a*b + c`` into one rounding (an FMA),
and no fast-math keeps them from reassociating sums or replacing divisions: then each printed
operation is one IEEE double operation, in the order the Python print gives, and the results
equal Python's bit for bit (x86-64 and arm64 compute doubles in SSE/NEON registers, without
x87's wider ones). ``-fno-tree-vectorize``: gcc 12's straight-line vectorizer pairs a
multiplication with an add-and-subtract into ``vfmaddsub`` where the machine has FMA (with
``-mfma`` or ``-march=native``), a fused rounding in spite of ``-ffp-contract=off`` that changed
the biped's dynamics; without it the runs stay identical with any ``-march``, for a few percent.
``-march=native`` and ``-O3`` give the same doubles (no operation is fused, reordered or
vectorized) about 9% sooner (docs/runtime.md); a library built for one processor may not run
on another, so the key of the cache names the processor features ``-march=native`` turns on.

The compiler found must build a tiny library when a build fails (``probe``): one that cannot
(not a compiler, no headers) is the user's to fix (``CompilerUnusable``), else the C is legdsl's.

The cache that keeps the libraries and objects (where it is, the seal, the trim): ``cache.py``;
the hashes it keeps them under: ``library_key`` and ``unit_key`` here. The runtime's units
(``step.c``, ``machine.c``, ``batch.c``) include the creature's sizes alone (``legdsl_sizes.h``,
``sizes_header``), so a creature of sizes built before compiles only its own C.
"""

from __future__ import annotations

import contextlib
import errno
import hashlib
import os
import re
import shutil
import signal
import subprocess
import tempfile
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any

from legdsl.codegen.c.cache import (
    OBJECTS,
    keep_object,
    reuse_object,
    seal,
    sealed,
    trim,
)
from legdsl.files import cache_dir
from legdsl.signals import signals_held

RUNTIME = Path(__file__).parent / "runtime"
RUNTIME_FILES = (
    "legdsl_math.h",
    "legdsl_sim.h",
    "legdsl_control.h",
    "legdsl_model.h",
    "step.c",
    "machine.c",
    "batch.c",
    "control_none.c",
)
FLAGS = (
    "-O3",
    "-std=c99",
    "-fno-fast-math",
    "-ffp-contract=off",
    "-fno-tree-vectorize",
    "-fno-semantic-interposition",
    "-fPIC",
    "-shared",
)
LIBS = ("-lm",)
# A unit longer than this (a creature of 60 or more links) compiles at -O1: gcc -O3 took 200 s
# and 1.5 GB on the 2 MB dynamics.c of an 82-DOF chain; the doubles are the same at any -O
# (nothing is fused or reordered without fast-math), the step a little slower.
LARGE_UNIT = 1_000_000
LANGUAGE = ("-x", "c")  # C even to a C++ driver (LEGDSL_CC=g++), whose symbols would be mangled
SIZES_FILE = "legdsl_sizes.h"  # written at each build from dynamics.h: sizes_header
SIZES = ("LEG_NQ", "LEG_NV", "LEG_NB", "LEG_NC", "LEG_FREE3D", "LEG_PLANAR")
SIZE_LINE = re.compile(r"^#define (LEG_[A-Z0-9]+) \d+\b.*$", re.MULTILINE)
INCLUDE = re.compile(r'^[ \t]*#[ \t]*include[ \t]*"([^"]+)"', re.MULTILINE)  # a local header
DYNAMICS_FILES = ("dynamics.c", "dynamics_some.c", "dynamics.h")  # generated per creature
# a library's translation units
UNITS = ("dynamics.c", "dynamics_some.c", "step.c", "machine.c", "batch.c", "control.c")


class NoCompiler(Exception):
    """No C compiler was found (the Python backend runs instead)."""


class BuildFailed(Exception):
    """The C compiler refused the generated code (a legdsl bug: the message has its output)."""


class CompilerUnusable(Exception):
    """The compiler found cannot build even a tiny library (not a C compiler, or one without
    its headers): the user's environment, not legdsl's code; the message says what to do."""


@dataclass(frozen=True)
class Compiler:
    path: str
    version: str  # the first line of ``--version``


@dataclass(frozen=True)
class Built:
    path: Path  # the shared library
    cached: bool  # reused from the cache (no compiler run)
    seconds: float  # time spent in the compiler (0 when cached)


# why each compiler was passed over, said if none is found (a failing cc was just "none found")
_PASSED_OVER: dict[str, str] = {}


@lru_cache(maxsize=8)
def _compiler(wanted: str | None) -> Compiler | None:
    names = [wanted] if wanted else ["cc", "gcc", "clang"]
    for name in names:
        path = shutil.which(name)
        if path is None:
            continue
        try:
            done = _probe_run([path, "--version"], timeout=10)
            if done.returncode != 0:
                _PASSED_OVER[name] = f"'{path} --version' failed (exit {done.returncode})"
                continue
            out = done.stdout
        except OSError as e:
            if e.errno in (errno.EMFILE, errno.ENFILE):  # the process's limit, not the compiler
                raise
            _PASSED_OVER[name] = f"{path}: {e.strerror or e}"
            continue
        except subprocess.SubprocessError:
            _PASSED_OVER[name] = f"'{path} --version' did not answer in 10 s"
            continue
        return Compiler(path, out.splitlines()[0] if out else "")
    return None


def find_compiler() -> Compiler | None:
    """The C compiler to build with, or None when there is none."""
    return _compiler(os.environ.get("LEGDSL_CC") or None)


def no_compiler() -> str | None:
    """None when a compiler is found, else why not, in one line that says what to do."""
    if find_compiler() is not None:
        return None
    wanted = os.environ.get("LEGDSL_CC") or None
    if wanted is None:
        why = "".join(f": {_PASSED_OVER[n]}" for n in ("cc", "gcc", "clang") if n in _PASSED_OVER)
        return f"no C compiler found (cc, gcc or clang; or set LEGDSL_CC){why}"
    fix = "set LEGDSL_CC to a C compiler (gcc, clang) or unset it"
    if shutil.which(wanted) is None:
        alone = " (name the program alone, without options)" if " " in wanted.strip() else ""
        return f"LEGDSL_CC={wanted}: no such program{alone}; {fix}"
    return f"LEGDSL_CC={wanted}: '{wanted} --version' failed, not a C compiler; {fix}"


def sources(generated_dir: Path, controller: str | None = None) -> dict[str, str]:
    """The files of a creature's library (with ``controller``'s C, if given): its generated C
    and the runtime, by file name; ``control.c`` is the controller's (or the runtime's none)."""
    files = {name: (RUNTIME / name).read_text() for name in RUNTIME_FILES}
    for name in DYNAMICS_FILES:
        files[name] = (generated_dir / name).read_text()
    files[SIZES_FILE] = sizes_header(files["dynamics.h"], generated_dir / "dynamics.h")
    if controller is not None:
        files["control.c"] = (generated_dir / f"control_{controller}.c").read_text()
    else:
        files["control.c"] = files["control_none.c"]
    return files


def sizes_header(dynamics_h: str, path: Path) -> str:
    """``legdsl_sizes.h``: the size lines of a creature's ``dynamics.h`` alone, all the runtime's
    units take from the creature. Their objects are kept by the hash of what they include, so
    every creature of the same sizes shares them, and the sizes stay constants in the loops."""
    found = {m.group(1): m.group(0) for m in SIZE_LINE.finditer(dynamics_h)}
    missing = [name for name in SIZES if name not in found]
    if missing:
        raise BuildFailed(f"{path} defines no {missing[0]}: compile the creature again")
    lines = [f"/* {SIZES_FILE}: the creature's sizes, from its dynamics.h (codegen/c/build.py) */"]
    lines += [found[name] for name in SIZES]
    return "\n".join(lines) + "\n"


@lru_cache(maxsize=8)
def native(compiler: Compiler) -> tuple[str, str]:
    """(``-march=native``, a digest of what it means on this processor: the macros it defines,
    ``__AVX2__`` and the like) where ``compiler`` takes it, else two empty strings."""
    try:
        out = _probe_run([compiler.path, "-march=native", "-dM", "-E", "-x", "c", os.devnull], 30)
    except (OSError, subprocess.SubprocessError):
        return "", ""
    if out.returncode != 0:
        return "", ""
    return "-march=native", hashlib.sha256(out.stdout.encode()).hexdigest()[:16]


def flags(compiler: Compiler) -> tuple[str, ...]:
    """The flags ``build`` gives ``compiler``: ``FLAGS``, and ``-march=native`` if it takes it."""
    march = native(compiler)[0]
    return FLAGS + ((march,) if march else ())


def unit_flags(compile_flags: list[str], text: str) -> list[str]:
    """The flags of one unit: -O1 in place of -O3 for one longer than ``LARGE_UNIT``."""
    if len(text) <= LARGE_UNIT:
        return compile_flags
    return ["-O1" if f == "-O3" else f for f in compile_flags]


def library_key(files: dict[str, str], compiler: Compiler) -> str:
    digest = hashlib.sha256()
    for name in sorted(files):
        digest.update(f"{name}\0{len(files[name])}\0".encode())
        digest.update(files[name].encode())
    given = " ".join(flags(compiler) + LIBS + LANGUAGE)
    if any(len(text) > LARGE_UNIT for text in files.values()):  # others keep their keys
        given += f" -O1 past {LARGE_UNIT}"
    digest.update(_built_by(compiler, given))
    return digest.hexdigest()[:20]


def unit_key(unit: str, files: dict[str, str], compiler: Compiler) -> str:
    """The hash an object of ``unit`` is kept under: its text, the headers it includes, its
    flags, the compiler and the processor's features. The runtime's units include only the
    creature's sizes, so one object of each serves every creature of those sizes."""
    digest = hashlib.sha256()
    for name in sorted({unit} | _included(unit, files)):
        code = _after_leading_comment(files[name])
        digest.update(f"{name}\0{len(code)}\0".encode())
        digest.update(code.encode())
    given = " ".join(unit_flags(list(flags(compiler)), files.get(unit, "")) + list(LANGUAGE))
    digest.update(_built_by(compiler, given))
    return digest.hexdigest()[:20]


def _included(unit: str, files: dict[str, str]) -> set[str]:
    """The files of ``files`` that ``unit`` includes, itself or through another of them."""
    found: set[str] = set()
    todo = [unit]
    while todo:
        for name in INCLUDE.findall(files.get(todo.pop(), "")):
            if name in files and name not in found:
                found.add(name)
                todo.append(name)
    return found


def _built_by(compiler: Compiler, given: str) -> bytes:
    """What a cache key takes from the build besides the sources: the compiler, its flags
    (``given``) and the processor features ``-march=native`` turns on."""
    return f"{compiler.path}\0{compiler.version}\0{given}\0{native(compiler)[1]}".encode()


def _after_leading_comment(text: str) -> str:
    """The text after its leading comment, which names the .leg file it was printed from: the
    same creature printed from two files (a copy, a tuned file) compiles to the same objects
    (nothing is compiled with -g, so no comment reaches an object)."""
    if text.startswith("/*") and "*/" in text:
        return text[text.index("*/") + 2 :]
    return text


def build(
    name: str,
    files: dict[str, str],
    compiler: Compiler | None = None,
    starting: Callable[[str], None] | None = None,
) -> Built:
    """The shared library of ``files`` (compiled now unless the cache has it; ``starting`` is
    told what is built, before the compiler runs)."""
    compiler = compiler or find_compiler()
    if compiler is None:
        raise NoCompiler(no_compiler() or "no C compiler found")
    root = cache_dir()
    root.mkdir(parents=True, exist_ok=True)
    final = root / f"{name}-{library_key(files, compiler)}.so"
    if final.is_file():
        if sealed(final):
            with contextlib.suppress(OSError):  # a cache shared read-only stays untouched
                os.utime(final)  # used now: the last to go when the cache is trimmed
            return Built(final, cached=True, seconds=0.0)
        final.unlink(missing_ok=True)  # damaged: built again below
    if starting is not None:
        lines = sum(text.count("\n") for text in files.values())
        starting(f"building the C library of {name} ({lines} lines of C; kept in {root})")
    start = time.perf_counter()
    try:
        _compile(name, files, compiler, root, final)
    except BuildFailed as e:
        why = probe(compiler, root)
        if why is not None:  # the compiler, not the generated C: the user's to fix
            raise CompilerUnusable(why) from e
        raise
    trim(root, keep=final)
    return Built(final, cached=False, seconds=time.perf_counter() - start)


def _compile(name: str, files: dict[str, str], compiler: Compiler, root: Path, final: Path) -> None:
    """Compile ``files`` into the library ``final``, through a temporary directory in ``root``."""
    # a compiler pass that outlived its kill may still write: what it leaves goes with the
    # leftovers (``trim``), not as an error in place of the KeyboardInterrupt
    with tempfile.TemporaryDirectory(
        dir=root, prefix=f".{name}-src-", ignore_cleanup_errors=True
    ) as work:
        for file, text in files.items():
            (Path(work) / file).write_text(text)
        partial = Path(work) / "lib.so"
        # each unit compiled at once in a process of its own (dynamics.c takes most of the
        # time), then linked: the same objects and the same library as one gcc command
        every = flags(compiler)
        compile_flags = [f for f in every if f != "-shared"]
        commands: list[list[str]] = []
        kept = {
            unit: root / OBJECTS / f"{unit}-{unit_key(unit, files, compiler)}.o" for unit in UNITS
        }
        compiled = [
            unit for unit in UNITS if not reuse_object(kept[unit], Path(work) / f"{unit}.o")
        ]
        with _processes() as started:  # Ctrl-C in a notebook: the kernel goes on, they must not
            for unit in compiled:
                source, obj = str(Path(work) / unit), str(Path(work) / f"{unit}.o")
                command = [
                    compiler.path,
                    *unit_flags(compile_flags, files.get(unit, "")),
                    "-I",
                    work,
                    "-c",
                    "-o",
                    obj,
                    *LANGUAGE,
                    source,
                ]
                commands.append(command)
                _start(command, compiler, work, started)
            # all, failed or not; their files named as the units are (control.c:37:37: ...)
            errors = [p.communicate()[1].replace(f"{work}{os.sep}", "") for p in started]
            codes = [process.returncode for process in started]
            for command, code, err in zip(commands, codes, errors, strict=True):
                _check(code, command, err, name, compiler)
            for unit in compiled:  # an object that is none (a wrapper's, exit 0) is not kept
                if _is_elf(Path(work) / f"{unit}.o"):
                    keep_object(Path(work) / f"{unit}.o", kept[unit])
            objects = [str(Path(work) / f"{unit}.o") for unit in UNITS]
            command = [compiler.path, *every, "-o", str(partial), *objects, *LIBS]
            linker = _start(command, compiler, work, started)
            err = linker.communicate()[1]
            if linker.returncode != 0:  # the kept objects may be why: built again next time
                for unit in set(UNITS) - set(compiled):
                    kept[unit].unlink(missing_ok=True)
            _check(linker.returncode, command, err, name, compiler)
            if not _is_elf(partial):  # exit 0 and no library: /bin/true, a wrapper gone wrong
                _check(1, command, "it wrote no shared library", name, compiler)
            seal(partial)
        os.replace(partial, final)  # atomic: a concurrent build renames an identical file


PROBE = (
    "#include <float.h>\n#include <math.h>\n#include <stdint.h>\n#include <string.h>\n"
    'double legdsl_probe(double x) { return sin(x) + (double)strlen("") + DBL_EPSILON; }\n'
)


def probe(compiler: Compiler, root: Path) -> str | None:
    """None when ``compiler`` builds a tiny shared library with the headers the runtime uses,
    else why not, in one line: after a failed build, this tells a broken or missing compiler
    (the user's to fix) from C legdsl generated wrong (legdsl's bug)."""
    with tempfile.TemporaryDirectory(dir=root, prefix=".probe-") as work:
        source, out = Path(work) / "probe.c", Path(work) / "probe.so"
        source.write_text(PROBE)
        command = [compiler.path, "-std=c99", "-fPIC", "-shared", "-o", str(out), str(source)]
        try:
            done = _probe_run(command, 60, env=_temporaries_in(work))
        except (OSError, subprocess.SubprocessError) as e:
            said = str(e)
        else:
            if done.returncode == 0 and _is_elf(out):
                return None
            lines = [line for line in done.stderr.splitlines() if line.strip()]
            said = lines[0].strip() if lines else f"exit {done.returncode}, no library written"
            said = said.replace(f"{work}{os.sep}", "")  # probe.c:1:19: error: ...
    fix = "install a C compiler with its headers (gcc and libc6-dev) or set LEGDSL_CC to one"
    tool = re.search(r"cannot (?:find|execute) \W(as|ld)\W", said)  # it runs them from PATH
    if tool:  # the compiler is there: not a compiler to install
        path = _temporaries_in(work)["PATH"]  # the one it ran with
        fix = f"put the folder of '{tool[1]}' (binutils) on PATH, which is {path}"
    return f"{compiler.path} cannot build a C library here ({said[:200]}); {fix}"


def _temporaries_in(work: str) -> dict[str, str]:
    """The environment of a compiler writing its temporary files (its assembly, the objects of
    a link) in ``work``, the build's directory in the cache: a missing, unwritable or full
    $TMPDIR does not stop a build that the cache has room for; with no PATH (cron), the path
    it was found on, where its linker is too (gcc found no 'ld': "install gcc", it said)."""
    return {"PATH": os.defpath, **os.environ, "TMPDIR": work}


def _stop(processes: list[subprocess.Popen[str]]) -> None:
    """End the compiler processes of a build cut short and reap them: after a KeyboardInterrupt
    caught in a notebook they compiled on into a directory being removed, and stayed zombies."""
    for process in processes:
        with contextlib.suppress(OSError):  # its group: gcc's cc1 and as wrote on after gcc died
            os.killpg(process.pid, signal.SIGKILL)
    for process in processes:
        while True:
            try:
                process.wait()
                break
            except KeyboardInterrupt:  # another Ctrl-C: the first is already unwinding
                continue


def _probe_run(
    command: list[str], timeout: float, env: dict[str, str] | None = None
) -> subprocess.CompletedProcess[str]:
    """``subprocess.run`` of a short look at the compiler (its version, what ``-march=native``
    means, the probe's tiny build), its process reaped whatever ends the wait: on a Ctrl-C
    ``subprocess.run`` waits for it a quarter of a second at most, and a compiler still
    starting stayed a zombie after the call (random API interrupts, seed 21090)."""
    with _processes() as started:  # the timeout, a Ctrl-C: ended and reaped, then raised
        _spawn(command, started, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env)
        out, err = started[0].communicate(timeout=timeout)
        code = started[0].returncode
    return subprocess.CompletedProcess(command, code, out, err)


@contextlib.contextmanager
def _processes() -> Iterator[list[subprocess.Popen[str]]]:
    """The list of the processes started meanwhile (``_spawn``): whatever ends this early, they
    are ended and reaped (``_stop``); in any case they are dropped with the signals held, their
    last references, so that each one's finalizer runs where a Ctrl-C held down cannot land in
    it ("Exception ignored in Popen.__del__" and a traceback, the Ctrl-C lost: random API
    interrupts, seed 21182)."""
    started: list[subprocess.Popen[str]] = []
    try:
        yield started
    except BaseException:
        _stop(started)
        raise
    finally:
        with signals_held():
            started.clear()


def _start(
    command: list[str], compiler: Compiler, work: str, started: list[subprocess.Popen[str]]
) -> subprocess.Popen[str]:
    """A compiler process of the build, noted in ``started``."""
    try:
        return _spawn(command, started, stderr=subprocess.PIPE, env=_temporaries_in(work))
    except OSError as e:  # removed or made unrunnable since it was found
        limit = "; raise the limit of open files (ulimit -n)" if e.errno == errno.EMFILE else ""
        raise CompilerUnusable(f"cannot run {compiler.path} ({e.strerror or e}){limit}") from e


def _spawn(
    command: list[str], started: list[subprocess.Popen[str]], **streams: Any
) -> subprocess.Popen[str]:
    """``command`` started in a process group of its own (its compiler's passes with it:
    ``_stop`` ends them all) and noted in ``started``, with the signals held: a Ctrl-C inside
    ``Popen`` left a compiler running that nobody knew of, a zombie after the call (random API
    interrupts, seed 21090). It starts with them blocked, and keeps them so: ``_stop`` ends it
    with SIGKILL, and its group is never the terminal's."""
    with signals_held():
        process = subprocess.Popen(command, text=True, process_group=0, **streams)
        started.append(process)
        return process


def _is_elf(path: Path) -> bool:
    try:
        with open(path, "rb") as f:
            return f.read(4) == b"\x7fELF"
    except OSError:
        return False


def _check(code: int, command: list[str], stderr: str, name: str, compiler: Compiler) -> None:
    if code == -signal.SIGKILL:  # the kernel's out-of-memory killer, most likely: not our C
        raise CompilerUnusable(
            f"{compiler.path} was killed (SIGKILL) building the C of {name}, most likely out "
            "of memory; close other programs and run again"
        )
    died = _died_of_a_limit(code, stderr)
    if died is not None:  # cc1 killed by SIGXFSZ or SIGSEGV for want of memory: not our C
        raise CompilerUnusable(f"{compiler.path} died building the C of {name} ({died}): a limit "
                               "of this process more likely than the C, a file size (ulimit -f) "
                               "or memory (ulimit -v) one; raise it and run again")  # fmt: skip
    if code != 0:
        raise BuildFailed(
            f"{compiler.path} failed on the C of {name} ({' '.join(command)}):\n" + stderr[-4000:]
        )


_DIED = ("internal compiler error", "virtual memory exhausted", "out of memory", "cannot allocate "
         "memory", "file size limit exceeded", "terminated signal", "killed signal")  # fmt: skip


def _died_of_a_limit(code: int, stderr: str) -> str | None:
    """What says the compiler (or a pass of it) died of a limit; None if it refused the C."""
    if code < 0:
        return f"ended by signal {-code}, {signal.strsignal(-code)}"
    if code == 0:
        return None
    return next((line.strip()[:200] for line in stderr.splitlines()
                 if any(words in line.lower() for words in _DIED)), None)  # fmt: skip
