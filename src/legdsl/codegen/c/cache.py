"""The cache of compiled C: libraries and the objects of their translation units.

The cache: ``legdsl.files.cache_dir()`` (``$LEGDSL_CACHE`` if set, else ``~/.cache/legdsl``);
deleting it is safe, everything in it is built again when next needed.
A library is named by the hash of its sources, the compiler's path and version, the flags and
the processor's features,
so an edit of any of them builds a new one and nothing is ever stale; an unchanged one is
reused. The compiler writes into a temporary file in the cache directory, which is then
renamed to the final name: two runs that build the same library at once each rename a
complete file, and a reader never sees a half-written one. A library ends with its own
SHA-256 after its last ELF byte (``seal``; the loader reads no further than the ELF says), and
the name it is kept under, whose hash says what it was built from; one whose digest or name does
not match, cut short or damaged on the disk, or another entry's copied over it (another
creature's object, which linked into a library that crashed each run), is built again: loading it
could crash the process (a truncated library is a SIGBUS, not an error); a library or object
is kept only when it is a whole ELF file, and a library loaded only when it still is
(``elf_problem``: a compiler may exit 0 having written one cut short). Each use touches the
file, and the cache keeps the most recently used libraries up to ``CACHE_BYTES``.

Each translation unit's object is kept too (``objects/``, sealed alike), by the hash of its
source, the headers it includes, its flags and the compiler: a creature's other controllers,
or a library it lost to the trim, compile only what changed (its ``control.c``, a second out
of nine for the quadruped's gallop) and link (the keys: ``build.unit_key``).
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import shutil
import struct
import time
from pathlib import Path

from legdsl.files import temp_sibling

SEAL = b"\nlegdsl-sha256:"  # then the digest, in hex, a space and the name, at its very end
CACHE_BYTES = 512 * 2**20  # the cache's size, past which the least recently used go
OBJECTS = "objects"  # the cache's folder of compiled translation units
MODULES = "modules"  # the cache's folder of generated modules (legdsl.codegen.kept)
COMPILERS = "compilers"  # the compilers' answers, by their identity (codegen/c/compiler.py)
LEFTOVER_SECONDS = 3600.0  # a build's sources older than this are a killed build's


def reuse_object(kept: Path, obj: Path) -> bool:
    """Copy the kept object to ``obj`` (unsealed) if it is whole, and mark it used."""
    body = read_kept(kept)
    if body is None:
        return False
    try:
        obj.write_bytes(body)
    except OSError:  # a full disk: the compiler, run instead, says so as for any build
        return False
    return True


def keep_object(obj: Path, kept: Path) -> None:
    """Keep a copy of a unit's new object (if there is room: the library is what the build
    is for)."""
    with contextlib.suppress(OSError):
        keep_sealed(obj.read_bytes(), kept)


def read_kept(kept: Path) -> bytes | None:
    """A kept file's bytes before its seal, marked used (the last to go when the cache is
    trimmed); None if it is missing, cut short or damaged."""
    body = unsealed(kept)
    if body is not None:
        with contextlib.suppress(OSError):  # a cache shared read-only stays untouched
            os.utime(kept)
    return body


def keep_sealed(data: bytes, kept: Path) -> None:
    """``data`` kept at ``kept``, sealed with its SHA-256 and its name and renamed into place
    whole: two processes that keep the same file each rename a whole one."""
    kept.parent.mkdir(parents=True, exist_ok=True)
    temporary = temp_sibling(kept, "new")
    try:
        temporary.write_bytes(data + _seal_of(data, kept.name))
        os.replace(temporary, kept)
    finally:
        temporary.unlink(missing_ok=True)


def seal(path: Path, name: str | None = None) -> None:
    """Append the library's SHA-256 to it, and the name it is to be kept under (``path``'s own
    unless given: a library is built under a temporary name), which ``sealed`` checks too."""
    seal = _seal_of(path.read_bytes(), name or path.name)
    with open(path, "ab") as out:
        out.write(seal)


def _seal_of(body: bytes, name: str) -> bytes:
    """The seal that ends a file kept as ``name`` whose bytes before it are ``body`` (``unsealed``
    reads it): their digest, then the name. The names of the cache are the hashes of what their
    files are built from, so an entry copied or renamed over another (whole, and sealed as
    its own) is found out and built again, not used as the other."""
    return SEAL + hashlib.sha256(body).hexdigest().encode() + b" " + name.encode()


def sealed(path: Path) -> bool:
    """Whether the library is whole and its own: its last bytes are the digest of the ones
    before and its name."""
    return unsealed(path) is not None


def unsealed(path: Path) -> bytes | None:
    """The file's bytes before its seal, or None if it is missing, cut short, damaged, or was
    sealed under another name (another entry's, copied over it)."""
    try:
        data = path.read_bytes()
    except OSError:
        return None
    body, mark, digest = data.rpartition(SEAL)
    return body if mark and mark + digest == _seal_of(body, path.name) else None


def elf_problem(data: bytes) -> str | None:
    """None when ``data`` is a whole ELF file (a library or an object), else what is wrong: its
    header, its section header table, its program headers and each segment it loads (and each
    section with bytes in the file) must lie within it. A library cut short (a full disk under
    a compiler that says nothing, a wrapper gone wrong) maps pages past its end, and the first
    touch of one is a SIGBUS that kills the process, no error to catch."""
    if len(data) < 16 or data[:4] != b"\x7fELF" or data[4] not in (1, 2) or data[5] not in (1, 2):
        return "not an ELF file"
    wide, order = data[4] == 2, "<" if data[5] == 1 else ">"
    head = struct.Struct(order + ("HHIQQQIHHHHHH" if wide else "HHIIIIIHHHHHH"))
    if len(data) < 16 + head.size:
        return f"cut short: {len(data)} bytes, in its ELF header"
    _, _, _, _, phoff, shoff, _, _, phsize, phnum, shsize, shnum, _ = head.unpack_from(data, 16)
    if shoff + shnum * shsize > len(data):
        return f"cut short: {len(data)} bytes, its section headers end at {shoff + shnum * shsize}"
    if phoff + phnum * phsize > len(data):
        return f"cut short: {len(data)} bytes, its program headers end at {phoff + phnum * phsize}"
    program = struct.Struct(order + ("IIQQQQQQ" if wide else "IIIIIIII"))
    for i in range(phnum if phsize >= program.size else 0):
        entry = program.unpack_from(data, phoff + i * phsize)
        kind, offset, size = (entry[0], entry[2], entry[5]) if wide else entry[0:2] + entry[4:5]
        if kind == 1 and offset + size > len(data):  # PT_LOAD
            return f"cut short: {len(data)} bytes, a segment it loads ends at {offset + size}"
    section = struct.Struct(order + ("IIQQQQIIQQ" if wide else "IIIIIIIIII"))
    for i in range(shnum if shsize >= section.size else 0):
        _, kind, _, _, offset, size, *_ = section.unpack_from(data, shoff + i * shsize)
        if kind != 8 and offset + size > len(data):  # SHT_NOBITS (.bss) has none in the file
            return f"cut short: {len(data)} bytes, a section ends at {offset + size}"
    return None


def trim(root: Path, keep: Path, most: int = CACHE_BYTES) -> None:
    """Remove the least recently used libraries, objects and kept modules while the cache
    holds more than ``most`` bytes. A process that has a removed library loaded keeps it (the
    file lives on until closed); one about to load it builds it again
    (``legdsl.sim.c_library.load_library``). The sources of a build killed outright (SIGKILL, a
    power cut), and a killed ``keep_sealed``'s temporary file, are removed after
    ``LEFTOVER_SECONDS``."""
    builds = [*root.glob(".*-src-*"), *root.glob(".probe-*"), *root.glob(f"{COMPILERS}/.*")]
    for work in [*builds, *root.glob(f"{OBJECTS}/.*"), *root.glob(f"{MODULES}/.*")]:
        with contextlib.suppress(OSError):  # another process's, just removed
            if time.time() - work.stat().st_mtime > LEFTOVER_SECONDS:
                if work.is_dir():
                    shutil.rmtree(work, ignore_errors=True)
                else:  # keep_sealed's
                    work.unlink()
    found = []
    for path in [*root.glob("*.so"), *root.glob(f"{OBJECTS}/*.o"), *root.glob(f"{MODULES}/*.z")]:
        try:
            info = path.stat()
        except OSError:  # removed by another process meanwhile
            continue
        found.append((info.st_mtime, info.st_size, path))
    total = sum(size for _, size, _ in found)
    for _, size, path in sorted(found, key=lambda f: (f[0], str(f[2]))):
        if total <= most:
            break
        if path != keep:
            try:
                path.unlink(missing_ok=True)
            except OSError:  # another user's, in a shared cache: theirs to remove
                continue
            total -= size
