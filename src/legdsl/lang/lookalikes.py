"""Characters that look like ASCII ones and are not: a Cyrillic 'а' in a name, the Kelvin
sign 'K', an em dash or a typographic minus for '-', full-width parentheses, the one
character '㎧' for 'm/s', a line separator for a line break. The user sees the character
they meant, so each is named (its Unicode name and code point) with the ASCII to write.
"""

from __future__ import annotations

import unicodedata

# Letters of other scripts drawn like Latin ones, which Unicode's compatibility
# normalisation (NFKC) leaves as they are; the other look-alikes it folds to ASCII.
_LETTERS = {
    **dict(zip("аеорсухіјѕԁһӏԛԝмкԍ", "aeopcyxijsdhlqwmkg", strict=True)),  # Cyrillic
    **dict(zip("АВЕКМНОРСТХЅІЈҮԌ", "ABEKMHOPCTXSIJYG", strict=True)),
    **dict(zip("ΑΒΕΖΗΙΚΜΝΟΡΤΥΧϹοικνραυχγϲϳ", "ABEZHIKMNOPTYXCoikvpauxycj", strict=True)),  # Greek
}
_SLASHES = {"∕": "/", "⁄": "/"}  # NFKC folds '㎧' to 'm∕s', with a division slash
# Dashes written for a minus sign (NFKC keeps them; a wave dash is no minus look-alike).
_MINUSES = "\u2010\u2011\u2012\u2013\u2014\u2015\u2212\ufe58\ufe63\uff0d"
# What NFKC may fold to ASCII without misleading: not 'º' (an ordinal, written for '°')
# to 'o', nor a superscript '²' to '2' (both told elsewhere).
_FOLDED = ("Lu", "Ll", "Nd", "Ps", "Pe", "Po", "Pd", "Sm", "So", "Sc")


def named(ch: str) -> str:
    """'CYRILLIC SMALL LETTER A, U+0430'."""
    return f"{unicodedata.name(ch, 'a character without a name')}, U+{ord(ch):04X}"


def ascii_for(ch: str) -> str | None:
    """The ASCII that ``ch`` looks like ('-' for a dash, 'a' for a Cyrillic 'а', 'm/s'
    for '㎧'), or None."""
    if ch.isascii():
        return None
    if ch in _MINUSES:
        return "-"
    if ch in _LETTERS or ch in _SLASHES:
        return _LETTERS.get(ch) or _SLASHES[ch]
    if unicodedata.category(ch) not in _FOLDED:
        return None
    folded = "".join(_SLASHES.get(c, c) for c in unicodedata.normalize("NFKC", ch))
    return folded if folded.isascii() and folded.isprintable() and folded.strip() else None


def minus_sign(ch: str, example: str) -> str:
    """The sentence for a dash written as a minus sign, with ``example`` written well."""
    what = "a typographic minus sign" if ch == "−" else f"a dash ({named(ch)}), not a minus sign"
    return f"'{ch}' is {what}: write the ASCII '-', as in '{example}'"


def lookalike(ch: str) -> str | None:
    """The sentence for a character that looks like ASCII and is not (or an invisible line
    break), saying what it is and what to write; None for any other character."""
    if unicodedata.category(ch) in ("Zl", "Zp"):
        return (
            f"an invisible character ({named(ch)}) stands here: replace it with an ordinary "
            "line break"
        )
    written = ascii_for(ch)
    if written is None:
        return None
    if written == "-":
        return minus_sign(ch, "-0.2 m")
    if len(written) > 1:
        return f"'{ch}' is one character ({named(ch)}) for '{written}': write the ASCII '{written}'"
    return f"'{ch}' is {named(ch)}, not the ASCII '{written}' it looks like: write '{written}'"


def letter_of_name(ch: str) -> str:
    """The sentence for a letter outside ASCII in a name."""
    rule = "names are made of the letters a-z and A-Z, digits and '_'"
    written = ascii_for(ch)
    if written is not None and (written.isalnum() or written == "_"):
        return f"{lookalike(ch)} ({rule})"
    return f"'{ch}' is not a letter of a name: {rule} (comments and strings may hold any text)"


def odd_letter_in_word(text: str, pos: int) -> int | None:
    """The offset of the first letter outside ASCII in the word that starts at ``pos`` with
    ASCII ('bοdy' with a Greek omicron, read as a name 'b' the parser did not expect there),
    or None."""
    if pos >= len(text) or not (text[pos].isascii() and (text[pos].isalpha() or text[pos] == "_")):
        return None
    end = pos
    while end < len(text) and (text[end].isalnum() or text[end] == "_"):
        if not text[end].isascii() and text[end].isalpha():
            return end
        end += 1
    return None
