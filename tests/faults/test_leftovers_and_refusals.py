"""A killed picture's folder left behind, and a refused write named by its temporary name.

A ``legdsl plot`` killed (kill -KILL) left ``.figure6.png.tmp-PID-RANDOM/`` in the run
directory, which no later plot or run removed (docs/runtime.md: "The next run into the
directory removes the temporary files left behind"). On a read-only disk, removing the
temporary file after the refused write failed too (EROFS even for a missing file), and that
error, naming ``.animation.html.tmp-27114-70b89766.html``, replaced the write's own, which
names the file asked for. ``legdsl plot``'s refusals named ``--output`` where its help shows
``-o``, and named it where no -o was given.
"""

from __future__ import annotations

import errno
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import CREATURES

from legdsl.cli import main
from legdsl.files import atomic_path, atomic_same_name, writing_alone
from legdsl.sim.trajectory import empty


def _dead_pid() -> int:
    proc = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True, check=True)  # fmt: skip
    return int(proc.stdout)


def _left(directory: Path, name: str, pid: int) -> Path:
    """What a writer of ``name`` killed leaves: its hidden folder, a half picture in it."""
    folder = directory / f".{name}.tmp-{pid}-8dfbe802"
    folder.mkdir(parents=True)
    (folder / name).write_bytes(b"\x89PNG half")
    return folder


def test_a_killed_drawings_folder_is_removed_by_the_next_drawing(tmp_path: Path) -> None:
    dead, alive = _left(tmp_path, "figure6.png", _dead_pid()), _left(tmp_path, "figure6.png", 1)
    with atomic_same_name(tmp_path / "figure6.png") as picture:
        picture.write_bytes(b"\x89PNG whole")
    assert not dead.exists()
    assert alive.exists()  # its writer (pid 1) is running: not a leftover
    assert (tmp_path / "figure6.png").read_bytes() == b"\x89PNG whole"


def test_a_run_into_the_directory_removes_every_killed_writers_leftover(tmp_path: Path) -> None:
    pid = _dead_pid()
    folder = _left(tmp_path, "figure6.png", pid)
    video = tmp_path / f".v.mp4.tmp-{pid}-0123abcd.mp4"
    video.write_bytes(b"half")
    mine = tmp_path / "notes.txt"
    mine.write_text("the user's")
    with writing_alone(tmp_path):  # as a run writing its files there
        pass
    assert not folder.exists() and not video.exists()
    assert mine.read_text() == "the user's"


@pytest.fixture
def read_only(monkeypatch: pytest.MonkeyPatch) -> None:
    """A read-only disk: making or removing a hidden name fails with EROFS (even a missing
    one, as Linux checks the mount before the name)."""

    def refused(path: Path) -> OSError:
        return OSError(errno.EROFS, os.strerror(errno.EROFS), str(path))

    unlink, mkdir = Path.unlink, Path.mkdir

    def no_unlink(self: Path, missing_ok: bool = False) -> None:
        if self.name.startswith("."):
            raise refused(self)
        unlink(self, missing_ok=missing_ok)

    def no_mkdir(self: Path, *args: object, **kwargs: object) -> None:
        if self.name.startswith("."):
            raise refused(self)
        mkdir(self, *args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(Path, "unlink", no_unlink)
    monkeypatch.setattr(Path, "mkdir", no_mkdir)


@pytest.mark.usefixtures("read_only")
def test_a_refused_write_names_the_file_asked_for(tmp_path: Path) -> None:
    out = tmp_path / "animation.html"
    with pytest.raises(OSError) as caught, atomic_path(out, suffix=".html") as tmp:
        raise OSError(errno.EROFS, os.strerror(errno.EROFS), str(tmp))
    assert caught.value.filename == str(out)
    with pytest.raises(OSError) as caught, atomic_same_name(tmp_path / "figure6.png"):
        pass
    assert caught.value.filename == str(tmp_path / "figure6.png")


def _run(directory: Path) -> Path:
    tr = empty(
        40, 3, 3, 1, 1, q_names=("x", "z", "pitch"), v_names=("x", "z", "pitch"),
        contact_names=("toe",), leg_names=("main",), leg_feet=(0,), total_mass=1.0,
    )  # fmt: skip
    tr.t[:] = np.arange(40) * 0.01
    tr.save(directory)
    info = {"source": str(CREATURES / "kangaroo.leg"), "creature": "kangaroo", "status": "ok"}
    (directory / "run.json").write_text(__import__("json").dumps(info))
    return directory


def test_plots_refusals_name_o_as_its_help_does(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    run = _run(tmp_path / "run")
    (tmp_path / "afile").write_text("")
    assert main(["plot", str(run), "--output", str(tmp_path / "afile" / "x.png")]) == 2
    assert f"legdsl: -o {tmp_path / 'afile' / 'x.png'}: " in capsys.readouterr().err
    assert main(["plot", str(run), "-o", str(tmp_path / "x.txt")]) == 2
    assert f"legdsl: -o {tmp_path / 'x.txt'}: this writes a PNG" in capsys.readouterr().err
    (run / "figure6.png").mkdir()  # no -o: the default picture is named, and no option
    assert main(["plot", str(run)]) == 2
    err = capsys.readouterr().err
    assert f"legdsl: {run / 'figure6.png'}: this is a directory" in err
    assert "--output" not in err and "draw it elsewhere: -o FILE.png" in err
