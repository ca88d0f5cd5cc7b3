"""Files named where a .leg file belongs that are no text: a run's trajectory.npz, an image,
a program. Told before the file is parsed, by what it looks like, and never shown: its bytes
echoed as a source line would write raw binary to the terminal.
"""

from __future__ import annotations

# Control bytes no text holds (a tab, a line end, a form feed and ESC, as pasted from a
# coloured terminal, are left to the parser, which points at a stray one)
_BINARY = frozenset(range(0x20)) - {0x09, 0x0A, 0x0B, 0x0C, 0x0D, 0x1B}
# A text file with a stray control character or two is text: the parser points at them
_STRAY = 3

# What a file is, by its first bytes (the files legdsl writes first)
_MAGIC: tuple[tuple[bytes, str], ...] = (
    (b"PK\x03\x04", "a zip archive (as a run's trajectory.npz is)"),
    (b"PK\x05\x06", "a zip archive (as a run's trajectory.npz is)"),
    (b"\x93NUMPY", "a NumPy array (.npy)"),
    (b"\x89PNG", "a PNG image"),
    (b"\xff\xd8\xff", "a JPEG image"),
    (b"GIF8", "a GIF image"),
    (b"glTF", "a binary glTF model (.glb)"),
    (b"PXR-USDC", "a USD scene (.usdc)"),
    (b"%PDF", "a PDF document"),
    (b"\x1f\x8b", "a gzip archive"),
    (b"\x89HDF", "an HDF5 file"),
    (b"SQLite format 3", "an SQLite database"),
    (b"\x7fELF", "a program (ELF)"),
    (b"MZ", "a Windows program"),
    (b"\xcf\xfa\xed\xfe", "a program (Mach-O)"),
    (b"\xca\xfe\xba\xbe", "a program (Mach-O) or a Java class"),
)


_UTF16 = "UTF-16 text"


def refusal(name: str, data: bytes) -> str | None:
    """The sentence for a file named ``name`` whose bytes are ``data`` if it is no text."""
    kind = not_text(data)
    if kind is None:
        return None
    if kind == _UTF16:
        return f"{name} is UTF-16 text, which legdsl does not read: save it as UTF-8 in your editor"
    return (
        f"{name} is not a text file (a .leg file is text): it looks like {kind}; name a .leg file"
    )


def not_text(data: bytes) -> str | None:
    """What ``data``, a file's bytes, looks like if it is no text ('a zip archive (as a run's
    trajectory.npz is)', 'UTF-16 text', 'binary data'); None for text, stray control
    characters in it (a NUL, a bell) included."""
    control = sum(1 for b in data if b in _BINARY)
    if not control:
        return None
    if data[4:8] == b"ftyp":
        return "a video (.mp4)"
    if data[:4] == b"RIFF" and data[8:12] == b"WEBP":
        return "a WebP image"
    kind = next((said for magic, said in _MAGIC if data.startswith(magic)), None)
    if kind is not None:
        return kind
    if control < _STRAY:
        return None
    zeros = data.count(0)
    if data[:2] in (b"\xff\xfe", b"\xfe\xff") or (zeros > len(data) // 3 and _utf16(data)):
        return _UTF16
    return "binary data"


def _utf16(data: bytes) -> bool:
    """Whether ``data`` reads as UTF-16 text of ASCII: every other byte zero."""
    head = data[:4096]
    return max(head[0::2].count(0), head[1::2].count(0)) >= 0.9 * (len(head) // 2)
