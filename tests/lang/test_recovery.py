"""The parser reads past a misspelt unit so that the file's other mistakes are found too,
and reports what cannot be read (not a number, not UTF-8) with its line and a caret."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.check.source import check_file
from legdsl.lang.errors import LegError
from legdsl.lang.parser import MAX_REPAIRS, MAX_SOURCE_BYTES, parse, parse_file

TWO_TYPOS = """\
creature a {
  planar
  body trunk free { mass 5 kgg  inertia 0.03 kg*m^2 }
  body arm on trunk via revolute shoulder at (0 m, 0 m) {
    length 0.3 m  mass 1 kg  inertia 0.01 kg*m^^2
  }
  body leg on trunk via prismatic slide at (0 m, 0 m) { length 0.5 m  mass 2 kgs  inertia 0.01 kg*m^2 }
}
"""


def test_without_recovery_every_misspelt_unit_is_raised_at_once() -> None:
    with pytest.raises(LegError) as caught:
        parse(TWO_TYPOS.replace("kg*m^^2", "kg*m^2"), "a.leg")
    spans = [(d.span.line, d.span.col) for d in caught.value.diagnostics]
    assert spans == [(3, 28), (7, 78)]
    assert "did you mean 'kg'?" in caught.value.diagnostics[0].message


def test_a_mistake_that_cannot_be_read_past_ends_the_parse_after_the_units() -> None:
    with pytest.raises(LegError) as caught:
        parse(TWO_TYPOS, "a.leg")
    found = [(d.span.line, d.span.col, d.message[:16]) for d in caught.value.diagnostics]
    assert found == [(3, 28, "'kgg' is not a u"), (5, 47, "unexpected '^'; ")]


def test_with_recovery_the_tree_carries_them_and_reads_the_suggested_unit() -> None:
    tree = parse(TWO_TYPOS.replace("kg*m^^2", "kg*m^2"), "a.leg", recover=True)
    assert [(d.span.line, d.span.col) for d in tree.pending] == [(3, 28), (7, 78)]
    assert tree.creatures[0].name.name == "a"


def test_the_checker_reports_a_misspelt_unit_beside_its_own_findings(tmp_path: Path) -> None:
    leg = tmp_path / "a.leg"
    leg.write_text(TWO_TYPOS.replace("kg*m^^2", "kg*m^2").replace("mass 1 kg", "mass -1 kg"))
    with pytest.raises(LegError) as caught:
        check_file(leg)
    messages = [(d.span.line, d.message.split(":")[0]) for d in caught.value.diagnostics]
    assert messages == [
        (3, "'kgg' is not a unit legdsl knows"),
        (5, "the mass of body 'arm' must be positive"),
        (7, "'kgs' is not a unit legdsl knows"),
    ]


def test_a_file_that_is_not_utf8_shows_the_line_and_a_caret(tmp_path: Path) -> None:
    leg = tmp_path / "a.leg"
    leg.write_bytes(b"creature a {\r\n  planar \xc3\xa9 \xff\r\n}\n")
    with pytest.raises(LegError) as caught:
        parse_file(leg)
    shown = caught.value.render().splitlines()
    assert shown[0].startswith(f"{leg}:2:12: error: the file is not UTF-8 text")
    assert "byte 0xff" in shown[0]
    assert shown[1:] == ["      planar é \ufffd", "               ^"]


@pytest.mark.parametrize("name", ["/dev/zero", "big.csv"])
def test_a_device_or_a_file_far_larger_than_a_leg_file_is_refused_unread(
    tmp_path: Path, name: str
) -> None:
    """Read no further than ``MAX_SOURCE_BYTES``: ``legdsl check /dev/zero`` read until memory
    ran out, then advised to raise the limit; a 90 MB file took 28 s and 730 MB."""
    path = Path(name) if name.startswith("/") else tmp_path / name
    if path.parent == tmp_path:
        with path.open("wb") as f:
            f.truncate(MAX_SOURCE_BYTES + 1)  # a sparse file: no time or disk to write it
    with pytest.raises(LegError) as caught:
        parse_file(path)
    (d,) = caught.value.diagnostics
    assert d.span.file == str(path)
    assert d.message.startswith("this holds more than 8 MB, far more than a .leg file")
    assert d.message.endswith("Name the .leg file")


@pytest.mark.parametrize(
    ("unit", "suggestion"),
    [
        ("m·s⁻²", "; did you mean 'm*s^-2'?"),  # as typeset: a dot and superscripts
        ("N⋅s/m", "; did you mean 'N*s/m'?"),
        # a prefix legdsl lacks: it suggested 'm*N*s/m', a metre-newton; now the value, and
        # the metre-newton as the other reading
        (
            "mN*s/m",
            ": it has no prefix 'm' (milli); it writes forces (its 'mN') in N, kN: write '0.001 N*s/m'"
            ", or '1 N*m*s/m' if the 'm' meant metres",
        ),
        ("kJ", ": it has no prefix 'k' (kilo): write '1000 J'"),  # was "unexpected ..."
    ],
)
def test_a_typeset_or_prefixed_unit_is_named_and_never_misread(unit: str, suggestion: str) -> None:
    text = f"creature a {{\n  planar\n  body trunk free {{ mass 5 kg  inertia 1 {unit} }}\n}}\n"
    with pytest.raises(LegError) as caught:
        parse(text, "a.leg")
    (d,) = caught.value.diagnostics
    assert d.message.startswith(f"'{unit}' is not a unit legdsl knows: ")
    if suggestion.startswith(": it has no prefix"):
        assert d.message == f"'{unit}' is not a unit legdsl knows" + suggestion
    else:
        assert d.message.endswith("'60 N*m/rad'" + suggestion)
    assert (d.span.line, d.span.col) == (3, 42)


FOREIGN_SPELLINGS = """\
creature a {
  planar
  gravity 9.81 m s^-2
  body trunk free { mass 0x10 kg  inertia 0.03 kg*m^2 }
  body shank on trunk via prismatic leg { mass 1_000 g  inertia 0.01 kg*m/(s^0) }
  actuator leg_spring on leg spring(k = 1000 N/m, b = 200 N s/m)
  actuator leg_servo on leg servo(kp = 1000 N/m**1, max = -5 N)
}
"""


def test_units_and_numbers_as_other_languages_write_them_are_each_named_once(
    tmp_path: Path,
) -> None:
    """Spaces, parentheses and '**' in a unit, hexadecimal and '_' in a number: one message
    each, at the unit or number, with the legdsl spelling; the parse and the check go on
    (the checker's own finding on line 7 shows), with no follow-on message."""
    leg = tmp_path / "a.leg"
    leg.write_text(FOREIGN_SPELLINGS)
    with pytest.raises(LegError) as caught:
        check_file(leg)
    found = [(d.span.line, d.span.col, d.message) for d in caught.value.diagnostics]
    assert [(line, col) for line, col, _ in found] == [
        (3, 16), (4, 26), (5, 48), (5, 70), (6, 59), (7, 45), (7, 59)
    ]  # fmt: skip
    messages = [m for _, _, m in found]
    assert messages[0].endswith("write 'm/s^2', not 'm s^-2'")
    assert messages[1].endswith("numbers are plain decimals, so write '16'")
    assert messages[2].endswith("digits are written without '_', as in '1000'")
    assert messages[3].endswith("write 'kg*m/s^0', not 'kg*m/(s^0)'")
    assert messages[4].endswith("write 'N*s/m', not 'N s/m'")
    assert messages[5].endswith("write 'N/m^1', not 'N/m**1'")
    assert messages[6] == "'max' must not be negative"


def test_a_hexadecimal_number_too_long_to_spell_in_decimal_is_still_named() -> None:
    text = "0x1234567890abcdef1234567890"
    source = f"creature a {{\n  planar\n  body trunk free {{ mass {text} kg }}\n}}\n"
    with pytest.raises(LegError) as caught:
        parse(source, "a.leg")
    (d,) = caught.value.diagnostics
    assert d.message.startswith(f"'{text}' is not a number legdsl reads: numbers are plain")


def _many_typos(count: int) -> str:
    params = "".join(f"  param p{i} = {i} kgg\n" for i in range(count))
    return (
        "creature a {\n  planar\n  body trunk free { mass 5 kg  inertia 0.03 kg*m^2 }\n"
        "  body extra on nowhere via fixed fx { mass 1 kg  inertia 0.01 kg*m^2 }\n"
        "  body leg on trunk via prismatic slide at (0 m, 0 m) { mass 1 kg  inertia 1 kg*m^2 }\n"
        "  actuator push on slide spring(k = 100 N/m, b = 1 N*s/m, rest = 0 m)\n}\n"
        f"controller c {{\n{params}  table {{ state A on time > 0 s: push.rest = 0 m }}\n}}\n"
    )


def _line(text: str, part: str) -> int:
    return text[: text.index(part)].count("\n") + 1


@pytest.mark.parametrize("count", [MAX_REPAIRS, MAX_REPAIRS + 1, 3 * MAX_REPAIRS])
def test_past_the_units_it_names_the_check_goes_on_and_says_how_many_were_not_shown(
    tmp_path: Path, count: int
) -> None:
    """A file converted from another tool may carry one misspelling throughout: past the
    first MAX_REPAIRS, the unknown parent body before them was dropped, and nothing said the
    list was cut. The parser reads past the rest at once; the checker's findings stay."""
    text = _many_typos(count)
    leg = tmp_path / "a.leg"
    leg.write_text(text)
    with pytest.raises(LegError) as caught:
        check_file(leg)
    found = caught.value.diagnostics
    assert found[0].message.startswith("unknown parent body 'nowhere'")
    units = [d for d in found if d.message.startswith("'kgg' is not a unit legdsl knows")]
    assert len(units) == min(count, MAX_REPAIRS)
    unshown = count - len(units)
    assert len(found) == 1 + len(units) + (1 if unshown else 0)
    if unshown:
        last = found[-1]
        assert last.message.startswith(
            f"{unshown} more misspelt unit{'s are' if unshown > 1 else ' is'} not shown, from "
            f"line {_line(text, f'p{MAX_REPAIRS} =')} on (legdsl names the first {MAX_REPAIRS}"
        )
        assert (last.span.line, last.span.col) == (text.count("\n"), 2)  # after the last '}'


def test_a_syntax_error_past_the_units_it_names_is_shown_before_the_count() -> None:
    text = _many_typos(MAX_REPAIRS + 2).replace("  table", "  table table")
    with pytest.raises(LegError) as caught:
        parse(text, "a.leg")
    found = [(d.span.line, d.message[:22]) for d in caught.value.diagnostics]
    assert found[MAX_REPAIRS:] == [
        (_line(text, "table table"), "unexpected 'table'; ex"),
        (text.count("\n"), "2 more misspelt units "),
    ]
