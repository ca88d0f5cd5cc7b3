"""A Python caller's argument refused in the API's words, not the command line's: ``min_stance=
'20 kg'`` was told "write e.g. min_stance=20s" (no Python), ``dt='0.4 kg'`` as ``--dt``,
``time='nan s'`` as 'nans', ``set={'speed@': ...}`` as "--set speed=1m/s@", and a run past
the memory a recording may take as "(exit 130) ... --record-rate"."""

from __future__ import annotations

import pytest

from legdsl.api.arguments import min_stance_time, seconds, setting_text, window_time, with_units
from legdsl.lang.errors import UsageError


@pytest.mark.parametrize(
    ("read", "said"),
    [
        (lambda: min_stance_time("20 kg"),
         "min_stance='20 kg': min_stance= is a time (s), but 20kg is a mass (kg); write e.g. "
         "min_stance='20 s'"),
        (lambda: with_units({"dt": "0.4 kg"}),
         "dt='0.4 kg': dt= is a time (s), but 0.4kg is a mass (kg); write e.g. dt='0.4 s'"),
        (lambda: with_units({"record_rate": "5 s"}),
         "record_rate='5 s': record_rate= is a frequency (Hz), but 5s is a time (s); write e.g. "
         "record_rate='0.2 Hz' (1/5s)"),
        (lambda: with_units({"drop": "-1 cm"}), "drop='-1 cm': drop= must not be negative"),
        (lambda: seconds("nan s"), "time='nan s': nan is not a finite number; give e.g. "
         "time='2 s'"),
        (lambda: window_time("start", "2 kg"), "start='2 kg': start= is a time (s), but 2kg is"),
        (lambda: setting_text("speed@", "1 m/s"),
         "set 'speed@': no time after '@': give e.g. set={'speed@4 s': '1 m/s'} (from 4 s on), "
         "or leave the '@' out to set it from the start"),
        (lambda: setting_text("speed@ -inf s", 2.0),
         "set 'speed@ -inf s': the time after '@', '-inf s', is not a finite number; give e.g. "
         "set={'speed@4 s': 2.0}"),
    ],
)  # fmt: skip
def test_a_refused_argument_is_told_in_python(read: object, said: str) -> None:
    with pytest.raises(UsageError) as e:
        read()  # type: ignore[operator]
    assert str(e.value).startswith(said) and "--" not in str(e.value)


def test_good_texts_still_read() -> None:
    assert seconds("500 ms") == pytest.approx(0.5) and min_stance_time("20ms") == 0.02
    assert with_units({"dt": "0.4 ms", "fall_tilt": "60 deg"})["dt"] == pytest.approx(4e-4)
    assert setting_text("speed@4 s", "1 m/s") == "speed=1m/s@4s"
