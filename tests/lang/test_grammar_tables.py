"""The parser's tables kept in legdsl's cache (``legdsl.lang.lalr.kept_parser``): a later
process loads them instead of building the parser again, the loaded parser reads every file as
the built one does (trees and positions), and tables that are damaged, missing or for another
grammar are never used."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import ROOT
from lark import Lark, Token, Tree

from legdsl.lang import lalr

GRAMMAR = (lalr.grammar_dir() / "legdsl.lark").read_text(encoding="utf-8")
FILES = sorted(
    [
        *(ROOT / "creatures").glob("*.leg"),
        *(ROOT / "src" / "legdsl" / "stdlib").glob("*.leg"),
        *(ROOT / "tests" / "good").rglob("*.leg"),
    ]
)


def _kept(cache: Path) -> list[Path]:
    return sorted((cache / "grammar").glob("*.lark-tables"))


def _not_built(monkeypatch: pytest.MonkeyPatch) -> None:
    """Building a parser fails from here on: only loading kept tables can give one."""

    def refuse(self: Lark, *args: object, **kwargs: object) -> None:
        raise AssertionError("the parser was built, not loaded")

    monkeypatch.setattr(lalr.Lark, "__init__", refuse)


def _positions(tree: Tree[Token]) -> list[tuple[object, ...]]:
    found: list[tuple[object, ...]] = []
    for node in tree.iter_subtrees():
        m = node.meta
        found.append((node.data, getattr(m, "line", None), getattr(m, "column", None),
                      getattr(m, "end_line", None), getattr(m, "end_column", None)))  # fmt: skip
        found += [(t.type, t.line, t.column, t.end_line, t.end_column)
                  for t in node.children if isinstance(t, Token)]  # fmt: skip
    return found


def test_a_later_process_loads_the_tables_and_reads_every_file_alike(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    built = lalr.kept_parser(GRAMMAR, tmp_path)
    assert len(_kept(tmp_path)) == 1
    _not_built(monkeypatch)
    loaded = lalr.kept_parser(GRAMMAR, tmp_path)
    assert loaded is not built and len(FILES) >= 40
    for path in FILES:
        text = path.read_text(encoding="utf-8")
        a, b = built.parse(text, start="start"), loaded.parse(text, start="start")
        assert a == b and _positions(a) == _positions(b), path
    value = "circle(center = (0, 5) m, radius = 5 m, turn = left)"
    assert built.parse(value, start="value") == loaded.parse(value, start="value")
    assert [t.name for t in built.terminals] == [t.name for t in loaded.terminals]


@pytest.mark.parametrize("damage", ["cut short", "garbage", "empty"])
def test_damaged_tables_are_built_again_and_kept_whole(tmp_path: Path, damage: str) -> None:
    lalr.kept_parser(GRAMMAR, tmp_path)
    [kept] = _kept(tmp_path)
    whole = kept.read_bytes()
    kept.write_bytes({"cut short": whole[: len(whole) // 2], "garbage": b"\x80\x05not a pickle",
                      "empty": b""}[damage])  # fmt: skip
    parser = lalr.kept_parser(GRAMMAR, tmp_path)
    assert parser.parse("creature c {}", start="start") is not None
    with kept.open("rb") as f:  # built again and kept, whole (pickled afresh: not byte-equal)
        Lark.load(f)
    assert [p.name for p in kept.parent.iterdir()] == [kept.name]  # no temporary file left


def test_a_cache_that_cannot_be_written_only_builds(tmp_path: Path) -> None:
    cache = tmp_path / "a file, not a folder"
    cache.write_text("")
    parser = lalr.kept_parser(GRAMMAR, cache)
    assert parser.parse("creature c {}", start="start") is not None


def test_an_edited_grammar_never_loads_the_old_tables(tmp_path: Path) -> None:
    lalr.kept_parser(GRAMMAR, tmp_path)
    edited = GRAMMAR + "\n// an edit\n"
    lalr.kept_parser(edited, tmp_path)
    assert len(_kept(tmp_path)) == 2


def test_with_no_home_to_keep_them_in_the_parser_is_built(monkeypatch: pytest.MonkeyPatch) -> None:
    """No HOME and a user the system does not know (a container's bare uid): ``Path.home()``
    raises RuntimeError, which the first parse must not pass on as a traceback."""
    monkeypatch.delenv("LEGDSL_CACHE", raising=False)
    monkeypatch.delenv("XDG_CACHE_HOME", raising=False)

    def no_home() -> Path:
        raise RuntimeError("Could not determine home directory.")

    monkeypatch.setattr(Path, "home", staticmethod(no_home))
    parser = lalr.lark_parser.__wrapped__()
    assert parser.parse("creature c {}", start="start") is not None
