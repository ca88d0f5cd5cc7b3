"""Records of actions, above all the standard library's: an unknown name that another action
records, a user's name that a called action's record would hide, and what an uncalled
action's text may tell about an unknown name (nothing)."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.check.source import check_model
from legdsl.lang.errors import LegError

ROOT = Path(__file__).resolve().parents[2]
CREATURE = (ROOT / "tests" / "bad" / "ctl_dim_comparison.leg").read_text().split("controller")[0]


def _errors(tmp_path: Path, text: str) -> list[tuple[str, int, str]]:
    path = tmp_path / "lib_records.leg"
    path.write_text(text)
    with pytest.raises(LegError) as info:
        check_model(path)
    first = text.split("controller")[0].count("\n")
    return [
        (Path(d.span.file).name, d.span.line - first, d.message) for d in info.value.diagnostics
    ]


def test_a_record_of_an_uncalled_action_asks_for_that_action(tmp_path: Path) -> None:
    """'marked' is recorded by 'mark', which the table never calls: declaring 'param marked'
    (what the message said) would pass and leave it a constant."""
    errors = _errors(
        tmp_path,
        "action mark() { record marked = time }\n"
        "action since(leg) { leg.spring.rest = select(marked > 0 s, 1 cm, 0 m) }\n"
        + CREATURE
        + "controller hop {\n  table {\n    state A on liftoff(main): since(main)\n  }\n}\n",
    )
    (message,) = [m for _, _, m in errors]
    assert "unknown name 'marked': it is recorded by action 'mark'" in message
    assert "call one of them too, in the same state" in message
    assert "declare it" not in message


def test_trim_step_side_alone_asks_for_trim_step_speed(tmp_path: Path) -> None:
    errors = _errors(
        tmp_path,
        "use raibert\n" + CREATURE + "controller hop {\n  table {\n"
        "    state A on liftoff(main): trim_step_side(trunk, 0.5, 0.1 m/s)\n  }\n}\n",
    )
    lifted = [m for _, _, m in errors if m.startswith("unknown name 'lifted':")]
    assert len(lifted) == 1
    assert "'trim_step_speed' or 'trim_step_speed_from'" in lifted[0]


def test_a_param_a_library_record_would_hide_is_told_at_the_param(tmp_path: Path) -> None:
    errors = _errors(
        tmp_path,
        "use raibert\n" + CREATURE + "controller hop {\n  param apex_trim = 1 m\n  table {\n"
        "    state A on liftoff(main): learn_apex(1 m, 0.1, 1 cm)\n  }\n}\n",
    )
    library = (ROOT / "src" / "legdsl" / "stdlib" / "raibert.leg").read_text().splitlines()
    line = next(n for n, text in enumerate(library, 1) if "record apex_trim" in text)
    assert errors == [
        (
            "lib_records.leg",
            2,
            f"action 'learn_apex' (stdlib/raibert.leg:{line}:10), which the table calls, records "
            "'apex_trim', which would hide the parameter 'apex_trim': give the parameter "
            "another name",
        )
    ]


def test_an_uncalled_library_action_tells_nothing_of_a_bare_unknown_name(
    tmp_path: Path,
) -> None:
    """steer_path reads 'route.ahead_heading'; a controller that never calls it and reads a
    bare 'route' was told to declare a path, quoting the library's text."""
    table = "  table {\n    state A on time > 1 s: leg_spring.rest = route * 1 m\n  }\n}\n"
    errors = _errors(tmp_path, "use raibert\n" + CREATURE + "controller hop {\n" + table)
    (message,) = [m for _, _, m in errors]
    assert message.startswith("unknown name 'route': not a part of the creature")
    # the user's own 'route.lateral' still asks for a path
    own = table.replace("route * 1 m", "route.lateral")
    errors = _errors(tmp_path, "use raibert\n" + CREATURE + "controller hop {\n" + own)
    assert any("declared with 'path route'" in m for _, _, m in errors)
