"""Two references no one here wrote agree on the exported models: sympy's Kane and MuJoCo.

The benchmark's Kane baseline (``benchmarks/kane_baseline.py``) builds the
equations of motion from the model IR with sympy.physics.mechanics; MuJoCo
runs the exported MJCF. Equal accelerations check the exporter's joint
semantics (several primitives in one body, skewed axes, welds, a fixed root,
the free root's quaternion and body-axis angular velocity) and the baseline.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import mujoco
import numpy as np
import pytest
from conftest import ROOT
from mjhelpers import index_maps, load_mjcf, random_state, set_state

from legdsl.check.source import check_model
from tests.export.test_export import BRICK, ZOO

sys.path.insert(0, str(ROOT / "benchmarks"))
from kane_baseline import compile_kane  # noqa: E402


@pytest.mark.parametrize("name", ["brick", "zoo"])
def test_kane_and_mujoco_accelerations_agree(name: str, tmp_path: Path) -> None:
    leg = tmp_path / f"{name}.leg"
    leg.write_text({"brick": BRICK, "zoo": ZOO}[name])
    model = check_model(leg)
    out = tmp_path / f"kane_{name}.py"
    compile_kane(model, out)
    spec = importlib.util.spec_from_file_location(f"kane_{name}", out)
    assert spec is not None and spec.loader is not None
    kane = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(kane)

    mj = load_mjcf(model)
    mj.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONTACT
    mj.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_ACTUATION
    data = mujoco.MjData(mj)
    maps = index_maps(model, mj)
    rng = np.random.default_rng(17)
    for _ in range(10):
        q, v = random_state(model, rng)
        tau = rng.normal(size=model.nv)
        set_state(mj, data, maps, q, v)
        data.qfrc_applied[maps[1]] = tau
        mujoco.mj_forward(mj, data)
        want = data.qacc_smooth[maps[1]]
        got = kane.forward_dynamics(list(q), list(v), tau)
        assert np.linalg.norm(got - want) <= 1e-9 * max(1.0, np.linalg.norm(want))
        m, _ = kane.mass_forcing(list(q), list(v))
        full = np.zeros((mj.nv, mj.nv))
        mujoco.mj_fullM(mj, data, full)
        want_m = full[np.ix_(maps[1], maps[1])]
        assert np.linalg.norm(m - want_m) <= 1e-9 * max(1.0, np.linalg.norm(want_m))
