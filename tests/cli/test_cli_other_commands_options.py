"""An unknown option's advice: ``run --grid`` was told "did you mean --dt?" and ``run --fps``
"did you mean --set?" (the names' dashes made them close), ``tune --grid`` was told its
missing options rather than that --grid is sweep's, and ``legdsl run --hlep`` the FILE it
lacks rather than the option mistyped."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.cli import main

HOPPER = str(Path(__file__).resolve().parents[2] / "creatures" / "hopper.leg")


@pytest.mark.parametrize(
    ("argv", "told"),
    [
        (["run", HOPPER, "--grid", "kp=1,2"],
         "legdsl: --grid is not an option of legdsl run: it is an option of legdsl sweep"),
        (["tune", HOPPER, "--grid", "kp=1,2"],
         "legdsl: --grid is not an option of legdsl tune: it is an option of legdsl sweep"),
        (["run", HOPPER, "--fps", "30"],
         "legdsl: --fps is not an option of legdsl run: it is an option of legdsl animate, "
         "export-motion and replay"),
        (["run", "--hlep"], "legdsl: --hlep is not an option of legdsl run: did you mean --help?"),
        (["run", HOPPER, "--xyzzy"],
         "legdsl: --xyzzy is not an option of legdsl run; 'legdsl run --help' lists them"),
        (["run", HOPPER, "--tme", "1"],
         "legdsl: --tme is not an option of legdsl run: did you mean --time?"),
        (["run"], "legdsl: the following arguments are required: FILE"),
    ],
)  # fmt: skip
def test_an_unknown_option_is_told_first_and_where_it_belongs(
    argv: list[str], told: str, capsys: pytest.CaptureFixture[str]
) -> None:
    with pytest.raises(SystemExit) as info:
        main(argv)
    assert info.value.code == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(told), err
    assert "did you mean --dt" not in err and "did you mean --set" not in err
