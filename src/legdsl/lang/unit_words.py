"""Words written as units that legdsl does not know ('kgs', 'm/sec', 'lb', '60°', 'µm'):
whether a word after a number was meant as a unit, and the sentence naming it with the
unit to write where there is one. The parser's syntax errors (``syntax_errors``), the
checker and the command line's values (``units.parse_unit``'s ``UnitError``) all say it
in these words."""

from __future__ import annotations

import difflib
import re

from legdsl.lang.units import UNITS, UnitError, parse_unit

# Units spelt out, or from elsewhere, in the singular (a final 's' is dropped before
# looking), with the symbol to suggest instead (None: no such unit in legdsl).
_UNIT_NAMES: dict[str, str | None] = {
    "sec": "s", "second": "s", "msec": "ms", "millisecond": "ms", "minute": "min",
    "meter": "m", "metre": "m", "centimeter": "cm", "centimetre": "cm", "millimeter": "mm",
    "millimetre": "mm", "kilometer": "km", "kilometre": "km", "kilogram": "kg", "kilo": "kg",
    "gram": "g", "newton": "N", "kilonewton": "kN", "joule": "J", "watt": "W", "hertz": "Hz",
    "degree": "deg", "radian": "rad", "revolution": "rev",
    "hour": None, "hr": None, "h": None, "inch": None, "in": None, "ft": None, "feet": None,
    "lb": None, "mph": None, "kph": None, "kmh": None, "mp": None, "rpm": "rev/min",
    "t": None, "tonne": None, "ton": None, "oz": None, "ounce": None, "pound": None,
    "mi": None, "mile": None, "yd": None, "yard": None, "°": "deg",
}  # fmt: skip
_UNIT_SYMBOL = "|".join(sorted(UNITS, key=len, reverse=True))
_UNIT_RUN = re.compile(rf"(?:{_UNIT_SYMBOL})+")
_UNIT_BY_LOWER = {u.lower(): u for u in UNITS}
_PREFIXES = "kcdmuµμnMG"  # SI prefixes (micro as 'u', 'µ' or Greek 'μ') that run into a symbol as a product would ('mN', 'kJ')


_SUPERSCRIPTS = str.maketrans("⁰¹²³⁴⁵⁶⁷⁸⁹⁻", "0123456789-")


def _plain_unit(word: str) -> str:
    """A unit as typeset ('m·s⁻²', 'N⋅m', 'N.s') in the symbols legdsl reads ('m*s^-2')."""
    for dot in "·⋅.":
        word = word.replace(dot, "*")
    return re.sub(r"[⁻⁰¹²³⁴⁵⁶⁷⁸⁹]+", lambda m: "^" + m.group().translate(_SUPERSCRIPTS), word)


def looks_like_unit(word: str) -> bool:
    """Whether a word after a number was meant as a unit (and is not, say, a property name)."""
    parts = [p for p in re.split(r"[*/^]", _plain_unit(word)) if not p.lstrip("-").isdigit()]
    return bool(parts) and all(
        p.lower().removesuffix("s") in _UNIT_NAMES
        or p.lower().removesuffix("s") in _UNIT_BY_LOWER
        or re.fullmatch(rf"(?:{_UNIT_SYMBOL})+\d*", p) is not None
        or (p[:1] in _PREFIXES and p[1:] in UNITS)
        or difflib.get_close_matches(p, list(UNITS), n=1, cutoff=0.8)
        for p in parts
    )


def unknown_unit(word: str) -> str:
    """The message for a word written as a unit that is none."""
    symbols = ", ".join(UNITS)
    message = (
        f"'{word}' is not a unit legdsl knows: a unit is made of the symbols {symbols} "
        f"joined by '*', '/' and '^', as in '5 m/s' or '60 N*m/rad'"
    )
    suggestion = suggest_unit(word)
    return message + (f"; did you mean '{suggestion}'?" if suggestion else "")


def suggest_unit(word: str) -> str | None:
    """A unit legdsl knows for a misspelt one: 'kgs' -> 'kg', 'm/sec' -> 'm/s', 'Nm' -> 'N*m'."""
    out = []
    for part in re.split(r"([*/^])", _plain_unit(word)):
        singular = part.lower().removesuffix("s")
        undoubled = _undoubled(part)
        if part in UNITS or part in "*/^" or part.lstrip("-").isdigit():
            out.append(part)
        elif undoubled is not None:  # a key pressed twice: 'kgg' is 'kg', not 'kg*g'
            out.append(undoubled)
        elif len(part) > 1 and part.lower() in _UNIT_BY_LOWER:  # 'MS', 'HZ': its case
            out.append(_UNIT_BY_LOWER[part.lower()])
        elif singular in _UNIT_NAMES:
            symbol = _UNIT_NAMES[singular]
            if symbol is None:
                return None
            out.append(symbol)
        elif len(singular) > 1 and singular in _UNIT_BY_LOWER:
            out.append(_UNIT_BY_LOWER[singular])
        elif part[:1] in _PREFIXES and part[1:] in UNITS:
            return None  # a prefix legdsl lacks ('mN'): not 'm*N', a metre-newton
        elif _UNIT_RUN.fullmatch(part):
            out.append("*".join(re.findall(_UNIT_SYMBOL, part)))
        else:
            close = difflib.get_close_matches(part, list(UNITS), n=1, cutoff=0.6)
            if not close:
                return None
            out.append(close[0])
    suggestion = "".join(out)
    try:
        parse_unit(suggestion)
    except UnitError:
        return None
    return suggestion if suggestion != word else None


def _undoubled(part: str) -> str | None:
    """The unit symbol ``part`` is with one doubled letter written once ('kgg', 'ss'), if any."""
    for i in range(1, len(part)):
        if part[i] == part[i - 1] and part[:i] + part[i + 1 :] in UNITS:
            return part[:i] + part[i + 1 :]
    return None
