"""A negative value given to a numeric option (``--time -5s``) reaches legdsl's own check of
the value, which says it must be more than zero; argparse alone read '-5s' as another option
and said "expected one argument"."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.cli import _parser, main
from legdsl.cli.common import negative_values_joined

HOPPER = str(Path(__file__).resolve().parents[2] / "creatures" / "hopper.leg")


@pytest.mark.parametrize(
    ("flag", "value"), [("--time", "-5s"), ("--dt", "-1ms"), ("--time", "-5"), ("--dt", "-.5ms")]
)
def test_a_negative_value_is_refused_by_legdsl_not_argparse(
    flag: str, value: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["run", HOPPER, flag, value, "--out", str(tmp_path / "run")]) == 2
    err = capsys.readouterr().err
    assert err.splitlines()[0] == f"legdsl: {flag} {value}: {flag} must be more than zero"
    assert not (tmp_path / "run").exists()


def test_only_a_negative_number_after_an_option_that_takes_a_value_is_joined() -> None:
    parser = _parser()
    argv = ["run", "f.leg", "--time", "-5s", "--animate", "--dt", "2ms", "--out", "-x"]
    assert negative_values_joined(argv, parser) == [
        "run", "f.leg", "--time=-5s", "--animate", "--dt", "2ms", "--out", "-x"
    ]  # fmt: skip
    # a flag takes no value, so what follows it is left to argparse; so is all after '--'
    assert negative_values_joined(["run", "--animate", "-5s"], parser) == [
        "run", "--animate", "-5s"
    ]  # fmt: skip
    assert negative_values_joined(["check", "--", "--time", "-5s"], parser) == [
        "check", "--", "--time", "-5s"
    ]  # fmt: skip
