"""A caret under the part of a command-line value that is wrong, as ``--path`` has one.

A quantity's mistake (``--time 0.2kg``, ``--set speed=2m/s@1kg``, ``--grid speed=1kg:2:3``,
``--dt 0``) was one line; the project's promise is that a unit error points at the unit. The
message stays as it was said, and the option with its value as given is echoed under it, with
a caret under the unit at fault (a wrong or unknown unit), the number (one out of range) or
the whole value (one that is no number). One place for every command: where its mistakes are
printed (``legdsl.cli``), from the words of the message and the command line.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Sequence

_OPTION = re.compile(r"(--?[A-Za-z][\w-]*)[ =:]")
# the words of a quantity's mistake (not a path's, a name's, a file's: those have their own)
_QUANTITY = re.compile(
    r"but '?[^'\s;]+'? is (an?|dimensionless)|is not a unit|must be more than zero|must not be "
    r"negative|give its unit|not a number|plain number|whole number|overflows|underflows|finite number|"
    r"too small to be a number"
)
_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|[-+]?(?:inf|nan)", re.I)


def _values(option: str, argv: Sequence[str], takes_value: Iterable[str]) -> list[str]:
    """The values ``option`` was given on the command line, as written."""
    found, takes = [], set(takes_value)
    for i, arg in enumerate(argv):
        if arg == "--":
            break
        if arg.startswith(option + "="):
            found.append(arg[len(option) + 1 :])
        elif arg == option and option in takes and i + 1 < len(argv):
            found.append(argv[i + 1])
    return found


def _find(value: str, token: str, after: int) -> int:
    """Where ``token`` is in ``value``: from ``after`` on if it is there, else anywhere."""
    at = value.find(token, after)
    return at if at >= 0 else value.find(token)


def _fault(message: str, value: str) -> tuple[int, int] | None:
    """Where in ``value`` the message's fault is (start, length)."""
    quantity = re.search(r"but '?([^'\s;]+?)'? is ", message)
    unknown = re.search(r"'([^']+)' is not a unit", message)
    after = value.rfind("@") + 1 if "'@'" in message else 0
    if unknown and (at := value.find(unknown.group(1), after)) >= 0:
        return at, len(unknown.group(1))
    if quantity and (at := value.find(quantity.group(1), after)) >= 0:
        text = quantity.group(1)
        number = _NUMBER.match(text)
        skip = number.end() if number and number.end() < len(text) else 0
        return at + skip, len(text) - skip  # the unit, or a bare number
    said = re.search(
        r"(\S+) is too (?:large|small) to be a number|'([^']+)' is not a number", message
    )
    token = (said.group(1) or said.group(2)) if said else ""
    if said and token and (at := _find(value, token, after)) >= 0:  # no number, or no double
        number = _NUMBER.match(token)
        return at, number.end() if said.group(1) and number else len(token)
    if "give its unit" in message:  # a bare number: under it, where the unit goes
        first = _NUMBER.match(value)
        if not after and first and value[first.end() : first.end() + 1] == "=":
            return 0, first.end()  # the time before '=' (--switch 6=bound)
        start = after or value.find("=", 0, value.find("@") % (len(value) + 1)) + 1
        bare = _NUMBER.match(value, start)
        return (start, bare.end() - start) if bare else (start, len(value) - start)
    number = _NUMBER.match(value)
    if re.search(r"must be more than zero|must not be negative", message) and number:
        return 0, number.end()
    plain = re.search(r"plain number|whole number|plain factor", message)
    if plain and number and number.end() < len(value):
        return number.end(), len(value) - number.end()  # the unit it takes none of
    return 0, len(value)


def pointed(message: str, argv: Sequence[str], takes_value: Iterable[str]) -> str:
    """``message`` with the option's value echoed and a caret under its fault, when the
    message is about an option's value given on the command line (and has no caret yet)."""
    said = _OPTION.match(message)
    if "\n" in message or not said or not _QUANTITY.search(message):
        return message
    option = said.group(1)
    values = _values(option, argv, takes_value)
    rest = message[said.end() :]
    value = next((v for v in values if v and (rest.startswith(v) or f" {v}" in message)), None)
    value = value or next((v for v in values if v and v.split("=")[0] in rest), None)
    if value is None:
        return message
    where = _fault(message, value)
    if where is None:
        return message
    start, length = where
    line = f"{option} {value}"
    indent = " " * (len(option) + 1 + start)
    return f"{message}\n    {line}\n    {indent}^{'~' * max(length - 1, 0)}"
