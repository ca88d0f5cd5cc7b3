"""Joint limits as mechanical stops (issue 18, item 5): 'stop k = ..., b = ...' beside a
joint's limits makes them a one-sided spring-damper in the runtime and in the MJCF export;
a run reports the time spent on each stop. Without 'stop' nothing changes."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

from legdsl.check.source import check_file
from legdsl.cli import main
from legdsl.export.mjcf import model_to_mjcf
from legdsl.lang.errors import LegError

ROOT = Path(__file__).resolve().parents[2]
HOPPER = (ROOT / "creatures" / "hopper.leg").read_text()
LEG_LIMITS = "    limits -0.25 m to 0.1 m\n"
HIP_LIMITS = "    limits -60 deg to 60 deg\n"


def _hopper(tmp_path: Path, text: str, name: str = "hopper.leg") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


@pytest.mark.parametrize(
    ("stop", "message"),
    [
        ("stop k = 2e4 N/m, b = 100 N*s/m", None),
        ("stop k = 2e4 N/m", None),
        ("stop k = 2e4 N*m/rad", "linear stiffness"),
        ("stop k = -5 N/m", "must be positive"),
        ("stop b = 5 N*s/m", "needs its stiffness k"),
        ("stop k = 1 N/m, c = 2", "not 'c'"),
        ("stop 5 N/m", "write the stop as"),
    ],
)
def test_the_stop_is_checked(tmp_path: Path, stop: str, message: str | None) -> None:
    path = _hopper(tmp_path, HOPPER.replace(LEG_LIMITS, LEG_LIMITS + f"    {stop}\n"))
    if message is None:
        (model,) = check_file(path)
        assert [(s.dof, s.low, s.high) for s in model.stops] == [("leg", -0.25, 0.1)]
        return
    with pytest.raises(LegError) as err:
        check_file(path)
    assert message in err.value.render()


def test_a_stop_needs_limits(tmp_path: Path) -> None:
    text = HOPPER.replace(LEG_LIMITS, "    stop k = 2e4 N/m\n")
    with pytest.raises(LegError, match="a stop needs the joint's limits"):
        check_file(_hopper(tmp_path, text))


def _run(path: Path, generated: Path, out: Path) -> dict:
    argv = ["run", str(path), "--controller", "hop", "--time", "1.5", "--generated",
            str(generated), "--out", str(out)]  # fmt: skip
    assert main(argv) in (0, 4)
    return json.loads((out / "run.json").read_text())


def test_a_stop_holds_the_joint_and_its_time_is_reported(generated: Path, tmp_path: Path) -> None:
    tight = HOPPER.replace(HIP_LIMITS, "    limits -5 deg to 5 deg\n")
    free = _run(_hopper(tmp_path, tight, "free.leg"), generated, tmp_path / "free")
    stopped = tight.replace(
        "    limits -5 deg to 5 deg\n",
        "    limits -5 deg to 5 deg\n    stop k = 500 N*m/rad, b = 5 N*m*s/rad\n",
    )
    held = _run(_hopper(tmp_path, stopped, "held.leg"), generated, tmp_path / "held")
    assert "time_on_stops" not in free  # a limit alone is not a stop
    assert held["time_on_stops"]["hip"] > 0.1
    q_free = np.load(tmp_path / "free" / "trajectory.npz")["q"][:, 3]
    q_held = np.load(tmp_path / "held" / "trajectory.npz")["q"][:, 3]
    n = min(len(q_free), len(q_held))
    assert np.abs(q_held[:n]).max() < np.abs(q_free[:n]).max()


def test_a_stop_that_is_never_reached_changes_nothing(generated: Path, tmp_path: Path) -> None:
    plain = _run(_hopper(tmp_path, HOPPER, "plain.leg"), generated, tmp_path / "plain")
    text = HOPPER.replace(LEG_LIMITS, LEG_LIMITS + "    stop k = 2e4 N/m, b = 100 N*s/m\n")
    with_stop = _run(_hopper(tmp_path, text, "stop.leg"), generated, tmp_path / "stop")
    assert with_stop["time_on_stops"] == {"leg": 0.0}
    for name in ("trajectory.npz", "trajectory.csv"):
        assert (tmp_path / "plain" / name).read_bytes() == (tmp_path / "stop" / name).read_bytes()
    assert plain["status"] == with_stop["status"]


def test_the_mjcf_export_carries_the_stop(tmp_path: Path) -> None:
    text = HOPPER.replace(LEG_LIMITS, LEG_LIMITS + "    stop k = 2e4 N/m, b = 100 N*s/m\n")
    (model,) = check_file(_hopper(tmp_path, text))
    xml = model_to_mjcf(model)
    # scaled to MuJoCo's acceleration units (tests/export/test_mjcf_stops.py checks the force)
    assert 'name="leg" type="slide" axis="0 0 -1" range="-0.25 0.1" solreflimit="-' in xml
    (plain,) = check_file(ROOT / "creatures" / "hopper.leg")
    assert "solreflimit" not in model_to_mjcf(plain)


def test_a_stop_too_stiff_for_the_step_is_warned_of_before_the_run(
    generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A stop of 1e12 N/m ran, and diverged only when reached; an actuator as stiff is refused
    before the run. A stop acts only once its limit is reached, so it gets a warning, at its
    line, with the bound (a stop the step can hold, above, gets none)."""
    text = HOPPER.replace(LEG_LIMITS, LEG_LIMITS + "    stop k = 1e12 N/m\n")
    path = _hopper(tmp_path, text)
    _run(path, generated, tmp_path / "run")
    err = capsys.readouterr().err
    assert (
        f"legdsl: warning: {path}:29:5: the stop of joint coordinate leg is too stiff for " in err
    )
    assert "use k below" in err and "a run that reaches it diverges there" in err
    _run(_hopper(tmp_path, HOPPER.replace(LEG_LIMITS, LEG_LIMITS + "    stop k = 2e4 N/m\n"),
                 "ok.leg"), generated, tmp_path / "ok")  # fmt: skip
    assert "warning" not in capsys.readouterr().err


def test_a_stop_too_stiff_is_told_in_the_unit_written_on_its_line(
    generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The warning gave k and its bound bare, in SI ('k = 1e+07: use k below 1.39e+04' for a
    stop written in kN/m): written into the line as kN/m, the bound was 1000 times too stiff."""
    text = HOPPER.replace(LEG_LIMITS, LEG_LIMITS + "    stop k = 1e4 kN/m, b = 0.1 kN*s/m\n")
    _run(_hopper(tmp_path, text), generated, tmp_path / "run")
    err = capsys.readouterr().err
    said = re.search(r"\(k = (\S+) (\S+)\): use k below (\S+) (\S+),", err)
    assert said is not None, err
    assert float(said[1]) == 1e4 and said[2] == said[4] == "kN/m"
    text = text.replace("1e4 kN/m", f"{said[3]} kN/m")  # the bound, in the line's unit
    _run(_hopper(tmp_path, text, "bound.leg"), generated, tmp_path / "bound")
    assert "too stiff" not in capsys.readouterr().err


MIRRORED_ARMS = """
creature arms {
  planar
  body base fixed { mass 1 kg  inertia 0.01 kg*m^2 }
  template arm(S) {
    body link_S on base via revolute j_S at (0.1 m, 0 m) {
      length 0.2 m  com 0.1 m  mass 0.2 kg  inertia 0.001 kg*m^2
      initial 30 deg
      limits 10 deg to 90 deg
      stop k = 100 N*m/rad, b = 1 N*m*s/rad
    }
  }
  instance a = arm(S = a)
  instance b = arm(S = b) mirror frontal
}
"""


def test_a_mirrored_stop_is_at_the_mirrored_limits(tmp_path: Path) -> None:
    """The mirror negates j_b (a hinge about y under x -> -x): its limits and their stop are
    [-90, -10] deg, so the arm swings down as the mirror image of j_a and meets its stop at
    -10 deg (the stop once stayed at [10, 90] deg: j_b started 40 deg past it)."""
    path = tmp_path / "arms.leg"
    path.write_text(MIRRORED_ARMS)
    (model,) = check_file(path)
    stops = {s.dof: (s.low, s.high) for s in model.stops}
    assert stops["j_b"] == pytest.approx((-np.radians(90), -np.radians(10)))
    assert stops["j_b"] == tuple(model.joint("j_b").dofs[0].limits or ())
    argv = ["run", str(path), "--time", "0.5", "--generated", str(tmp_path / "gen"),
            "--out", str(tmp_path / "run")]  # fmt: skip
    assert main(argv) == 0
    q = np.load(tmp_path / "run" / "trajectory.npz")["q"]
    np.testing.assert_allclose(q[:, 1], -q[:, 0], rtol=0, atol=1e-12)
    assert q[-1, 0] == pytest.approx(np.radians(10), abs=np.radians(0.1))  # on the stop
    spent = json.loads((tmp_path / "run" / "run.json").read_text())["time_on_stops"]
    assert spent["j_a"] == spent["j_b"] > 0.1
