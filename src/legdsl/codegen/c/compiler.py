"""The C compiler legdsl builds with: found (``find_compiler``), why none is (``no_compiler``),
what ``-march=native`` means for it (``native``), and the processes it runs in.

``$LEGDSL_CC`` if set, else the first of ``cc``, ``gcc``, ``clang`` on the PATH. A cache key
names the compiler by its path and its ``--version`` line and the processor by what
``-march=native`` defines (``cc -march=native -dM -E``): two compiler runs, 15 ms, that a
run whose library is cached would pay in each new process. They are remembered in the cache
(``compilers/``) under the compiler program's identity (its real path, size, modification
time, inode and device) and, for ``-march=native``, the processor's (``/proc/cpuinfo``'s model
and feature lines): a cached run runs no compiler, and an upgraded or replaced compiler, or
another processor sharing the cache, is asked again. A script (a wrapper, ``#!``) may run any
compiler whatever its own stat says: its answers are never remembered.
"""

from __future__ import annotations

import contextlib
import errno
import hashlib
import json
import os
import platform
import shutil
import signal
import subprocess
from collections.abc import Iterator
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any

from legdsl.codegen.c.cache import COMPILERS, keep_sealed, read_kept
from legdsl.files import cache_dir
from legdsl.signals import signals_held


@dataclass(frozen=True)
class Compiler:
    path: str
    version: str  # the first line of ``--version``
    identity: str = ""  # the program's stat (``_identity``), "" where its answers are not kept


# why each compiler was passed over, said if none is found (a failing cc was just "none found")
_PASSED_OVER: dict[str, str] = {}


@lru_cache(maxsize=8)
def _compiler(wanted: str | None) -> Compiler | None:
    names = [wanted] if wanted else ["cc", "gcc", "clang"]
    for name in names:
        path = shutil.which(name)
        if path is None:
            continue
        identity = _identity(path)
        known = _remembered(identity, "version")
        if isinstance(known, str):
            return Compiler(path, known, identity)
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
        version = out.splitlines()[0] if out else ""
        _remember(identity, "version", version)
        return Compiler(path, version, identity)
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
        # which() passes over a directory and a file without execute permission alike
        given = Path(wanted).expanduser() if os.sep in wanted else None
        if given is not None and given.is_dir():
            return f"LEGDSL_CC={wanted}: a directory, not a program; {fix}"
        if given is not None and given.exists():
            return f"LEGDSL_CC={wanted}: not executable (chmod +x it if it is a compiler); {fix}"
        alone = " (name the program alone, without options)" if " " in wanted.strip() else ""
        return f"LEGDSL_CC={wanted}: no such program{alone}; {fix}"
    return f"LEGDSL_CC={wanted}: '{wanted} --version' failed, not a C compiler; {fix}"


@lru_cache(maxsize=8)
def native(compiler: Compiler) -> tuple[str, str]:
    """(``-march=native``, a digest of what it means on this processor: the macros it defines,
    ``__AVX2__`` and the like) where ``compiler`` takes it, else two empty strings."""
    identity = f"{compiler.identity}\0{_processor()}" if compiler.identity and _processor() else ""
    known = _remembered(identity, "native")
    if isinstance(known, list) and len(known) == 2 and all(isinstance(k, str) for k in known):
        return known[0], known[1]
    try:
        out = _probe_run([compiler.path, "-march=native", "-dM", "-E", "-x", "c", os.devnull], 30)
    except (OSError, subprocess.SubprocessError):
        return "", ""
    found = ("", "")
    if out.returncode == 0:
        found = ("-march=native", hashlib.sha256(out.stdout.encode()).hexdigest()[:16])
    _remember(identity, "native", list(found))
    return found


def _identity(path: str) -> str:
    """The compiler program's identity (its real path, size, modification time, inode,
    device), or "" for a script, which may run any compiler, or one that cannot be read."""
    try:
        real = os.path.realpath(path)
        with open(real, "rb") as f:
            if f.read(2) == b"#!":
                return ""
            info = os.fstat(f.fileno())
    except OSError:
        return ""
    return f"{real}\0{info.st_size}\0{info.st_mtime_ns}\0{info.st_ino}\0{info.st_dev}"


@lru_cache(maxsize=1)
def _processor() -> str:
    """The processor's model and features (``/proc/cpuinfo``'s lines that name them), or ""
    where the system does not say: then what ``-march=native`` means is asked every time."""
    try:
        text = Path("/proc/cpuinfo").read_text(errors="replace")
    except OSError:
        return ""
    named = ("vendor_id", "cpu family", "model", "flags", "features", "isa", "uarch",
             "cpu implementer", "cpu architecture", "cpu variant", "cpu part", "cpu revision")  # fmt: skip
    lines = {line for line in text.splitlines() if line.lower().startswith(named)}
    return platform.machine() + "\0" + "\n".join(sorted(lines)) if lines else ""


def _memo(identity: str) -> Path:
    return cache_dir() / COMPILERS / f"{hashlib.sha256(identity.encode()).hexdigest()[:20]}.json"


def _remembered(identity: str, what: str) -> object:
    """The answer kept for ``identity`` (``_remember``), or None."""
    if not identity:
        return None
    try:
        body = read_kept(_memo(identity))
        kept = json.loads(body) if body is not None else {}
    except (OSError, ValueError):  # no cache (no HOME), or not legdsl's file
        return None
    if not isinstance(kept, dict) or kept.get("identity") != identity:
        return None
    return kept.get(what)


def _remember(identity: str, what: str, answer: object) -> None:
    """Keep ``answer`` for ``identity`` (where there is room and the cache may be written)."""
    if not identity:
        return
    with contextlib.suppress(OSError, ValueError):
        body = read_kept(_memo(identity))
        kept = json.loads(body) if body is not None else {}
        if not isinstance(kept, dict) or kept.get("identity") != identity:
            kept = {"identity": identity}
        kept[what] = answer
        keep_sealed(json.dumps(kept).encode(), _memo(identity))


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
