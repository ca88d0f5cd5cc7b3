"""A file that is no text named where a .leg file belongs (a run's trajectory.npz, an image,
a program) was parsed, its raw bytes echoed to the terminal as the source line of an
'unexpected name' error; it is refused by what it looks like, its bytes never shown."""

from __future__ import annotations

import io
import zipfile
from pathlib import Path

import pytest

from legdsl.cli import main
from legdsl.lang.errors import LegError
from legdsl.lang.parser import parse_file


def _told(path: Path) -> str:
    with pytest.raises(LegError) as info:
        parse_file(path)
    assert len(info.value.diagnostics) == 1
    return info.value.render()


def test_a_zip_archive_is_refused_as_no_text(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w") as z:
        z.writestr("t.npy", b"\x93NUMPY\x01\x00" + bytes(range(256)))
    path = tmp_path / "trajectory.npz"
    path.write_bytes(buffer.getvalue())
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"{path}: error: {path} is not a text file (a .leg file is text): it ")
    assert "a zip archive (as a run's trajectory.npz is)" in err
    assert all(c in "\n" or c >= " " for c in err)


@pytest.mark.parametrize(
    ("head", "kind"),
    [
        (b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR", "a PNG image"),
        (b"\x7fELF\x02\x01\x01\x00\x00\x00\x00", "a program (ELF)"),
        (b"\x00\x01\x02\x03\x04\x05\x06\x07", "binary data"),
    ],
)
def test_binary_files_are_named_by_what_they_look_like(
    tmp_path: Path, head: bytes, kind: str
) -> None:
    path = tmp_path / "f.leg"
    path.write_bytes(head + b"creature\n\xff\xfe\x01")
    told = _told(path)
    assert (
        told
        == f"{path}: error: {path} is not a text file (a .leg file is text): it looks like {kind}; name a .leg file"
    )


def test_utf16_text_is_told_to_be_saved_as_utf8(tmp_path: Path) -> None:
    path = tmp_path / "u.leg"
    path.write_bytes("creature a {\n  planar\n}\n".encode("utf-16-le"))
    assert "is UTF-16 text, which legdsl does not read: save it as UTF-8" in _told(path)


def test_a_stray_control_character_in_text_is_pointed_at_and_not_shown(tmp_path: Path) -> None:
    path = tmp_path / "a.leg"
    path.write_bytes(b"creature a {\n  planar\x00\x1b[31m\n}\n")
    told = _told(path)
    assert told.startswith(f"{path}:2:9: error: a control character (U+0000) stands here")
    assert "\x00" not in told and "\x1b" not in told
    assert "planar\ufffd\ufffd[31m" in told
