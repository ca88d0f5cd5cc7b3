"""Units: parsing unit strings, dimensions, and conversion to SI.

A dimension is a tuple of exponents over (mass, length, time, angle). Angle is
kept as its own dimension so that a linear spring (N/m) on a revolute joint,
or a length where an angle belongs, is caught; ``rad`` is its SI unit and
``deg`` converts to it.
"""

from __future__ import annotations

import difflib
import itertools
import math
import re
from dataclasses import dataclass

from legdsl.lang.numbers_said import apart as apart
from legdsl.lang.numbers_said import out_of_range as out_of_range
from legdsl.lang.numbers_said import percentage
from legdsl.lang.unit_tables import _FOREIGN, _PREFIX_FACTORS, _UNIT_NAMES

Dim = tuple[int, int, int, int]  # exponents of kg, m, s, rad

DIMENSIONLESS: Dim = (0, 0, 0, 0)

# symbol -> (factor to SI, dimension)
UNITS: dict[str, tuple[float, Dim]] = {
    "kg": (1.0, (1, 0, 0, 0)),
    "g": (1e-3, (1, 0, 0, 0)),
    "m": (1.0, (0, 1, 0, 0)),
    "cm": (1e-2, (0, 1, 0, 0)),
    "mm": (1e-3, (0, 1, 0, 0)),
    "km": (1e3, (0, 1, 0, 0)),
    "s": (1.0, (0, 0, 1, 0)),
    "ms": (1e-3, (0, 0, 1, 0)),
    "min": (60.0, (0, 0, 1, 0)),
    "Hz": (1.0, (0, 0, -1, 0)),
    "kHz": (1e3, (0, 0, -1, 0)),
    "N": (1.0, (1, 1, -2, 0)),
    "kN": (1e3, (1, 1, -2, 0)),
    "J": (1.0, (1, 2, -2, 0)),
    "W": (1.0, (1, 2, -3, 0)),
    "rad": (1.0, (0, 0, 0, 1)),
    "deg": (math.pi / 180.0, (0, 0, 0, 1)),
    "rev": (2.0 * math.pi, (0, 0, 0, 1)),
}

# Names for the dimensions a property may ask for, with an example unit for messages.
KINDS: dict[str, tuple[Dim, str]] = {
    "dimensionless": (DIMENSIONLESS, "no unit"),
    "mass": ((1, 0, 0, 0), "kg"),
    "length": ((0, 1, 0, 0), "m"),
    "time": ((0, 0, 1, 0), "s"),
    "angle": ((0, 0, 0, 1), "deg"),
    "velocity": ((0, 1, -1, 0), "m/s"),
    "angular velocity": ((0, 0, -1, 1), "rad/s"),
    "acceleration": ((0, 1, -2, 0), "m/s^2"),
    "force": ((1, 1, -2, 0), "N"),
    "torque": ((1, 2, -2, 0), "N*m"),
    "moment of inertia": ((1, 2, 0, 0), "kg*m^2"),
    "linear stiffness": ((1, 0, -2, 0), "N/m"),
    "linear damping": ((1, 0, -1, 0), "N*s/m"),
    "angular stiffness": ((1, 2, -2, -1), "N*m/rad"),
    "angular damping": ((1, 2, -1, -1), "N*m*s/rad"),
    "frequency": ((0, 0, -1, 0), "Hz"),
}

_ATOM = re.compile(r"([A-Za-z]+)(?:\^(-?\d+))?")


class UnitError(ValueError):
    """A unit string that names no known unit; it reads as the sentence a file's unknown
    unit gets ('hz' is not a unit legdsl knows: ...; did you mean 'Hz'?), so that the
    command line's values (``--dt 0.4MS``, ``--set speed=1m/sec``) are told the same."""

    def __init__(self, text: str) -> None:
        super().__init__(text)
        self.text = text

    def __str__(self) -> str:
        return unknown_unit(self.text)


def parse_unit(text: str) -> tuple[float, Dim]:
    """Parse ``N*m*s/rad`` into (factor to SI, dimension); ``/`` divides the next atom only."""
    factor = 1.0
    dim = [0, 0, 0, 0]
    sign = 1
    pos = 0
    while True:
        match = _ATOM.match(text, pos)
        if not match or match.group(1) not in UNITS:
            raise UnitError(text)
        scale, base = UNITS[match.group(1)]
        if len((match.group(2) or "").lstrip("-")) > 3:  # 'm^100000': no unit has it
            raise UnitError(text)
        power = sign * int(match.group(2) or 1)
        try:
            factor *= scale**power
        except OverflowError:  # '1 km^200': past a double, so the number reads as too large
            factor = math.inf
        for i in range(4):
            dim[i] += base[i] * power
        pos = match.end()
        if pos == len(text):
            return factor, (dim[0], dim[1], dim[2], dim[3])
        if text[pos] not in "*/":
            raise UnitError(text)
        sign = 1 if text[pos] == "*" else -1
        pos += 1


def unit_pattern() -> str:
    """A regular expression for a unit string made of the known unit symbols."""
    names = "|".join(sorted(UNITS, key=len, reverse=True))
    atom = rf"(?:{names})(?:\^-?\d+)?(?![A-Za-z0-9_])"
    return rf"{atom}(?:[*/]{atom})*"


def describe(dim: Dim) -> str:
    """A human name for a dimension, e.g. 'linear stiffness (N/m)'; one no kind names in the
    units people write it in: with a newton where it has one ('N*m*s', 'N*m/s'), else in
    base units ('kg*m^-1')."""
    for name, (kind_dim, example) in KINDS.items():
        if kind_dim == dim:
            return name if name == "dimensionless" else f"{name} ({example})"
    if (newtons := newton_unit(dim)) is not None:
        return newtons
    parts = []
    for symbol, exp in zip(("kg", "m", "s", "rad"), dim, strict=True):
        if exp:
            parts.append(symbol if exp == 1 else f"{symbol}^{exp}")
    return "*".join(parts) or "dimensionless"


def newton_unit(dim: Dim) -> str | None:
    """A dimension with one kilogram and a time of s^-1 or less in newtons, as the gains are
    written ('N*m*s' for kg*m^2/s, 'N*m/s' for kg*m^2/s^3, 'N*s/m/rad'); None for another
    (a mass, an inertia: no newton in them)."""
    kg, m, s, rad = dim
    if kg != 1 or s > -1:
        return None
    rest = tuple(zip(("m", "s", "rad"), (m - 1, s + 2, rad), strict=True))
    up = "".join(f"*{n}" if e == 1 else f"*{n}^{e}" for n, e in rest if e > 0)
    down = "".join(f"/{n}" if e == -1 else f"/{n}^{-e}" for n, e in rest if e < 0)
    return f"N{up}{down}"


def si_unit(dim: Dim) -> str:
    """The SI unit of a dimension as ``--set`` reads it (``kg*m^2/s^2/rad``; empty if none)."""
    symbols = ("kg", "m", "s", "rad")
    up = [s if e == 1 else f"{s}^{e}" for s, e in zip(symbols, dim, strict=True) if e > 0]
    down = [s if e == -1 else f"{s}^{-e}" for s, e in zip(symbols, dim, strict=True) if e < 0]
    if not up:
        return "*".join(f"{s}^{e}" for s, e in zip(symbols, dim, strict=True) if e)
    return "*".join(up) + "".join(f"/{d}" for d in down)


def named_si_unit(dim: Dim) -> str:
    """The SI unit of a dimension with a newton in it where it has one, as people write it:
    ``N*m/rad`` for kg*m^2/s^2/rad, ``N*s/m`` for kg/s; ``si_unit`` for the rest (a mass, an
    inertia: no time in them)."""
    return newton_unit(dim) or si_unit(dim)


def unit_for(dim: Dim) -> str:
    """A unit to write for a dimension: the example unit of its kind, else its SI unit."""
    for kind_dim, example in KINDS.values():
        if kind_dim == dim:
            return "" if dim == DIMENSIONLESS else example
    return si_unit(dim)


def a_kind(dim: Dim, unit: str = "") -> str:
    """'a velocity (m/s)', 'an angle (deg)', 'dimensionless', 'a quantity in m^-1*rad'; with
    ``unit`` (of ``dim``: the file's), that unit in place of the kind's ('an angle (rad)')."""
    if dim == DIMENSIONLESS:
        return "dimensionless"
    name = describe(dim)
    if all(kind_dim != dim for kind_dim, _ in KINDS.values()):
        return f"a quantity in {unit or named_si_unit(dim)}"
    if unit:
        name = f"{name.partition(' (')[0]} ({unit})"
    return ("an " if name[0] in "aeiou" else "a ") + name


@dataclass(frozen=True)
class Quantity:
    """A number converted to SI, with its dimension; ``unitless`` when written without a unit."""

    value: float
    dim: Dim
    unitless: bool = False


# Words written as units that legdsl does not know ('kgs', 'm/sec', 'lb', '60°', 'µm'):
# whether a word after a number was meant as a unit, and the sentence naming it.
_UNIT_SYMBOL = "|".join(sorted(UNITS, key=len, reverse=True))


def _symbol_run(text: str) -> bool:
    """Whether ``text`` is unit symbols run together ('kgm', 'Nms'): read position by position
    (as '(?:kg|m|mm|...)+' a regular expression takes time exponential in a long run of
    'm's that ends in another letter)."""
    reached = {0}
    for i in range(len(text)):
        if i in reached:
            reached.update(i + len(u) for u in UNITS if text.startswith(u, i))
    return bool(text) and len(text) in reached


def _symbols_and_power(text: str) -> tuple[str, str] | None:
    """'kgm2' as ('kgm', '2'): symbols run together and a power, or None."""
    found = re.fullmatch(r"([A-Za-z]+)(\d+)", text)
    return (found[1], found[2]) if found is not None and _symbol_run(found[1]) else None


_UNIT_BY_LOWER = {u.lower(): u for u in UNITS}
# SI prefixes (micro as 'u', 'µ' or Greek 'μ') that run into a symbol as a product would
# ('mN', 'kJ')
_PREFIXES = "kcdmuµμnMG"
_SUPERSCRIPTS = str.maketrans("⁰¹²³⁴⁵⁶⁷⁸⁹⁻", "0123456789-")


def _plain_unit(word: str) -> str:
    """A unit as typeset ('m·s⁻²', 'N⋅m', 'N.s') in the symbols legdsl reads ('m*s^-2')."""
    for dot in "·⋅.":
        word = word.replace(dot, "*")
    return re.sub(r"[⁻⁰¹²³⁴⁵⁶⁷⁸⁹]+", lambda m: "^" + m.group().translate(_SUPERSCRIPTS), word)


def looks_like_unit(word: str, fuzzy: bool = True) -> bool:
    """Whether a word after a number was meant as a unit (and is not, say, a property name);
    not ``fuzzy``: only as a unit's case, plural, name or symbols run together, not by a
    near spelling ('com', a property, is near 'cm')."""
    powers = r"[-+]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?"  # 'm^2', 'm^2.0', 'm^1e3'
    parts = [p for p in re.split(r"[*/^]", _plain_unit(word)) if not re.fullmatch(powers, p)]
    return bool(parts) and all(
        p.lower().removesuffix("s") in _UNIT_NAMES
        or p.lower() in _UNIT_NAMES
        or p.lower().removesuffix("s") in _UNIT_BY_LOWER
        or p.lower() in _UNIT_BY_LOWER
        or _symbol_run(p.rstrip("0123456789"))
        or (p[:1] in _PREFIXES and p[1:] in UNITS)
        or (fuzzy and difflib.get_close_matches(p, list(UNITS), n=1, cutoff=0.8))
        for p in parts
    )


def unknown_unit(
    word: str, number: str | tuple[str, ...] | None = None, want: Dim | None = None
) -> str:
    """The message for a word written as a unit that is none; ``number``, the number
    written before it (a vector's numbers), if known, for the value to write instead;
    ``want``, the dimension the value must have, if known, to suggest only units of it."""
    if word == "%" and not isinstance(number, tuple):  # '--set k=30%', as a file's '30%'
        return percentage(number)
    other = metre_or_milli(word, number, want)
    if other is not None:
        return other
    if (whole := re.sub(r"\^\(([-+]?\d+)\)", r"^\1", word)) != word and _parses(whole):
        return (  # 'm*s^(-1)': a whole power, in parentheses as a unit takes none
            f"a unit takes no parentheses, around a power neither: write '{whole}', not '{word}'"
        )
    if re.search(r"\^[-+]?(?:\d+(?:\.\d*)?[eE]|\d{4})", word):  # 'm^1e300', 'm^10000'
        return (
            f"'{word}' has a power past any unit's: a unit's powers are small whole numbers "
            "written with digits, as in 'm^2' or 's^-1'"
        )
    if re.search(r"\^[-+]?(?:\d*[./]\d|\()", word):  # 'm^2.5', 'm^(1/2)'
        return (
            f"'{word}' has a power that is not a whole number: a unit's powers are whole, as "
            "in 'm^2' or 's^-1' (a square root of a unit has no unit in legdsl)"
        )
    symbols = ", ".join(UNITS)
    message = (
        f"'{word}' is not a unit legdsl knows: a unit is made of the symbols {symbols} "
        f"joined by '*', '/' and '^', as in '5 m/s' or '60 N*m/rad'"
    )
    found = suggest_units(word)
    return message + (f"; did you mean {' or '.join(repr(f) for f in found)}?" if found else "")


def bare_number(text: str) -> bool:
    """Whether ``text`` is a number alone, without a unit (as Python's ``float`` reads it)."""
    try:
        float(text)
    except ValueError:
        return False
    return True


def _decimal(value: float) -> str:
    """A number as a person writes it: '0.0003', '5e-09', '1500'."""
    if value != 0 and not 1e-5 <= abs(value) < 1e6:
        mantissa, exponent = f"{value:.6g}".split("e")
        return f"{mantissa}e{int(exponent)}"
    return f"{value:.10f}".rstrip("0").rstrip(".") if value % 1 else f"{value:.0f}"


def _family(unit: str) -> tuple[str, str] | None:
    """The kind of ``unit`` and legdsl's symbols for it: ('lengths', 'm, cm, mm, km')."""
    dim = parse_unit(unit)[1]
    names = {(0, 1, 0, 0): "lengths", (1, 0, 0, 0): "masses", (0, 0, 1, 0): "times",
             (1, 1, -2, 0): "forces", (0, 0, -1, 0): "frequencies"}  # fmt: skip
    if dim not in names:
        return None
    return names[dim], ", ".join(u for u, (_, d) in UNITS.items() if d == dim)


def other_system(word: str, number: str | tuple[str, ...] | None) -> str | None:
    """A unit with a prefix legdsl lacks ('µm', 'dm', 'us', 'mN*m') or from another system
    of units ('in', 'lb', 'h', 'km/h'): what legdsl writes instead, with the value if known."""
    parts = re.split(r"([*/])", word)
    factor, unit, converted = 1.0, "", []
    for i, part in enumerate(parts):
        atom = re.fullmatch(r"([^\W\d_]+)(\^-?\d+)?", part)
        if part in ("*", "/") or (atom is not None and atom.group(1) in UNITS):
            unit += part
            continue
        # 'Ms', 'KG': a unit with the wrong case, not one of another system
        if atom is None or atom.group(1).lower() in _UNIT_BY_LOWER:
            return None
        found = _stand_in(atom.group(1))
        if found is None:
            return None
        scale, base, why = found
        power = atom.group(2) or ""
        exponent = int(power[1:]) if power else 1
        factor *= scale ** (-exponent if i and parts[i - 1] == "/" else exponent)
        converted.append((i, base, power, exponent, why, atom.group(1)))
        unit += base + power
    if not converted:
        return None
    try:
        to_si, dim = parse_unit(unit)
    except (UnitError, ValueError):
        return None
    at, base, power, exponent, why, symbol = converted[0]
    family = _family(base)
    said = f"'{word}' is not a unit legdsl knows{why}"
    if len(parts) > 1 and not why:  # 'km/h': the part it lacks (a speed is not a time)
        said += ": it has no " + ", ".join(f"'{c[-1]}'" for c in converted)
    told = family is not None and len(converted) == 1
    # 'mN*m' is a torque: its force is named, or 'writes forces' would be read of the whole
    whose = f" (its '{symbol}{power}')" if len(parts) > 1 and why else ""
    message = said + (f"; it writes {family[0]}{whose} in {family[1]}" if family and told else "")
    if number is None:
        return message + f"; write the value in {unit}"
    if isinstance(number, tuple):  # a vector's, '(0, 5) ft': the vector in legdsl's unit
        values = ", ".join(_decimal(float(n) * factor) for n in number)
        return message + f": write '({values}) {unit}'"
    value = float(number) * factor
    ways = [f"'{_decimal(value)} {unit}'"]
    example = next((ex for d, ex in KINDS.values() if d == dim and d != DIMENSIONLESS), unit)
    if at > 0 and example != unit:  # '10 km/h': '2.78 m/s' before '0.167 km/min'
        ways.insert(0, f"'{_decimal(value * to_si / parse_unit(example)[0])} {example}'")
    if family and value and at == 0 and len(converted) == 1:  # '0.3 mm' beside '0.0003 m':
        rest = "".join(parts[1:])  # the one nearest 1
        scaled = {
            other: value * (UNITS[base][0] / UNITS[other][0]) ** exponent
            for other in family[1].split(", ")
        }
        best = min(scaled, key=lambda u: abs(math.log10(abs(scaled[u]))))
        if best != base:
            ways.append(f"'{_decimal(scaled[best])} {best}{power}{rest}'")
    return message + ": write " + " or ".join(ways)


def _parses(unit: str) -> bool:
    try:
        parse_unit(unit)
    except UnitError:
        return False
    return True


def metre_or_milli(
    word: str, number: str | tuple[str, ...] | None, want: Dim | None = None
) -> str | None:
    """``other_system``'s sentence, with an 'm' before a symbol ('mN/rad') read both ways it
    may be meant: milli ('0.15 N/rad') or a metre run into it ('150 N*m/rad', m*N); only
    the reading of ``want``, the dimension the value must have, where one has it."""
    told = other_system(word, number)
    found = re.search(rf"(?<![A-Za-z])m({_UNIT_SYMBOL})(\^-?\d+)?(?![A-Za-z])", word)
    if told is None or found is None or "m" + found[1] in UNITS:
        return told
    metre = word[: found.start()] + found[1] + (found[2] or "") + "*m" + word[found.end() :]
    if not _parses(metre):
        return told
    milli_fits = want is not None and parse_unit(metre_free(word, found))[1] == want
    if want is not None and parse_unit(metre)[1] == want and not milli_fits:
        said = f"'{word}' is not a unit legdsl knows: units multiplied are joined by '*', "
        said += f"and it has no prefix 'm' (milli) for '{found[1]}'"
        if isinstance(number, tuple):
            return said + f": write '({', '.join(number)}) {metre}'"
        return said + (f": write '{number} {metre}'" if number else f"; write it in {metre}")
    if milli_fits:
        return told
    shown = f"({', '.join(number)})" if isinstance(number, tuple) else number
    if shown:
        return told + f", or '{shown} {metre}' if the 'm' meant metres"
    return told + f" (or in {metre} if the 'm' meant metres)"


def metre_free(word: str, found: re.Match[str]) -> str:
    """``word`` with the prefix 'm' at ``found`` dropped (its unit as milli reads it)."""
    return word[: found.start()] + found[1] + (found[2] or "") + word[found.end() :]


def _stand_in(symbol: str) -> tuple[float, str, str] | None:
    """A symbol from another system ('h', 'in') or with a prefix legdsl lacks ('dm'): (its
    factor to a unit legdsl has, that unit, what to add to "not a unit legdsl knows")."""
    singular = symbol.lower().removesuffix("s") if len(symbol) > 2 else symbol.lower()
    if symbol in _FOREIGN or singular in _FOREIGN:
        factor, base = _FOREIGN.get(symbol) or _FOREIGN[singular]
        return factor, base, ""
    if symbol[:1] in _PREFIX_FACTORS and symbol[1:] in UNITS and symbol not in UNITS:
        name, factor = _PREFIX_FACTORS[symbol[:1]]
        return factor, symbol[1:], f": it has no prefix '{symbol[:1]}' ({name})"
    return None


def stand_in_unit(word: str) -> str | None:
    """legdsl's unit of the kind of a unit from another system or with a prefix legdsl lacks
    ('ft' -> 'm', 'dm' -> 'm'), to read in its place once it is reported; else None."""
    found = _stand_in(word)
    return found[1] if found else None


def suggest_unit(word: str) -> str | None:
    """A unit legdsl knows for a misspelt one: 'kgs' -> 'kg', 'm/sec' -> 'm/s', 'Nm' -> 'N*m'."""
    found = suggest_units(word)
    return found[0] if found else None


def suggest_units(word: str) -> list[str]:
    """The units legdsl knows a misspelt one may be, likeliest first: one, but symbols run
    together may be read more ways than one: 'Nms' is 'N*ms' or 'N*m*s'."""
    out: list[list[str]] = []
    for part in re.split(r"([*/^])", _plain_unit(word)):
        singular = part.lower() if part.lower() in _UNIT_NAMES else part.lower().removesuffix("s")
        undoubled = _undoubled(part)
        if part in UNITS or part in "*/^" or part.lstrip("-").isdigit():
            out.append([part])
        elif undoubled is not None:  # a key pressed twice: 'kgg' is 'kg', not 'kg*g'
            out.append([undoubled])
        elif part.lower() in _UNIT_BY_LOWER:  # 'MS', 'HZ', 'S': its case
            out.append([_UNIT_BY_LOWER[part.lower()]])
        elif (run_power := _symbols_and_power(part)) is not None:  # 'm/s2', 'kgm2': a power
            run, power = run_power
            out.append(["*".join(split) + f"^{power}" for split in _splits(run)])
        elif singular in _UNIT_NAMES:
            symbol = _UNIT_NAMES[singular]
            if symbol is None:
                return []
            out.append([symbol])
        elif len(singular) > 1 and singular in _UNIT_BY_LOWER:
            out.append([_UNIT_BY_LOWER[singular]])
        elif part[:1] in _PREFIXES and part[1:] in UNITS:
            return []  # a prefix legdsl lacks ('mN'): not 'm*N', a metre-newton
        elif _symbol_run(part):
            out.append(["*".join(split) for split in _splits(part)])
        else:
            close = difflib.get_close_matches(part, list(UNITS), n=1, cutoff=0.6)
            if not close:
                return []
            out.append([close[0]])
    found = []
    for choice in itertools.islice(itertools.product(*out), 4):
        suggestion = "".join(choice)
        try:
            parse_unit(suggestion)
        except UnitError:
            continue
        if suggestion != word:
            found.append(suggestion)
    return found


def _splits(run: str) -> list[list[str]]:
    """The ways symbols run together read as symbols, the longest symbols first:
    'Nms' -> [['N', 'ms'], ['N', 'm', 's']]; none for a run longer than a unit is written
    (their number grows exponentially with its length)."""
    if not run:
        return [[]]
    if len(run) > 12:
        return []
    return [
        [symbol, *rest]
        for symbol in sorted(UNITS, key=len, reverse=True)
        if run.startswith(symbol)
        for rest in _splits(run[len(symbol) :])
    ]


_LONGEST = max(len(u) for u in UNITS)


def _undoubled(part: str) -> str | None:
    """The unit symbol ``part`` is with one doubled letter written once ('kgg', 'ss'), if any."""
    if len(part) > _LONGEST + 1:  # no symbol with one letter doubled
        return None
    for i in range(1, len(part)):
        if part[i] == part[i - 1] and part[:i] + part[i + 1 :] in UNITS:
            return part[:i] + part[i + 1 :]
    return None
