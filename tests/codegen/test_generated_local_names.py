"""Names a .leg file may give that C or the generated Python already uses: each runs, and the
two backends agree bit for bit (a C keyword, a math.h macro, a function the law calls)."""

from __future__ import annotations

import re
from pathlib import Path

from conftest import CREATURES
from runtime_helpers import assert_same, needs_c_compiler

from legdsl.codegen.c.printer import c_spellings, taken_in_c
from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions

RUNTIME = Path(__file__).resolve().parents[2] / "src" / "legdsl" / "codegen" / "c" / "runtime"

# The hopper's parameters renamed, each clashing with something in the law that reads it:
# int and int_ (C spells int as int_), leg_min and minimum (called in the same function),
# macros of math.h and errno.h; the C functions' own arguments (p, tis) and names the runtime's
# headers declare (a sensor, a dynamics function, a stdint type).
RENAMED = {
    "k_speed": "p",
    "stance_guess": "tis",
    "full": "leg_sense_leg",
    "height": "forward_dynamics",
    "speed": "int64_t",
    "kp": "int",
    "kv": "int_",
    "apex_limit": "leg_min",
    "k_trim": "minimum",
    "k_apex": "maximum",
    "stroke": "NAN",
    "k_height": "HUGE_VAL",
    "swing_kv": "errno",
    "swing_kp": "__LINE__",
}


def _renamed_hopper(folder: Path) -> Path:
    head, controller = (CREATURES / "hopper.leg").read_text().split("controller hop", 1)
    for old, new in RENAMED.items():
        controller = re.sub(rf"(?<![\w.]){old}(?!\w)", new, controller)
    path = folder / "clash.leg"
    path.write_text(head + "controller hop" + controller)
    return path


@needs_c_compiler
def test_parameters_named_as_c_and_python_names_run_alike_on_both_backends(
    tmp_path: Path,
) -> None:
    sess = RunSession.from_file(_renamed_hopper(tmp_path), generated=tmp_path / "generated")
    opts = RunOptions(duration=0.3)
    python = sess.run("hop", [], options=opts, backend="python").result
    c = sess.run("hop", [], options=opts, backend="c").result
    assert python.status == "ok", python.message
    assert_same(python, c)


def test_a_name_c_cannot_spell_gets_one_no_other_local_has() -> None:
    assert c_spellings(["int", "int_", "x"]) == {"int": "int_2"}
    assert c_spellings(["NAN", "leg_min", "_Bool", "short", "M_PI", "uM_PI"]) == {
        "NAN": "NAN_",
        "leg_min": "leg_min_",
        "_Bool": "u_Bool",  # _Bool_ is the implementation's too (_ and a capital)
        "short": "short_",
        "M_PI": "uM_PI2",  # M_PI_ is math.h's family; uM_PI is the function's own
    }
    assert all(not taken_in_c(s) for s in c_spellings(["_X", "__y", "LEG_PI", "FP_NAN"]).values())


def test_every_name_of_the_math_header_is_taken_in_c() -> None:
    """The generated laws and dynamics call legdsl_math.h's functions and macros: a local
    named as one of them would expand or hide it."""
    text = (RUNTIME / "legdsl_math.h").read_text()
    names = set(re.findall(r"\b(?:leg|LEG)_\w+", text))
    assert names and not {n for n in names if not taken_in_c(n)}
