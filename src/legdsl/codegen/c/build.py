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
import signal
import subprocess
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from legdsl.codegen.c.cache import (
    OBJECTS,
    elf_problem,
    keep_object,
    reuse_object,
    seal,
    trim,
    unsealed,
)
from legdsl.codegen.c.compiler import (  # noqa: F401 (_compiler, _probe_run: tests clear, use)
    Compiler,
    _compiler,
    _probe_run,
    _processes,
    _spawn,
    find_compiler,
    native,
    no_compiler,
)
from legdsl.files import cache_dir

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
# a compiler still running after PATIENCE[0] s, then every PATIENCE[1] s, is said to be (a hung
# one, LEGDSL_CC a wrapper gone wrong, said nothing until it was killed)
PATIENCE = (10.0, 30.0)
STILL = "still building"  # how those notes start (``build``'s ``starting`` is told them too)
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
class Built:
    path: Path  # the shared library
    cached: bool  # reused from the cache (no compiler run)
    seconds: float  # time spent in the compiler (0 when cached)


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
    told what is built, before the compiler runs, and then, while it runs past ``PATIENCE``,
    which units it is still compiling and for how long: notes that start with ``STILL``)."""
    compiler = compiler or find_compiler()
    if compiler is None:
        raise NoCompiler(no_compiler() or "no C compiler found")
    root = cache_dir()
    root.mkdir(parents=True, exist_ok=True)
    final = root / f"{name}-{library_key(files, compiler)}.so"
    if final.is_file():
        body = unsealed(final)  # sealed, and an ELF file that holds all it maps
        if body is not None and elf_problem(body) is None:
            with contextlib.suppress(OSError):  # a cache shared read-only stays untouched
                os.utime(final)  # used now: the last to go when the cache is trimmed
            return Built(final, cached=True, seconds=0.0)
        final.unlink(missing_ok=True)  # damaged: built again below
    if starting is not None:
        lines = sum(text.count("\n") for text in files.values())
        starting(f"building the C library of {name} ({lines} lines of C; kept in {root})")
    start = time.perf_counter()
    try:
        _compile(name, files, compiler, root, final, starting)
    except BuildFailed as e:
        why = probe(compiler, root)
        if why is not None:  # the compiler, not the generated C: the user's to fix
            raise CompilerUnusable(why) from e
        raise
    trim(root, keep=final)
    return Built(final, cached=False, seconds=time.perf_counter() - start)


def _compile(
    name: str,
    files: dict[str, str],
    compiler: Compiler,
    root: Path,
    final: Path,
    waiting: Callable[[str], None] | None = None,
) -> None:
    """Compile ``files`` into the library ``final``, through a temporary directory in ``root``
    (``waiting`` told of compilers still running: ``_outputs``)."""
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
            said = _outputs(started, compiled, f"{name}: {_named(compiler)}", waiting)
            errors = [err.replace(f"{work}{os.sep}", "") for err in said]
            codes = [process.returncode for process in started]
            for command, code, err in zip(commands, codes, errors, strict=True):
                _check(code, command, err, name, compiler)
            for unit in compiled:  # an object that is none (a wrapper's, exit 0) is not kept
                if _whole(Path(work) / f"{unit}.o") is None:
                    keep_object(Path(work) / f"{unit}.o", kept[unit])
            objects = [str(Path(work) / f"{unit}.o") for unit in UNITS]
            command = [compiler.path, *every, "-o", str(partial), *objects, *LIBS]
            linker = _start(command, compiler, work, started)
            (err,) = _outputs([linker], ["the link"], f"{name}: {_named(compiler)}", waiting)
            if linker.returncode != 0:  # the kept objects may be why: built again next time
                for unit in set(UNITS) - set(compiled):
                    kept[unit].unlink(missing_ok=True)
            _check(linker.returncode, command, err, name, compiler)
            if not partial.exists():  # exit 0 and no library: /bin/true (``probe`` says so)
                _check(1, command, "it wrote no shared library", name, compiler)
            wrong = _whole(partial)  # garbage, or cut short: a wrapper gone wrong
            if wrong is not None:  # the compiler's failure, whatever the C: it said it was done
                raise CompilerUnusable(f"{_named(compiler)} wrote no loadable library for {name} "
                                       f"({wrong}), though it exited 0; {_fix(compiler, True)}")  # fmt: skip
            seal(partial, final.name)  # its name is its key: another's is not taken for it
        os.replace(partial, final)  # atomic: a concurrent build renames an identical file


def _outputs(
    started: list[subprocess.Popen[str]],
    units: list[str],
    who: str,
    waiting: Callable[[str], None] | None,
) -> list[str]:
    """What each process of ``started`` (compiling ``units``) wrote (``_said``), once all have
    ended; ``waiting`` is told which are still running after ``PATIENCE[0]`` s and then every
    ``PATIENCE[1]`` s, by ``who`` (the library, the compiler) and for how long."""
    start = time.monotonic()
    note = start + PATIENCE[0]
    said = []
    for process in started:
        while True:
            left = None if waiting is None else max(0.0, note - time.monotonic())
            try:
                said.append(_said(process.communicate(timeout=left)))
                break
            except subprocess.TimeoutExpired:
                assert waiting is not None
                running = [u for u, p in zip(units, started, strict=False) if p.poll() is None]
                seconds = time.monotonic() - start
                if running:  # else the one waited for ended since: 'has run 3 s on  (if ...'
                    waiting(f"{STILL} the C library of {who} has run {seconds:.0f} s on "
                            f"{', '.join(running)} (if it hangs, stop it and set LEGDSL_CC to another compiler)")  # fmt: skip
                note += PATIENCE[1]
    return said


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
            wrong = _whole(out)
            if done.returncode == 0 and wrong is None:
                return None
            lines = [line for line in done.stderr.splitlines() if line.strip()]
            said = lines[0].strip() if lines and done.returncode else ""
            if not said:  # exit 0 and garbage, or a library cut short: no loadable one
                none = not out.exists() or wrong == "not an ELF file"
                said = f"exit {done.returncode}, " + (
                    "no library written" if not out.exists() else "no loadable library written"
                    if none else f"its library {wrong}"
                )  # fmt: skip
            said = said.replace(f"{work}{os.sep}", "")  # probe.c:1:19: error: ...
    fix = _fix(compiler, garbage=said.startswith("exit 0,"))
    tool = re.search(r"cannot (?:find|execute) \W(as|ld)\W", said)  # it runs them from PATH
    if tool:  # the compiler is there: not a compiler to install
        path = _temporaries_in(work)["PATH"]  # the one it ran with
        fix = f"put the folder of '{tool[1]}' (binutils) on PATH, which is {path}"
    return f"{_named(compiler)} cannot build a C library here ({said[:200]}); {fix}"


def _temporaries_in(work: str) -> dict[str, str]:
    """The environment of a compiler writing its temporary files (its assembly, the objects of
    a link) in ``work``, the build's directory in the cache: a missing, unwritable or full
    $TMPDIR does not stop a build that the cache has room for; with no PATH (cron), the path
    it was found on, where its linker is too (gcc found no 'ld': "install gcc", it said)."""
    return {"PATH": os.defpath, **os.environ, "TMPDIR": work}


def _start(
    command: list[str], compiler: Compiler, work: str, started: list[subprocess.Popen[str]]
) -> subprocess.Popen[str]:
    """A compiler process of the build, noted in ``started``."""
    try:
        # its output kept, both streams (said when it fails): a wrapper's chatter is not the
        # run's, and a pipe to ``head`` that closes early is not the compiler's to die of
        streams = {"stdout": subprocess.PIPE, "stderr": subprocess.PIPE}
        return _spawn(command, started, env=_temporaries_in(work), **streams)
    except OSError as e:  # removed or made unrunnable since it was found
        limit = "; raise the limit of open files (ulimit -n)" if e.errno == errno.EMFILE else ""
        raise CompilerUnusable(f"cannot run {compiler.path} ({e.strerror or e}){limit}") from e


def _said(streams: tuple[str, str]) -> str:
    """What a compiler process wrote: its errors, then its output (a wrapper's) if any."""
    out, err = streams
    return err + (f"(and on its standard output:)\n{out}" if out and out.strip() else "")


def _whole(path: Path) -> str | None:
    """None when ``path`` is a whole ELF file (``elf_problem``), else what is wrong with it."""
    try:
        return elf_problem(path.read_bytes())
    except OSError as e:
        return f"none written ({e.strerror or e})"


def _named(compiler: Compiler) -> str:
    """The compiler as the user knows it: the LEGDSL_CC they set, if they did."""
    return f"{compiler.path} (LEGDSL_CC)" if os.environ.get("LEGDSL_CC") else compiler.path


def _fix(compiler: Compiler, garbage: bool) -> str:
    """What to do about a compiler that cannot build a library: the LEGDSL_CC the user set, if
    it exited 0 and wrote none that loads (no headers to install would make it do that)."""
    if garbage and os.environ.get("LEGDSL_CC"):
        return "set LEGDSL_CC to a working C compiler (gcc, clang) or unset it"
    return "install a C compiler with its headers (gcc and libc6-dev) or set LEGDSL_CC to one"


def _check(code: int, command: list[str], stderr: str, name: str, compiler: Compiler) -> None:
    if code == -signal.SIGKILL:  # the kernel's out-of-memory killer, most likely: not our C
        raise CompilerUnusable(
            f"{compiler.path} was killed (SIGKILL) building the C of {name}, most likely out "
            "of memory; close other programs and run again"
        )
    if code == -signal.SIGPIPE:  # a pipe of its own closed (its output is legdsl's to read)
        raise CompilerUnusable(f"{_named(compiler)} died building the C of {name} (ended by "
                               f"SIGPIPE, a pipe it wrote to was closed):\n{stderr[-2000:]}")  # fmt: skip
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
