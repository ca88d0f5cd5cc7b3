"""A number with its unit written as one text (``"1.5 m/s"``, ``"500 ms"``), read one way by the
API's arguments and the commands' time options: a number, blanks or none, a unit. Blanks used
to be dropped wherever they were, and ``'1.5 2 m/s'`` ran 1.52 m/s, ``'1 0 ms'`` read 10 ms."""

from __future__ import annotations

import re

from legdsl.lang.errors import UsageError

_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"


def one_text(where: str, text: str, write: str) -> str:
    """``text`` read as the API reads every text with its unit: a number, blanks or none, a
    unit (blanks around its '*', '/' and '^' too), made the form ``legdsl run`` takes
    (``"1.5 m/s"`` -> ``1.5m/s``); blanks inside the number are refused, ``where``'s mistake
    with an example in ``write`` (``{}`` for the value): the blanks were dropped, and
    ``set={'speed': '1.5 2 m/s'}`` ran 1.52 m/s; so are blanks between a unit's symbols
    ('2 m s' read as 2 ms). A text not so is left to the reader to tell."""
    if signed := re.fullmatch(r"\s*([-+])\s+([\d.].*?)\s*", text, re.S):  # '- 1 deg'
        inner = one_text(where, signed.group(2), write)  # its own blanks told first
        text = signed.group(1) + re.sub(rf"^({_NUMBER})", r"\1 ", inner).strip()
        raise UsageError(f"{where}: a number is written without blanks inside it, its sign "
                         f"too; write e.g. {write.format(text)}")  # fmt: skip
    match = re.fullmatch(rf"\s*({_NUMBER})(\s*)(.*?)\s*", text, re.S)
    if match is None:
        return text.strip()
    number, blank = match.group(1), match.group(2)
    unit = re.sub(r"\s*([*/^])\s*", r"\1", match.group(3))
    more = re.match(rf"{_NUMBER}|[eE][-+]?\d+", unit)
    if blank and more:  # '1.5 2 m/s', '3 00 ms', '1.5 e-1 m/s': a number cut by a blank
        joined = re.sub(r"\s+", "", text[match.start(1) : match.start(3) + more.end()])
        rest = unit[more.end() :].strip()
        example = write.format(f"{joined} {rest}".strip())
        raise UsageError(f"{where}: a number is written without blanks inside it; write its "
                         f"digits together, then its unit, e.g. {example}")  # fmt: skip
    if re.fullmatch(r"[A-Za-z]+(?:\s+[A-Za-z]+)+", unit):  # '2 m s': it read as 2 ms
        example = write.format(f"{number} {'*'.join(unit.split())}")
        raise UsageError(f"{where}: a unit is written without blanks inside it, its symbols "
                         f"joined by '*', e.g. {example}")  # fmt: skip
    return number + unit
