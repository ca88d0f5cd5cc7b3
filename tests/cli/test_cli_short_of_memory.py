"""A process short of memory (``ulimit -v``) is told so in one line, whether the shortage
shows as a MemoryError, a library that cannot be mapped (ImportError: "failed to map segment
from shared object", matplotlib loaded for a sweep's heat map) or the import machinery failing
(SystemError: "error return without exception set"); each was a traceback or an "internal
error" somewhere."""

from __future__ import annotations

import pytest
from conftest import CREATURES

import legdsl.cli as cli

UNMAPPED = ImportError(
    "/x/matplotlib/ft2font.so: failed to map segment from shared object", name="ft2font"
)
NULL = SystemError("error return without exception set")


@pytest.mark.parametrize("shortage", [MemoryError(), UNMAPPED, NULL])
@pytest.mark.parametrize("while_", ["loading", "working"])
def test_a_shortage_of_memory_is_one_line(
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
    shortage: BaseException,
    while_: str,
) -> None:
    def short(*_: object) -> object:
        raise shortage

    if while_ == "loading":
        monkeypatch.setattr(cli, "_parser", short)
    else:
        monkeypatch.setattr(cli, "_cmd_show", short)
    assert cli.main(["show", str(CREATURES / "hopper.leg")]) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and err.startswith("legdsl: ")
    assert "ulimit -v" in err and "internal error" not in err
