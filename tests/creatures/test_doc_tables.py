"""The main measurement tables of docs/kangaroo.md, docs/biped.md and docs/quadruped.md still
come out: each row is read from the doc, rerun on the C backend (bit-identical to Python) and
its figures compared with the doc's at the precision the doc prints them. These runs are
chaotic at the bit level, so a change anywhere in the printer or the simulator may move the
third decimal: re-measure the row with the command the failure prints and update the doc.

Checked: the kangaroo's speed table (every row and column), its "how much one setting says"
table (every row, both speeds) and its hop height table (every cell written), the biped's run
speed table (speed, error, strides, heading), its Table 2 at 1.5 m/s (every row), its gallop
table (both columns, every row) and the gallops' other speeds, and the quadruped's gait table
(outcome, mean speed, error, pairs, mu) and the bound's Table 2 at 2.8 m/s (every row; the
figures in brackets, a run before the speed correction, are not rerun). A 20 s kangaroo run
takes well under a second on the C backend, so these tables are rerun whole (about 1 s in all
here, the biped's and the bound's runs shared with the tables above).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from doc_tables import (
    Comparison,
    Row,
    fell_at,
    heading_speed,
    metrics,
    numbers,
    pair_spreads,
    run_command,
    run_creature,
    table,
    table2_metrics,
)
from runtime_helpers import needs_c_compiler

pytestmark = needs_c_compiler

KANGAROO = table("docs/kangaroo.md", "| command | 20 s without a fall |")
BIPED_RUN = table("docs/biped.md", "| command | `legdsl run ... --set speed=` |")
GALLOP = table("docs/biped.md", "| | `gallop` 1.5 m/s | `gallop_human` 1.5 m/s |")
GALLOP_SPEEDS = table("docs/biped.md", "| command | `gallop`: speed, pitch |")
QUADRUPED = table("docs/quadruped.md", "| gait | command | outcome | mean speed |")
SENSITIVITY = table("docs/kangaroo.md", "| change (default) |")
HOP_HEIGHT = table("docs/kangaroo.md", "| asked apex |")
BIPED_TABLE2 = table("docs/biped.md", "| quantity | this run | robot | paper animation |")
BOUND_TABLE2 = table("docs/quadruped.md", "| Table 2, quadruped bound | this run (2.8 m/s) |")


def _label(row: Row) -> str:
    return row[next(iter(row.cells))]


def _speed(text: str) -> str:
    """'1.0 m/s' as a --set value: 1m/s."""
    return f"{float(numbers(text)[0]):g}m/s"


@pytest.mark.parametrize("row", KANGAROO, ids=_label)
def test_the_kangaroo_speed_table(generated: Path, row: Row) -> None:
    command = numbers(row["command"])
    schedule = "->" in row["command"]
    settings = [f"speed={command[0]}m/s", f"speed={command[1]}m/s@{command[2]}s"] if schedule \
        else [f"speed={command[0]}m/s"]  # fmt: skip
    start = float(numbers(row["mean speed from 3 s"])[1]) if schedule else 3.0
    run = run_creature(generated, "kangaroo", "hop", settings, 20.0)
    m = metrics(run, start, joint="tail_base", against="hip")
    check = Comparison(f"{run_command('kangaroo', 'hop', settings, 20)} && legdsl metrics "
                       f"runs/x --from {start:g} --joint tail_base --against hip")  # fmt: skip
    check.text(row, "20 s without a fall", "yes" if fell_at(run) is None else "no")
    speed, target = m.value("running_speed"), float(command[1 if schedule else 0])
    check.number(row, "mean speed from 3 s", speed)
    check.number(row, "error", 100 * (speed - target) / target)
    for column, key in [
        ("stride (s)", "stride_duration"),
        ("stance (s)", "stance_duration"),
        ("peak g", "peak_vertical_acceleration"),
        ("pitch magnitude (deg)", "pitch_magnitude"),
        ("tail wag (deg)", "joint_magnitude"),
        ("tail-hip correlation", "joint_correlation"),
    ]:
        check.number(row, column, m.value(key))
    check.check()


@pytest.mark.parametrize("row", BIPED_RUN, ids=_label)
def test_the_biped_run_speed_table(generated: Path, row: Row) -> None:
    settings = [f"speed={row['`legdsl run ... --set speed=`'].strip('`')}"]
    run = run_creature(generated, "biped", "run", settings, 20.0)
    m = metrics(run, 3.0)
    check = Comparison(f"{run_command('biped', 'run', settings, 20)} && legdsl metrics runs/x "
                       "--from 3 (heading: the largest |yaw| of root_rpy from 3 s)")  # fmt: skip
    fell = fell_at(run)
    check.text(row, "command", row["command"] + ("" if fell is None else f", fell at {fell:.1f} s"))
    speed = m.summary("running_speed")
    check.figures(row, "running speed", [speed.value, speed.std], numbers(row["running speed"]))
    target = float(numbers(row["command"])[0])
    check.number(row, "error", 100 * (speed.value - target) / target)
    check.number(row, "strides", m.n_strides)
    tr = run.result.trajectory
    yaw = np.degrees(np.abs(tr.root_rpy[tr.t >= 3.0, 2])).max()
    check.number(row, "heading, max |yaw| after 3 s", float(yaw))
    check.check()


GALLOP_ROWS = {  # the gallop table's quantities: the metrics that give each, in its order
    "running speed": ["running_speed"],
    "**pitch magnitude": ["pitch_magnitude"],
    "roll magnitude": ["roll_magnitude"],
    "stride duration (s) / length (m)": ["stride_duration", "stride_length"],
    "single support, left": ["single_support_duration_left"],
    "double support": ["double_support_duration"],
    "single support, right": ["single_support_duration_right"],
    "flight": ["flight_duration"],
    "fraction of the time in double support": ["double_support_fraction"],
    "change of leg length during support": ["leg_length_change"],
    "peak vertical acceleration": ["peak_vertical_acceleration"],
}


@pytest.mark.parametrize("column", list(GALLOP[0].cells)[1:])
def test_the_biped_gallop_table(generated: Path, column: str) -> None:
    controller = re.findall(r"`(\w+)`", column)[0]
    settings = [f"speed={_speed(column)}"]
    run = run_creature(generated, "biped", controller, settings, 20.0)
    m = metrics(run, 3.0)
    check = Comparison(f"{run_command('biped', controller, settings, 20)} && legdsl metrics "
                       "runs/x --from 3")  # fmt: skip
    for row in GALLOP:
        label = _label(row)
        if label == "strides from 3 s":
            check.number(row, column, m.n_strides)
            continue
        keys = next(k for prefix, k in GALLOP_ROWS.items() if label.startswith(prefix))
        doc = numbers(row[column])
        if len(keys) == 1 and len(doc) == 2:  # value ± std
            s = m.summary(keys[0])
            check.figures(row, f"{label}, {column}", [s.value, s.std], doc)
        else:
            check.figures(row, f"{label}, {column}", [m.value(k) for k in keys], doc)
    check.check()


@pytest.mark.parametrize("row", GALLOP_SPEEDS, ids=_label)
@pytest.mark.parametrize("controller", ["gallop", "gallop_human"])
def test_the_biped_gallop_speeds(generated: Path, row: Row, controller: str) -> None:
    column = next(c for c in row.cells if c.startswith(f"`{controller}`"))
    settings = [f"speed={_speed(row['command'])}"]
    run = run_creature(generated, "biped", controller, settings, 20.0)
    check = Comparison(f"{run_command('biped', controller, settings, 20)} && legdsl metrics "
                       "runs/x --from 3")  # fmt: skip
    fell = fell_at(run)
    if fell is not None or row[column].startswith("falls"):
        check.text(row, column, "holds 20 s" if fell is None else f"falls at {fell:.1f} s")
    else:
        m = metrics(run, 3.0)
        s = m.summary("running_speed")
        doc = numbers(row[column])
        check.figures(row, column, [s.value, s.std, m.value("pitch_magnitude")], doc)
    check.check()


QUADRUPED_PAIRS = {
    "trot": {"toe_fl": "toe_rr", "toe_rr": "toe_fl", "toe_fr": "toe_rl", "toe_rl": "toe_fr"},
    "pace": {"toe_fl": "toe_rl", "toe_rl": "toe_fl", "toe_fr": "toe_rr", "toe_rr": "toe_fr"},
    "bound": {"toe_fl": "toe_fr", "toe_fr": "toe_fl", "toe_rl": "toe_rr", "toe_rr": "toe_rl"},
}


@pytest.mark.parametrize("row", QUADRUPED, ids=lambda r: f"{r['gait']} {r['command']}")
def test_the_quadruped_gait_table(generated: Path, row: Row) -> None:
    gait, target = row["gait"], float(numbers(row["command"])[0])
    settings = [f"speed={target:g}m/s"]
    run = run_creature(generated, "quadruped", gait, settings, 20.0)
    check = Comparison(f"nice python docs/scripts/quadruped_matrix.py --gait {gait} "
                       f"--speeds {target:g} (or {run_command('quadruped', gait, settings, 20)})")  # fmt: skip
    fell = fell_at(run)
    check.text(row, "outcome", "20 s" if fell is None else f"fell at {fell:.1f} s")
    speed = heading_speed(run, 3.0)
    check.number(row, "mean speed", speed)
    check.number(row, "error", 100 * (speed - target) / target)
    spreads = np.array(pair_spreads(run, QUADRUPED_PAIRS[gait], 3.0))
    if spreads.size:  # none when it fell before 3 s
        check.number(row, "pairs ≤ 10 ms", float(np.mean(spreads <= 0.010)))
    m = metrics(run, 3.0)
    interior = [s.value for s in m.summaries if s.key.startswith("friction_interior_")]
    check.number(row, "μ", max(interior))
    check.check()


SENSITIVITY_QUANTITIES = {  # a column's quantities after "up": the figure each is
    "speed error": lambda m, speed: 100 * (m.value("running_speed") - speed) / speed,
    "tail wag": lambda m, speed: m.value("joint_magnitude"),
    "stance": lambda m, speed: m.value("stance_duration"),
    "peak g": lambda m, speed: m.value("peak_vertical_acceleration"),
}


@pytest.mark.parametrize("column", list(SENSITIVITY[0].cells)[1:], ids=lambda c: c.split(":")[0])
@pytest.mark.parametrize("row", SENSITIVITY, ids=lambda r: _label(r).split(" (")[0].strip("`"))
def test_the_kangaroo_sensitivity_table(generated: Path, row: Row, column: str) -> None:
    """docs/kangaroo.md's "how much one setting says": each change (the `--set` in its first
    cell) at the column's speed, 20 s; the time it stayed up, then the column's quantities
    from 3 s (`--joint tail_base` for the tail wag)."""
    speed = float(numbers(column)[0])
    settings = [f"speed={speed:g}m/s", *re.findall(r"`([^`]+)`", _label(row))]
    run = run_creature(generated, "kangaroo", "hop", settings, 20.0)
    m = metrics(run, 3.0, joint="tail_base")
    check = Comparison(f"{run_command('kangaroo', 'hop', settings, 20)} && legdsl metrics "
                       "runs/x --from 3 --joint tail_base")  # fmt: skip
    fell = fell_at(run)
    up, _, figures = row[column].partition(", ")
    if up != ("20 s" if fell is None else f"fell at {fell:.1f} s"):
        check.wrong.append(f"{row.where}: {column!r}: the doc says {up!r}, the run "
                           + ("held 20 s" if fell is None else f"fell at {fell:.1f} s"))  # fmt: skip
    quantities = column.partition(":")[2].split(", ")[1:]  # after "up"
    values = [SENSITIVITY_QUANTITIES[q](m, speed) for q in quantities]
    check.figures(row, column, values, numbers(figures))
    check.check()


HOP_SPEED, HOP_FROM = 4.0, 5.0  # "Turned on, at 4 m/s (20 s, from 5 s)"
HOP_APEX = [c for c in HOP_HEIGHT[0].cells if c.startswith("apex")]  # k_apex = 0.05, then 0
FELL = re.compile(r"fell at ([\d.]+) s")


def _k_apex(column: str) -> str:
    """'apex, `k_apex = 0.05`': 0.05."""
    return re.findall(r"k_apex = ([\d.]+)", column)[0]


@pytest.mark.parametrize(
    ("row", "column"),
    [(r, c) for r in HOP_HEIGHT for c in HOP_APEX if r[c]],  # the cells written
    ids=lambda x: f"k_apex={_k_apex(x)}" if isinstance(x, str) else _label(x),
)
def test_the_kangaroo_hop_height_table(generated: Path, row: Row, column: str) -> None:
    """docs/kangaroo.md's hop height table: the asked apex at the column's `k_apex`, 4 m/s,
    20 s, the apex from 5 s (and for `k_apex = 0.05` its error and the running speed), or
    when it fell."""
    asked = float(numbers(_label(row))[0])
    settings = [f"speed={HOP_SPEED:g}m/s", f"k_apex={_k_apex(column)}", f"height={asked:g}m"]
    run = run_creature(generated, "kangaroo", "hop", settings, 20.0)
    check = Comparison(f"{run_command('kangaroo', 'hop', settings, 20)} && legdsl metrics "
                       f"runs/x --from {HOP_FROM:g}")  # fmt: skip
    fell, said = fell_at(run), FELL.search(row[column])
    if fell is not None and said is not None:
        check.figures(row, f"{column}, fell at (s)", [fell], [said.group(1)])
    elif fell is not None or said is not None:
        check.text(row, column, "a run of 20 s" if fell is None else f"(fell at {fell:.1f} s)")
    else:
        m = metrics(run, HOP_FROM)
        apex = m.summary("apex_height")
        check.figures(row, column, [apex.value, apex.std], numbers(row[column]))
        if column == HOP_APEX[0]:  # the error and the running speed are this column's
            check.number(row, "error", 100 * (apex.value - asked) / asked)
            speed = m.value("running_speed")
            check.number(row, "running speed", speed)
            error = re.findall(r"\(([-+\u2212]?\d+\.\d+)%\)", row["running speed"])
            error = [e.replace("\u2212", "-") for e in error]
            check.figures(row, "running speed", [100 * (speed - HOP_SPEED) / HOP_SPEED], error)
    check.check()


BIPED_TABLE2_ROWS = {  # the biped's Table 2: the metric of each row
    "pitch magnitude": "pitch_magnitude",
    "roll magnitude": "roll_magnitude",
    "stride length": "stride_length",
    "stride duration": "stride_duration",
    "flight duration": "flight_duration",
    "stance duration": "stance_duration",
    "change of leg length": "leg_length_change",
    "error in running speed": "speed_error",
}


def test_the_biped_table2(generated: Path) -> None:
    """docs/biped.md's Table 2 at 1.5 m/s: every row a step a stride, as `--table2 'biped run'`
    measures on the steps of either foot (the paper's biped stride is one step)."""
    settings = ["speed=1.5m/s"]
    run = run_creature(generated, "biped", "run", settings, 20.0)
    steps = table2_metrics(run, "biped", "biped run", 3.0)
    assert steps.reference == "either"
    check = Comparison(f"{run_command('biped', 'run', settings, 20)} && legdsl metrics runs/x "
                       "--from 3 --table2 'biped run'")  # fmt: skip
    for row in BIPED_TABLE2:
        label = _label(row)
        key = next(k for prefix, k in BIPED_TABLE2_ROWS.items() if label.startswith(prefix))
        s = steps.summary(key)
        check.figures(row, f"{label}, this run", [s.value, s.std], numbers(row["this run"]))
    check.check()


BOUND_TABLE2_ROWS = {  # the bound's Table 2: the metric of each row (table2.toml's measure)
    "pitch magnitude": "pitch_magnitude",
    "stride length": "stride_length",
    "stride duration": "stride_duration",
    "gathered flight": "flight_time_before_rear",
    "extended flight": "flight_time_before_front",
    "stance, front legs": "stance_duration_front",
    "stance, rear legs": "stance_duration_rear",
    "change of leg length": "leg_length_change",
    "running speed": "running_speed",
}


def test_the_quadruped_bound_table2(generated: Path) -> None:
    """docs/quadruped.md's Table 2 of the bound: `this run` (the run before the speed
    correction, in brackets, is not rerun)."""
    column = list(BOUND_TABLE2[0].cells)[1]  # "this run (2.8 m/s)"
    settings = [f"speed={_speed(column.replace('(', ''))}"]  # numbers() skips brackets
    run = run_creature(generated, "quadruped", "bound", settings, 20.0)
    m = table2_metrics(run, "quadruped", "quadruped bound", 3.0)
    check = Comparison(f"{run_command('quadruped', 'bound', settings, 20)} && legdsl metrics "
                       "runs/x --from 3 --table2 'quadruped bound'")  # fmt: skip
    for row in BOUND_TABLE2:
        label = _label(row)
        key = next(k for prefix, k in BOUND_TABLE2_ROWS.items() if label.startswith(prefix))
        s = m.summary(key)
        check.figures(row, f"{label}, {column}", [s.value, s.std], numbers(row[column]))
    check.check()
