"""Writing files and directories whole or not at all: the one write-then-rename helper.

Every writer in legdsl (run directories, metrics.json, exports, the player, videos, the
generated modules) goes through this module, so that a crash, a Ctrl-C or a SIGKILL at any
instant leaves either the old file or the new one, never a mix or a half-written file.

Temporary names are hidden siblings of the target, ``.NAME.TAG-PID-RANDOM`` (keeping the
target's suffix, which tools such as ffmpeg read; NAME is cut short, with a digest of the
whole, where the temporary name would pass the file system's 255 bytes), so two processes
writing the same target at the same moment never share one; leftovers of a killed writer are
recognised by ``is_leftover`` and ``leftovers``. A writer of several files into one directory
(a run directory) holds ``writing_alone``'s lock meanwhile.

A write the system refuses for want of room (a full disk, a quota, a file too large, an I/O
error) raises an ``OSError`` that names the target, not its temporary name, and says what to
free (``refused``); the temporary file is removed and an older file at the target is kept.
A target that is a device or a pipe (``/dev/null``, a FIFO) is written in place (``is_device``),
as is one of this process's open files (``/dev/stdout`` with stdout sent to a file: through
the descriptor, so that what is printed after it follows it); a symbolic link to a file has
that file replaced, and stays a link.

``cache_dir`` is where legdsl keeps what it can always build again (the compiled C libraries,
the generated modules of the creatures compiled, the parser's tables), for every stage that
keeps something there.
"""

from __future__ import annotations

import contextlib
import errno
import fcntl
import hashlib
import os
import re
import secrets
import shutil
import signal
import stat
import sys
import tempfile
from collections.abc import Iterator
from pathlib import Path

# .NAME.TAG-PID-HEX[.suffix]: what temp_sibling makes
_LEFTOVER = re.compile(
    r"^\.(?P<name>.+)\.(?P<tag>tmp|new|old)-(?P<pid>\d+)-[0-9a-f]{8}(?P<suffix>\.[^.]*)?$"
)


# the longest file name of the common file systems (ext4, XFS, Btrfs, APFS: 255 bytes)
NAME_MAX = 255
# what a temporary name adds to its target's: two dots, the tag, a pid, 8 hex digits, dashes
_ADDED = len("..old--") + len(str(2**32)) + 8
_SUFFIX_MAX = 16  # a longer "suffix" is no format's extension: the temporary name drops it


# errors of a write the disk refused, and what the user can do about each
REFUSED_WRITES = {
    errno.ENOSPC: "the disk is full: free some space on it",
    errno.EDQUOT: "your disk quota is used up: remove some of your files on that disk",
    errno.EFBIG: "the file is larger than the file-size limit (ulimit -f) or that file system allows",
    errno.EIO: "the disk reported an input/output error: check the disk",
}


def cache_dir() -> Path:
    """Where legdsl keeps what it can always build again (compiled C, generated modules, the
    parser's tables):
    ``$LEGDSL_CACHE`` if set, else ``$XDG_CACHE_HOME/legdsl`` or ``~/.cache/legdsl``. A relative
    ``$XDG_CACHE_HOME`` is ignored, as the XDG spec says (it named a folder in whatever directory
    a command ran in: ./relx/legdsl/); ``~/`` is expanded first (a settings file no shell read)."""
    # "~/x" from a file of settings that no shell expanded: not a directory named "~" here
    try:
        if os.environ.get("LEGDSL_CACHE"):
            return Path(os.environ["LEGDSL_CACHE"]).expanduser()
        xdg = Path(os.environ.get("XDG_CACHE_HOME") or ".").expanduser()
        return (xdg if xdg.is_absolute() else Path.home() / ".cache") / "legdsl"
    except RuntimeError:  # no HOME, and a user the system does not know (a container's bare uid)
        raise FileNotFoundError(errno.ENOENT, NO_CACHE) from None


NO_CACHE = "no cache directory: HOME is not set and this user has no home directory"


def refused(e: OSError, path: str | Path) -> OSError:
    """``e``, a write of ``path`` the disk refused, as an ``OSError`` naming ``path`` that says
    why and what to free; other errors (a permission, a missing folder) as they are."""
    if e.errno not in REFUSED_WRITES:
        return e
    why = e.strerror or os.strerror(e.errno)
    if REFUSED_WRITES[e.errno] not in why:  # not said already
        why = f"{why} ({REFUSED_WRITES[e.errno]})"
    return OSError(e.errno, why, str(path))


def refused_in(said: str) -> int | None:
    """The errno of a refused write that another program (ffmpeg, a C compiler) reports in
    the text ``said``, or None: those tools say ``No space left on device``, as strerror does."""
    for number in REFUSED_WRITES:
        if os.strerror(number).lower() in said.lower():
            return number
    return None


def free_bytes(path: str | Path) -> int | None:
    """The bytes free on the disk ``path`` would be written to (its nearest existing
    folder's), or None where the system does not say."""
    probe = Path(path)
    while not probe.exists() and probe.parent != probe:
        probe = probe.parent
    try:
        return shutil.disk_usage(probe).free
    except OSError:
        return None


def temp_sibling(path: str | Path, tag: str = "tmp", suffix: str | None = None) -> Path:
    """A fresh hidden name beside ``path``: ``.NAME.TAG-PID-RANDOM`` plus its suffix (or
    ``suffix``), NAME shortened where the whole would pass the file system's limit."""
    path = Path(path)
    end = _suffix(path) if suffix is None else suffix
    unique = f"{os.getpid()}-{secrets.token_hex(4)}"
    return path.with_name(f".{_temp_stem(path.name, end)}.{tag}-{unique}{end}")


def _suffix(path: Path) -> str:
    return path.suffix if len(os.fsencode(path.suffix)) <= _SUFFIX_MAX else ""


def _temp_stem(name: str, suffix: str) -> str:
    """``name`` as its temporary siblings spell it: whole where the sibling's name fits in
    NAME_MAX bytes, else cut short and made unique again by a digest of the whole name."""
    room = NAME_MAX - _ADDED - len(os.fsencode(suffix))
    raw = os.fsencode(name)
    if len(raw) <= room:
        return name
    return f"{os.fsdecode(raw[: room - 9])}~{hashlib.sha256(raw).hexdigest()[:8]}"


def is_leftover(path: Path, name: str | None = None) -> bool:
    """Whether ``path`` is a temporary sibling (of the target ``name``, if given)."""
    m = _LEFTOVER.match(path.name)
    return m is not None and (name is None or _names(m, name))


def written_as(path: Path) -> str:
    """The name ``path`` is written for: a temporary sibling's target's, else its own."""
    m = _LEFTOVER.match(path.name)
    return m.group("name") if m else path.name


def _names(m: re.Match[str], name: str) -> bool:
    """Whether the temporary name ``m`` matched is one of the target ``name``'s."""
    return m.group("name") in (name, _temp_stem(name, m.group("suffix") or ""))


def _pid_alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:
        return True  # it exists, owned by someone else
    return True


def leftovers(directory: Path, name: str) -> list[Path]:
    """Temporary siblings of ``directory/name`` whose writer is no longer running."""
    if not directory.is_dir():
        return []
    found = []
    for p in directory.iterdir():
        m = _LEFTOVER.match(p.name)
        if m and _names(m, name) and not _pid_alive(int(m.group("pid"))):
            found.append(p)
    return sorted(found)


def remove(path: Path) -> None:
    """Remove a file or a directory tree, whichever ``path`` is; missing is fine."""
    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path, ignore_errors=True)
    else:
        path.unlink(missing_ok=True)


def _normal_mode(path: Path) -> None:
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(path, 0o666 & ~umask)  # mkstemp makes it private; give it a normal file's mode


def is_device(path: Path) -> bool:
    """Whether ``path`` is a device or a pipe (/dev/null, /dev/stdout, a FIFO): written in
    place, since renaming a file over it would replace the device itself (as root, in /dev)."""
    try:
        mode = os.stat(path).st_mode
    except OSError:
        return False
    return not (stat.S_ISREG(mode) or stat.S_ISDIR(mode))


# The standard streams this process was started without (``>&-``), each given /dev/null by
# ``keep_standard_descriptors``: closed, the first file opened takes its number, and
# ``-o /dev/stdout`` wrote over that file (a font of matplotlib's, in ``legdsl plot``).
CLOSED_AT_START: set[int] = set()


def keep_standard_descriptors() -> None:
    """Give each closed standard descriptor (0, 1, 2) /dev/null, and remember which."""
    for fd in (0, 1, 2):
        try:
            os.fstat(fd)
        except OSError:
            null = os.open(os.devnull, os.O_RDWR)
            if null != fd:
                os.dup2(null, fd)
                os.close(null)
            CLOSED_AT_START.add(fd)


def closed_stream(path: str | Path) -> str | None:
    """``path``'s standard stream if it names one this process was started without."""
    fd = process_fd(Path(path))
    return (
        ("standard input", "standard output", "standard error")[fd]
        if (fd in CLOSED_AT_START and fd is not None)
        else None
    )


# a descriptor of this process by its name: /dev/stdout -> /proc/self/fd/1, /dev/fd/2
_FD_NAME = re.compile(r"^/(?:proc/(?P<pid>self|thread-self|\d+)/fd|dev/fd)/(?P<fd>\d+)$")


def process_fd(path: Path) -> int | None:
    """The descriptor of this process that ``path`` names (through its symbolic links:
    ``/dev/stdout``, ``/dev/fd/N``, ``/proc/self/fd/N``), or None. Such a file is written in
    place: replaced by a rename, the link itself would go (as root, ``/dev/stdout``), or the
    file the shell sent stdout to would be swapped under the open descriptor."""
    name = os.path.abspath(path)
    for _ in range(40):  # the system's own limit of links followed
        m = _FD_NAME.match(name)
        if m and m.group("pid") in (None, "self", "thread-self", str(os.getpid())):
            return int(m.group("fd"))
        try:
            link = os.readlink(name)
        except OSError:
            return None
        name = os.path.normpath(os.path.join(os.path.dirname(name), link))
    return None


def _replaced(path: Path) -> Path:
    """The file a write of ``path`` replaces: a symbolic link's target, so the link stays."""
    return Path(os.path.realpath(path)) if path.is_symlink() else path


@contextlib.contextmanager
def _in_place(path: Path) -> Iterator[Path]:
    """``path`` itself to write (a device, a pipe, a descriptor's file); a descriptor of this
    process is then moved past what was written, for what is printed next to follow it."""
    fd = process_fd(path)
    with _refusals_of(path, path):
        yield path
    if fd is not None:
        with contextlib.suppress(OSError):  # a pipe or a terminal: nothing to move
            os.lseek(fd, 0, os.SEEK_END)


@contextlib.contextmanager
def _drawn_first(path: Path, name: str) -> Iterator[Path]:
    """A scratch file called ``name`` to write, then copied to ``path`` (a device, a pipe),
    if it was written: for a writer that seeks, or that takes the format from the name."""
    with tempfile.TemporaryDirectory(prefix="legdsl-") as scratch:
        drawn = Path(scratch) / name
        yield drawn
        if drawn.exists():
            write_atomic(path, drawn.read_bytes())


@contextlib.contextmanager
def atomic_path(path: str | Path, suffix: str | None = None) -> Iterator[Path]:
    """A temporary path to write (ending in ``suffix``, by default ``path``'s own); renamed
    over ``path`` (a link's target) when the block ends without error, removed if it raises.
    Parents are made."""
    path = Path(path)
    if (is_device(path) or process_fd(path) is not None) and suffix not in (None, path.suffix):
        # a writer that takes its format from the name (USD): /dev/stdout has none
        with _drawn_first(path, path.with_suffix(suffix).name) as drawn:
            yield drawn
        return
    if is_device(path) or process_fd(path) is not None:
        with _in_place(path) as same:
            yield same
        return
    target = _replaced(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    _remove_leftovers(target)  # a killed writer's (kill -9: .v.mp4.tmp-... stayed)
    tmp = temp_sibling(target, suffix=suffix)
    try:
        with _refusals_of(tmp, path):
            yield tmp
        instant(f"wrote {tmp.name}")
        _rename(tmp, target, path)
    except BaseException:
        _discard(tmp)
        raise


@contextlib.contextmanager
def atomic_same_name(path: str | Path) -> Iterator[Path]:
    """``atomic_path`` for a writer that names what it writes after its file (the plots): the
    temporary file has ``path``'s own name, in a hidden sibling directory. A writer that wrote
    nothing leaves ``path`` as it was."""
    path = Path(path)
    if is_device(path) or process_fd(path) is not None:
        # drawn into a file first: a picture's writer may seek, which a pipe cannot
        with _drawn_first(path, path.name) as drawn:
            yield drawn
        return
    target = _replaced(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    _remove_leftovers(target)  # a killed drawing's folder (kill -9: .figure6.png.tmp-... stayed)
    folder = temp_sibling(target, suffix="")
    try:
        inner = folder / path.name
        with _refusals_of(folder, path):
            folder.mkdir()
        with _refusals_of(inner, path):
            yield inner
        if inner.exists():
            _rename(inner, target, path)
    finally:
        _discard(folder)


def _remove_leftovers(target: Path) -> None:
    """Remove the temporary siblings of ``target`` whose writers were killed."""
    with contextlib.suppress(OSError):
        for left in leftovers(target.parent, target.name):
            remove(left)


def _discard(tmp: Path) -> None:
    """Remove a temporary file or folder, if there is one, without an error of its own: on a
    read-only disk even removing a missing file fails (EROFS), and that error, naming the
    hidden temporary name, replaced the write's own, which names the file the user asked for
    ("Read-only file system (rofs/old/.animation.html.tmp-27114-70b89766.html)")."""
    with contextlib.suppress(OSError):
        remove(tmp)


@contextlib.contextmanager
def _refusals_of(tmp: Path, path: Path) -> Iterator[None]:
    """A write of ``tmp`` (an error naming no file, or ``tmp``) that the disk refused, raised
    as ``refused`` of ``path``, the file the user knows."""
    try:
        yield
    except OSError as e:
        if e.filename is not None and str(e.filename) != str(tmp) and e.errno != errno.ENOSPC:
            raise  # another file's (an input that cannot be read): as it is
        raise refused(type(e)(e.errno, e.strerror, str(path)), path) from None


def _rename(tmp: Path, target: Path, path: Path) -> None:
    try:
        os.replace(tmp, target)
    except OSError as e:  # name the file the user knows (a directory in its place...)
        raise refused(type(e)(e.errno, e.strerror, str(path)), path) from None


@contextlib.contextmanager
def writing_alone(directory: Path) -> Iterator[None]:
    """Hold ``directory``'s lock while writing several files into it: two writers of one
    directory (two runs given the same ``--out``) take turns, so its files all come from one
    of them, the last (the system releases the lock of a writer killed meanwhile)."""
    fd = os.open(directory, os.O_RDONLY | os.O_DIRECTORY)
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:  # said, not a silent wait (a video drawn from it takes minutes)
            print(f"legdsl: {directory} is in use by another legdsl command (a run, or one "
                  "drawing from it): waiting for it to finish", file=sys.stderr)  # fmt: skip
            fcntl.flock(fd, fcntl.LOCK_EX)
        _remove_all_leftovers(directory)
        yield
    finally:
        os.close(fd)


def _remove_all_leftovers(directory: Path) -> None:
    """Remove every temporary file or folder in ``directory`` whose writer was killed: a run's
    own and those of the pictures, players and exports drawn there (a ``legdsl plot`` killed
    left ``.figure6.png.tmp-PID-RANDOM/``, which no later run removed)."""
    with contextlib.suppress(OSError):
        for p in directory.iterdir():
            m = _LEFTOVER.match(p.name)
            if m and not _pid_alive(int(m.group("pid"))):
                remove(p)


def file_sha256(path: Path) -> str | None:
    """The SHA-256 of ``path``'s bytes, in hex; None if it cannot be read."""
    try:
        return hashlib.sha256(path.read_bytes()).hexdigest()
    except OSError:
        return None


def write_atomic(path: str | Path, data: str | bytes) -> None:
    """Write ``data`` (text as UTF-8 with ``\\n`` line ends, or bytes) to ``path`` whole."""
    if not isinstance(data, str | bytes):
        raise TypeError(f"write_atomic writes str or bytes, not {type(data).__name__}")
    raw = data.encode("utf-8") if isinstance(data, str) else data
    fd = process_fd(Path(path))
    if fd is not None:  # through the descriptor, at its place: what it printed stays before
        for stream in (sys.stdout, sys.stderr):
            with contextlib.suppress(Exception):
                stream.flush()
        with _refusals_of(Path(path), Path(path)), open(fd, "wb", closefd=False) as f:
            f.write(raw)
        return
    if is_device(Path(path)):
        with atomic_path(path) as device, open(device, "wb") as f:
            f.write(raw)
        return
    with atomic_path(path) as tmp:
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
        with os.fdopen(fd, "wb") as f:
            f.write(raw)
            f.flush()
            os.fsync(f.fileno())
        _normal_mode(tmp)


def instant(label: str) -> None:
    """A named instant inside a writer, for the kill tests: with ``LEGDSL_KILL_AT=N`` in the
    environment the process kills itself (SIGKILL) at its N-th instant, counting from 1."""
    global _instants
    at = os.environ.get("LEGDSL_KILL_AT")
    if not at:
        return
    _instants += 1
    if _instants == int(at):
        os.kill(os.getpid(), signal.SIGKILL)


_instants = 0


def replace_dir(fresh: Path, final: Path) -> None:
    """Put the complete directory ``fresh`` at ``final``, retiring the old one.

    At every instant ``final`` is the old directory or the new one, except between the two
    renames of the swap, when the old one is at ``.NAME.old-PID-RANDOM``; ``recover_dir`` (run
    before any reader or writer of ``final``) puts that back if the writer was killed there.
    """
    for attempt in range(8):
        retired = temp_sibling(final, "old")
        try:
            os.rename(final, retired)
            had_old = True
            instant("retired the old directory")
        except FileNotFoundError:
            had_old = False
        try:
            os.rename(fresh, final)
        except OSError as e:
            if had_old and not final.exists():
                os.rename(retired, final)  # put the old directory back
            elif had_old:
                remove(retired)
            # another writer put its own new directory there in between: retire that one too
            if e.errno in (errno.ENOTEMPTY, errno.EEXIST) and attempt < 7:
                continue
            raise
        break
    instant("swapped the new directory in")
    if had_old:
        remove(retired)
    instant("removed the old directory")


def recover_dir(final: Path) -> None:
    """Repair ``final`` after a writer that was killed: if it is missing, the newest retired
    (``old``) copy is put back; every leftover of a dead writer is then removed."""
    final = _replaced(final)  # a link: its directory is the one swapped (write_module_dir)
    found = leftovers(final.parent, final.name)
    if not final.exists():
        old = [p for p in found if _LEFTOVER.match(p.name).group("tag") == "old"]  # type: ignore[union-attr]
        if old:
            newest = max(old, key=lambda p: p.stat().st_mtime)
            with contextlib.suppress(OSError):
                os.rename(newest, final)
    for p in found:
        if p.exists():
            remove(p)
