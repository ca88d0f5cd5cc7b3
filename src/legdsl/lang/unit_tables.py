"""Units spelt out or from other systems, and SI prefixes legdsl lacks: the tables
``legdsl.lang.units`` reads a word written as a unit by, to name the unit legdsl writes."""

from __future__ import annotations

# Units spelt out, or from elsewhere, in the singular (a final 's' is dropped before
# looking), with the symbol to suggest instead (None: no such unit in legdsl).
_UNIT_NAMES: dict[str, str | None] = {
    "sec": "s", "second": "s", "msec": "ms", "millisecond": "ms", "minute": "min",
    "meter": "m", "metre": "m", "centimeter": "cm", "centimetre": "cm", "millimeter": "mm",
    "millimetre": "mm", "kilometer": "km", "kilometre": "km", "kilogram": "kg", "kilo": "kg",
    "gram": "g", "newton": "N", "kilonewton": "kN", "joule": "J", "watt": "W", "hertz": "Hz",
    "degree": "deg", "radian": "rad", "revolution": "rev", "fps": "Hz",
    "hour": None, "hr": None, "h": None, "inch": None, "in": None, "ft": None, "feet": None,
    "lb": None, "mph": None, "kph": None, "kmh": None, "mp": "m/s", "rpm": "rev/min",
    "t": None, "tonne": None, "ton": None, "oz": None, "ounce": None, "pound": None,
    "mi": None, "mile": None, "yd": None, "yard": None, "°": "deg",
}  # fmt: skip
# Units from elsewhere that legdsl has no symbol for: (factor to a unit it has, that unit)
_FOREIGN: dict[str, tuple[float, str]] = {
    "in": (0.0254, "m"), "inch": (0.0254, "m"), "ft": (0.3048, "m"), "feet": (0.3048, "m"),
    "foot": (0.3048, "m"), "yd": (0.9144, "m"), "yard": (0.9144, "m"), "mi": (1609.344, "m"),
    "mile": (1609.344, "m"), "lb": (0.45359237, "kg"), "pound": (0.45359237, "kg"),
    "oz": (0.028349523125, "kg"), "ounce": (0.028349523125, "kg"), "t": (1000.0, "kg"),
    "tonne": (1000.0, "kg"), "ton": (1000.0, "kg"), "h": (60.0, "min"), "hr": (60.0, "min"),
    "hour": (60.0, "min"), "mph": (0.44704, "m/s"), "kph": (1/3.6, "m/s"), "kmh": (1/3.6, "m/s"),
}  # fmt: skip
# SI prefixes legdsl has no symbol with: prefix -> (name, factor)
_PREFIX_FACTORS: dict[str, tuple[str, float]] = {
    "k": ("kilo", 1e3), "c": ("centi", 1e-2), "d": ("deci", 1e-1), "m": ("milli", 1e-3),
    "u": ("micro", 1e-6), "µ": ("micro", 1e-6), "μ": ("micro", 1e-6), "n": ("nano", 1e-9),
    "M": ("mega", 1e6), "G": ("giga", 1e9),
}  # fmt: skip
