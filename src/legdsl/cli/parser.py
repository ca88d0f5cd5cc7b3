"""The parser of every ``legdsl`` command: argparse told to say a mistake in one line.

argparse's own behaviour, changed in one place for every command (the subcommands' parsers
are made by ``add_parser`` of this class, wherever they are defined):

- an option that takes one value, given two values, is refused (``--time 0.1 --time 0.3`` ran
  0.3 s, ``-o gen2 --generated gen3`` wrote gen3), as a repeated ``--path`` always was, and
  so is a flag given with its opposite (``--anchor-pads --no-anchor-pads``);
- no abbreviations (``--tim 0.3`` ran 0.3 s): an unknown option is refused with the close
  names it may have meant (``--tme``: did you mean --time?);
- a value that is no number (``--jobs 2x``, ``--slow-motion 2s``) is told in a sentence
  with the number to write, not as "invalid float value";
- a mistake is one line, ``legdsl: what is wrong, and how to fix it``, exit status 2, with
  no usage dump (``legdsl COMMAND --help`` shows it).
"""

from __future__ import annotations

import argparse
import difflib
import re
import sys
from collections.abc import Sequence
from typing import Any, NoReturn

_GIVEN = "_legdsl_given"  # a parse's options given so far: dest -> (option, value)

# what a plain number means, for the options whose number is a factor or a count
_MEANS = {"slow_motion": "{n} (the video {n} times slower than real time)"}


def _shown(value: Any) -> str:
    return f"{value:g}" if isinstance(value, float) else str(value)


class _Once(argparse._StoreAction):
    """``store`` that refuses a second value, which silently replaced the first (the same
    value again is no contradiction: a script's default given twice)."""

    def __call__(
        self,
        parser: argparse.ArgumentParser,
        namespace: argparse.Namespace,
        values: Any,
        option_string: str | None = None,
    ) -> None:
        given: dict[str, tuple[str, Any]] = namespace.__dict__.setdefault(_GIVEN, {})
        if self.dest in given and given[self.dest][1] != values:
            first, value = given[self.dest]
            now = option_string or first
            both = f"({_shown(value)} and {_shown(values)})"
            said = (
                f"{now} is given twice {both}"
                if now == first
                else f"{first} and {now} are one option, given twice {both}"
            )
            raise argparse.ArgumentError(None, f"{said}: give it once")
        given[self.dest] = (option_string or self.dest, values)
        setattr(namespace, self.dest, values)


class _OnceEither(argparse.BooleanOptionalAction):
    """``--anchor-pads`` and ``--no-anchor-pads`` together: the later won silently."""

    def __call__(
        self,
        parser: argparse.ArgumentParser,
        namespace: argparse.Namespace,
        values: Any,
        option_string: str | None = None,
    ) -> None:
        given: dict[str, tuple[str, Any]] = namespace.__dict__.setdefault(_GIVEN, {})
        first = given.setdefault(self.dest, (option_string or self.dest, None))[0]
        if option_string is not None and first != option_string:
            raise argparse.ArgumentError(
                None, f"{first} and {option_string} say the opposite: give one of them"
            )
        super().__call__(parser, namespace, values, option_string)


def _number_in(text: str) -> str | None:
    found = re.match(r"\s*[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?", text)
    return found.group().strip() if found else None


def not_a_number(action: argparse.Action, text: str) -> str:
    """What to say of ``text`` given to an option of ``type=int`` or ``float``."""
    flag = action.option_strings[-1] if action.option_strings else action.metavar or action.dest
    number = _number_in(text)
    if action.type is int:
        whole = str(round(float(number))) if number is not None else "2"
        if whole == "0" and number is not None and float(number) > 0:
            whole = "1"
        return (
            f"{flag} {text}: {flag} takes a whole number, without a unit: write e.g. {flag} {whole}"
        )
    n = number if number is not None else "2"
    meaning = _MEANS.get(action.dest, "{n}").format(n=n)
    return (
        f"{flag} {text}: {flag} takes a plain number, without a unit: write e.g. {flag} {meaning}"
    )


def _an_option(word: str) -> bool:
    """Whether ``word`` is written as an option (not '-', not a negative number)."""
    return word.startswith("-") and len(word) > 1 and _number_in(word) is None


class LegParser(argparse.ArgumentParser):
    """``argparse.ArgumentParser`` with legdsl's rules (the module's docstring)."""

    # the command line being read and the parser of all commands, for a caret in a mistake
    reading: tuple[Sequence[str], argparse.ArgumentParser] | None = None

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        kwargs.setdefault("allow_abbrev", False)
        super().__init__(*args, **kwargs)
        self.register("action", None, _Once)
        self.register("action", "store", _Once)

    def add_argument(self, *args: Any, **kwargs: Any) -> argparse.Action:
        if kwargs.get("action") is argparse.BooleanOptionalAction:
            kwargs["action"] = _OnceEither
        return super().add_argument(*args, **kwargs)

    def _get_value(self, action: argparse.Action, arg_string: str) -> Any:
        if action.type in (int, float) and (not arg_string.isascii() or "_" in arg_string):
            flag = action.option_strings[-1] if action.option_strings else action.dest
            raise argparse.ArgumentError(  # Python's int() and float() read '1_0' as 10
                None,
                f"{flag} {arg_string}: {arg_string!r} is not a number: write it with the digits "
                "0-9, without '_' (as in a .leg file)",
            )
        try:
            return super()._get_value(action, arg_string)
        except argparse.ArgumentError:
            if action.type in (int, float):
                raise argparse.ArgumentError(None, not_a_number(action, arg_string)) from None
            raise

    def parse_args(  # type: ignore[override]
        self, args: Sequence[str] | None = None, namespace: argparse.Namespace | None = None
    ) -> argparse.Namespace:
        LegParser.reading = (list(sys.argv[1:] if args is None else args), self)
        parsed, extras = self.parse_known_args(args, namespace)
        if extras:
            self.error(self._not_taken(extras, parsed))
        vars(parsed).pop(_GIVEN, None)
        return parsed

    def _command(self, parsed: argparse.Namespace) -> LegParser:
        """The parser of the subcommand ``parsed`` is of, else this one."""
        for action in self._actions:
            if isinstance(action, argparse._SubParsersAction):
                sub = action.choices.get(getattr(parsed, action.dest or "", None) or "")
                if isinstance(sub, LegParser):
                    return sub
        return self

    def _not_taken(self, extras: Sequence[str], parsed: argparse.Namespace) -> str:
        """What to say of the first argument no option or place took."""
        parser = self._command(parsed)
        word = extras[0]
        if _an_option(word):
            return parser.unknown_option(word.partition("=")[0], self)
        return (
            f"{word!r} is one argument too many for {parser.prog} (a value given to an option "
            f"that takes none, or a second file?); '{parser.prog} --help' shows what it takes"
        )

    def unknown_option(self, name: str, top: argparse.ArgumentParser) -> str:
        """What to say of ``name``, an option this command (``self``) does not take: the
        commands that take it (``run --grid``: one of ``legdsl sweep``), else the names it is
        close to (compared without their dashes: '--grid' is not close to '--dt'), else
        where the options are listed."""
        options = [o for a in self._actions for o in a.option_strings]
        options += [o for a in top._actions for o in a.option_strings if o != "--version"]
        others = [
            sub.prog.split()[-1]
            for a in top._actions
            if isinstance(a, argparse._SubParsersAction)
            for sub in dict.fromkeys(a.choices.values())
            if sub is not self and name in sub._option_string_actions
        ]
        if others and name not in options:
            which = others[0] if len(others) == 1 else f"{', '.join(others[:-1])} and {others[-1]}"
            return f"{name} is not an option of {self.prog}: it is an option of {top.prog} {which}"
        started = [o for o in options if o.startswith(name) and name.startswith("--")]
        bare = {o.lstrip("-"): o for o in options if o.startswith("--")}
        near = difflib.get_close_matches(name.lstrip("-"), list(bare), n=3, cutoff=0.6)
        close = started or [bare[n] for n in near]
        if close:
            meant = " or ".join(dict.fromkeys(close))
            return f"{name} is not an option of {self.prog}: did you mean {meant}?"
        return f"{name} is not an option of {self.prog}; '{self.prog} --help' lists them"

    def _unknown_before(self) -> str | None:
        """Of a command line that lacks a required argument, what to say of an unknown option
        in it (``legdsl run --hlep``: the option, not the FILE it lacks), or None."""
        if LegParser.reading is None:
            return None
        argv, top = LegParser.reading
        from legdsl.cli.common import options_with_a_value

        takes_value = options_with_a_value(top, short=True)
        known = set(self._option_string_actions) | set(top._option_string_actions)
        for i, word in enumerate(argv):
            if word == "--":
                break
            name = word.partition("=")[0]
            after_value = i > 0 and argv[i - 1] in takes_value
            if _an_option(word) and name not in known and not after_value:
                return self.unknown_option(name, top)
        return None

    def error(self, message: str) -> NoReturn:
        """One line, what is wrong and how to fix it (argparse printed its usage first)."""
        said = re.match(r"argument ([^:]+): (.*)", message, re.DOTALL)
        if said:
            flags, what = said.group(1).split("/")[-1], said.group(2)
            if what.startswith("expected one argument"):
                message = (
                    f"{flags} needs a value after it ('{self.prog} --help' says what it takes)"
                )
            elif choice := re.match(r"invalid choice: '(.*)' \(choose from (.*)\)", what):
                given, offered = choice.group(1), choice.group(2)
                close = difflib.get_close_matches(given, re.findall(r"'([^']*)'", offered), n=1)
                meant = f" (did you mean {close[0]}?)" if close else ""
                message = (
                    f"{flags} {given}: choose one of {offered}{meant}"
                    if flags.startswith("-")
                    else f"'{given}' is not a {flags.lower()} of {self.prog}{meant}: choose one "
                    f"of {offered}"
                )
            else:
                message = f"{flags}: {what}"
        elif message.startswith("the following arguments are required"):
            message = self._unknown_before() or (
                f"{message} ('{self.prog} --help' shows how to give them)"
            )
        if LegParser.reading is not None:
            from legdsl.cli.common import options_with_a_value
            from legdsl.cli.pointed import pointed

            argv, top = LegParser.reading
            message = pointed(message, argv, options_with_a_value(top, short=True))
        print(f"legdsl: {message}", file=sys.stderr)
        sys.exit(2)
