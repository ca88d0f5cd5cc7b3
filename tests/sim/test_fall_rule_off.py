"""The fall rule turned off, for a creature built to crawl or lie on the ground (an outside
user's snake, its ``nose`` contact at the root's origin): it always ended 'fell', since the
ground's spring lets a resting root sink a few mm and even ``--fall-height 0`` was a fall, and
``--fall-height=-1m`` was refused without saying what to write instead. ``--fall-height off``
and ``--fall-tilt off`` (``fall_height='off'``, ``fall_tilt='off'`` in Python) turn it off, in
both backends, and run.json and the command to run again say so (docs/runtime.md)."""

from __future__ import annotations

import json
import math
import shlex
from pathlib import Path

import numpy as np
import pytest
from runtime_helpers import needs_c_compiler

from legdsl.cli import main

CRAWLER = """\
creature crawler {
  planar
  gravity 9.81 m/s^2

  body head free {
    mass 2 kg  inertia 0.02 kg*m^2
    length 0.3 m  direction (1, 0)  com 0.15 m
    initial x = 0 m, z = 0.3 m, pitch = 0 deg
  }
  body l1 on head via revolute j1 at tip {
    length 0.3 m  direction (1, 0)  com 0.15 m  mass 1 kg  inertia 0.0075 kg*m^2
    initial 20 deg
  }
  body l2 on l1 via revolute j2 at tip {
    length 0.25 m  direction (1, 0)  com 0.1 m  mass 0.8 kg  inertia 0.005 kg*m^2
    initial -35 deg
  }
  contact nose on head
  contact c1 on l1 at tip
  contact tail on l2 at tip

  actuator s1 on j1 servo(kp = 40 N*m/rad, kv = 1 N*m*s/rad, setpoint = 0 deg)
  actuator s2 on j2 servo(kp = 40 N*m/rad, kv = 1 N*m*s/rad, setpoint = 0 deg)

  ground {
    normal spring(k = 2e4 N/m, b = 200 N*s/m)
    tangent spring(k = 1e4 N/m, b = 100 N*s/m)
  }
}

controller wave {
  param amp = 30 deg
  param period = 300 ms
  table {
    state UP   on time_in_state >= period: s1.setpoint = amp; s2.setpoint = -amp
    state DOWN on time_in_state >= period: s1.setpoint = -amp; s2.setpoint = amp
  }
}
"""


@pytest.fixture
def crawler(tmp_path: Path) -> Path:
    leg = tmp_path / "crawler.leg"
    leg.write_text(CRAWLER)
    return leg


def _run(leg: Path, out: Path, *extra: str, capsys: pytest.CaptureFixture[str]) -> tuple[int, str]:
    code = main(["run", str(leg), "--generated", str(leg.parent / "gen"), "--controller",
                 "wave", "--time", "1", "--out", str(out), *extra])  # fmt: skip
    err = capsys.readouterr().err
    assert "Traceback" not in err and "internal error" not in err, err
    return code, err


@pytest.mark.parametrize("backend", ["python", pytest.param("c", marks=needs_c_compiler)])
def test_a_crawler_on_the_ground_runs_with_the_fall_rule_off(
    crawler: Path, capsys: pytest.CaptureFixture[str], backend: str
) -> None:
    lying = crawler.parent / f"lying-{backend}"
    code, err = _run(crawler, lying, "--fall-height", "0", "--fall-tilt", "179deg",
                     "--backend", backend, capsys=capsys)  # fmt: skip
    assert code == 4 and "the root fell to -0.00" in err, err  # sunk into the ground's spring
    crawling = crawler.parent / f"crawling-{backend}"
    code, err = _run(crawler, crawling, "--fall-height", "off", "--fall-tilt", "OFF",
                     "--backend", backend, capsys=capsys)  # fmt: skip
    assert code == 0, err
    info = json.loads((crawling / "run.json").read_text())
    assert info["status"] == "ok" and info["sim_time"] == 1.0
    assert info["options"]["fall_height"] == "off"
    assert info["options"]["fall_tilt"] == math.pi  # no tilt is past upside down
    assert min(info["options"].values(), key=str) is not None  # run.json is plain JSON


@needs_c_compiler
def test_the_backends_agree_with_the_fall_rule_off(
    crawler: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    runs = {}
    for backend in ("python", "c"):
        out = crawler.parent / backend
        code, err = _run(crawler, out, "--fall-height", "off", "--backend", backend,
                         capsys=capsys)  # fmt: skip
        assert code == 0, err
        runs[backend] = np.load(out / "trajectory.npz")
    assert runs["python"].files == runs["c"].files
    for name in runs["python"].files:
        assert np.array_equal(runs["python"][name], runs["c"][name], equal_nan=True), name


def test_the_command_to_run_again_says_off(
    crawler: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = crawler.parent / "run"
    code, err = _run(crawler, out, "--fall-height", "off", "--fall-tilt", "off", capsys=capsys)
    assert code == 0, err
    crawler.write_text(CRAWLER.replace("mass 2 kg", "mass 2.5 kg"))  # made from another file
    assert main(["plot", str(out)]) == 2
    said = capsys.readouterr().err
    words = shlex.split(said.split("run it again (", 1)[1].rstrip().removesuffix(")"))
    at = words.index("--fall-height")
    assert words[at + 1] == "off" and words[words.index("--fall-tilt") + 1] == "180deg"


@pytest.mark.parametrize(
    ("option", "said"),
    [
        ("--fall-height=-1m", "--fall-height must not be negative; to turn the fall rule's "
         "height off (a creature built to crawl or lie on the ground), write --fall-height off"),
        ("--fall-tilt=0deg", "--fall-tilt must be more than zero; to turn the fall rule's tilt "
         "off (a creature built to crawl or lie on the ground), write --fall-tilt off"),
        ("--fall-tilt=200deg", "give at most 180deg, or off"),
    ],
)  # fmt: skip
def test_a_refused_fall_limit_says_how_to_turn_the_rule_off(
    crawler: Path, capsys: pytest.CaptureFixture[str], option: str, said: str
) -> None:
    out = crawler.parent / "refused"
    code, err = _run(crawler, out, option, capsys=capsys)
    assert code == 2 and said in err, err
    assert not out.exists()


def test_the_api_turns_the_fall_rule_off(crawler: Path) -> None:
    import legdsl
    from legdsl.lang.errors import UsageError

    creature = legdsl.load(str(crawler), generated=str(crawler.parent / "gen"))
    run = creature.run(controller="wave", time=1, fall_height="off", fall_tilt=" Off ")
    assert run.status == "ok", run.message
    with pytest.raises(UsageError, match=r"fall_height='off'"):
        creature.run(controller="wave", time=1, fall_height="-1 m")
    with pytest.raises(UsageError, match=r"^run\(\): fall_height=-1.0: .*write fall_height='off'$"):
        creature.run(controller="wave", time=1, fall_height=-1.0)
