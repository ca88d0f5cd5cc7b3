"""The C print of the dynamics computes the same doubles as the Python print.

For every shipped creature, every function of ``dynamics.c`` is called through ctypes at random
states and compared with the same function of the golden ``dynamics.py`` by ``==`` on every
float, and byte for byte (a zero's sign counts). Where Python raises (``math.cos`` of an
infinity), the C function flags the same error (``legdsl_math.h``).
"""

from __future__ import annotations

import ctypes
import inspect
import math
import random
from pathlib import Path

import pytest
from conftest import GENERATED, SHIPPED, shipped_dynamics, shipped_model

from legdsl.codegen.c.build import build, find_compiler, sources
from legdsl.codegen.c.dynamics import C_FUNCTIONS, flatten
from legdsl.codegen.c.slices import SLICED, parts_of

pytestmark = pytest.mark.skipif(
    find_compiler() is None,
    reason="the C backend's tests need a C compiler (cc, gcc or clang; apt-get install gcc)",
)

DOUBLES = ctypes.POINTER(ctypes.c_double)


def _library(name: str) -> ctypes.CDLL:
    return ctypes.CDLL(str(build(name, sources(GENERATED / name)).path))


def _state(name: str, rng: random.Random) -> dict[str, list[float]]:
    model = shipped_model(name)
    q = [rng.uniform(-1.5, 1.5) for _ in range(model.nq)]
    if model.joints[0].is_free_3d:  # a quaternion, not of unit norm (the code divides by it)
        q[3:7] = [rng.uniform(-1.0, 1.0) for _ in range(4)]
    return {
        "q": q,
        "v": [rng.uniform(-5.0, 5.0) for _ in range(model.nv)],
        "tau": [rng.uniform(-50.0, 50.0) for _ in range(model.nv)],
    }


def _call_c(lib: ctypes.CDLL, name: str, params: tuple[str, ...], state: dict[str, list[float]],
            size: int) -> tuple[list[float], int]:  # fmt: skip
    args = [(ctypes.c_double * len(state[p]))(*state[p]) for p in params]
    out = (ctypes.c_double * size)()
    err = ctypes.c_int(0)
    getattr(lib, name)(*args, out, ctypes.byref(err))
    return list(out), err.value


@pytest.mark.parametrize("name", SHIPPED)
def test_every_function_equals_the_python_print(name: str) -> None:
    lib = _library(name)
    dyn = shipped_dynamics(name)
    rng = random.Random(f"c-dynamics-{name}")
    checked = 0
    for _ in range(60):
        state = _state(name, rng)
        for fname in C_FUNCTIONS:
            params = tuple(inspect.signature(getattr(dyn, fname)).parameters)  # q, v, tau
            expected = [float(x) for x in flatten(getattr(dyn, fname)(*(state[p] for p in params)))]
            got, err = _call_c(lib, fname, params, state, len(expected))
            assert err == 0, fname
            assert got == expected, f"{name}.{fname} differs at {state}"
            # byte for byte: -0.0 == 0.0, so compare the bits too
            assert [math.copysign(1, x) for x in got] == [math.copysign(1, x) for x in expected]
            checked += len(expected)
    assert checked > 1000


def test_the_table_of_sines_gives_what_libm_gives_for_each_angle_bit_for_bit() -> None:
    """dynamics.c remembers sin and cos by the argument's bits: 0.0 and -0.0 (whose sines
    differ in sign) are two entries, and angles that evict each other are taken again."""
    name = "hopper"  # planar: the pitch's sine is an entry of the root's rotation
    lib, dyn = _library(name), shipped_dynamics(name)
    base = _state(name, random.Random("trig-table"))
    angles = [0.0, -0.0, 0.0, 1e-300, -1e-300] + [0.01 * k for k in range(200)] + [-0.0, 0.0]
    for angle in angles:
        state = {**base, "q": [*base["q"][:2], angle, -angle, *base["q"][4:]]}
        for fname in ("body_poses", "forward_dynamics"):
            params = ("q",) if fname == "body_poses" else ("q", "v", "tau")
            expected = [float(x) for x in flatten(getattr(dyn, fname)(*(state[p] for p in params)))]
            got, err = _call_c(lib, fname, params, state, len(expected))
            assert err == 0
            assert [x.hex() for x in got] == [x.hex() for x in expected], (fname, angle)


def _has_fma() -> bool:
    try:
        return " fma " in Path("/proc/cpuinfo").read_text().replace("\n", " ")
    except OSError:
        return False


@pytest.mark.skipif(not _has_fma(), reason="the processor has no FMA instructions to tempt gcc")
def test_the_flags_keep_fused_multiply_adds_out_even_with_fma_allowed(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """With -mfma, gcc's vectorizer would fuse a product into an add-and-subtract in spite of
    -ffp-contract=off (the biped's dynamics then differ); legdsl's flags keep it out."""
    import legdsl.codegen.c.build as build_module

    monkeypatch.setattr(build_module, "FLAGS", (*build_module.FLAGS, "-mfma"))
    lib = _library("biped")
    dyn = shipped_dynamics("biped")
    model = shipped_model("biped")
    rng = random.Random("fma")
    for _ in range(100):
        state = _state("biped", rng)
        got, _ = _call_c(lib, "forward_dynamics", ("q", "v", "tau"), state, model.nv)
        assert got == dyn.forward_dynamics(state["q"], state["v"], state["tau"])


@pytest.mark.parametrize("name", ["hopper", "biped"])
def test_an_infinite_angle_is_a_domain_error_as_in_python(name: str) -> None:
    lib = _library(name)
    dyn = shipped_dynamics(name)
    model = shipped_model(name)
    state = _state(name, random.Random(1))
    hinge = [d for d in model.dofs if d.motion == "hinge"][-1]  # a joint angle, not the root
    state["q"][hinge.q_index] = math.inf
    with pytest.raises(ValueError, match="math domain error"):
        dyn.forward_dynamics(state["q"], state["v"], state["tau"])
    _, err = _call_c(lib, "forward_dynamics", ("q", "v", "tau"), state, model.nv)
    assert err == 1  # LEG_EDOM: ValueError("math domain error")


def test_the_header_names_the_source_and_the_sizes() -> None:
    text = (GENERATED / "biped" / "dynamics.h").read_text()
    assert text.startswith("/* Generated by legdsl") and "creatures/biped.leg" in text
    model = shipped_model("biped")
    assert f"#define LEG_NV {model.nv}\n" in text
    assert f"#define LEG_OUT_FORWARD_DYNAMICS {model.nv}\n" in text


def test_a_controller_with_no_c_twin_is_printed_as_a_stub_for_python() -> None:
    """A control law the C printer cannot spell exactly (here math.erf) keeps the controller
    on the Python state machine: the C file says so, and says nothing else."""
    import dataclasses

    import sympy
    from conftest import compiled_creature

    from legdsl.codegen.c.control import render_control_c
    from legdsl.lower.control import Setting

    compiled = compiled_creature("hopper")
    lc = compiled.lowered[0]
    key, body = next(iter(sorted(lc.bodies.items())))
    odd = Setting("hip_motor", "force", sympy.erf(sympy.Symbol("input_speed")))
    bodies = dict(lc.bodies)
    bodies[key] = dataclasses.replace(body, settings=(*body.settings, odd))
    text = render_control_c(compiled.model, dataclasses.replace(lc, bodies=bodies),
                            "creatures/hopper.leg", {s: "" for s in lc.states}, "x")  # fmt: skip
    assert "const int64_t leg_has_c_controller = 0;" in text
    assert "math.erf" in text and "static" not in text
    normal = render_control_c(compiled.model, lc, "creatures/hopper.leg",
                              {s: "" for s in lc.states}, "x")  # fmt: skip
    assert "const int64_t leg_has_c_controller = 1;" in normal


def _call_some(lib: ctypes.CDLL, name: str, params: tuple[str, ...],
               state: dict[str, list[float]], want: list[int], size: int) -> tuple[list[float], int]:  # fmt: skip
    args = [(ctypes.c_double * len(state[p]))(*state[p]) for p in params]
    out = (ctypes.c_double * size)(*([12345.0] * size))
    err = ctypes.c_int(0)
    getattr(lib, f"{name}_some")(*args, (ctypes.c_ubyte * len(want))(*want), out, ctypes.byref(err))
    return list(out), err.value


@pytest.mark.parametrize("name", SHIPPED)
def test_the_some_functions_write_the_wanted_parts_as_the_whole_functions_do(name: str) -> None:
    """NAME_some writes the outputs of the wanted parts (a contact; a body's position or
    rotation) bit for bit as NAME does, leaves the others as they were, and flags NAME's error:
    an infinite angle of a part not wanted is still Python's domain error, and a zero
    quaternion still divides by zero."""
    lib, dyn = _library(name), shipped_dynamics(name)
    model = shipped_model(name)
    rng = random.Random(f"c-some-{name}")
    hinges = [d.q_index for d in model.dofs if d.motion == "hinge"]
    checked = 0
    for trial in range(40):
        state = _state(name, rng)
        for fname in SLICED:
            params = tuple(inspect.signature(getattr(dyn, fname)).parameters)
            result = getattr(dyn, fname)(*(state[p] for p in params))
            whole = [float(x) for x in flatten(result)]
            by_part = parts_of(result, SLICED[fname])
            want = [rng.random() < 0.4 for _ in by_part]
            got, err = _call_some(lib, fname, params, state, want, len(whole))
            assert err == 0
            for p, ks in enumerate(by_part):
                for k in ks:
                    expected = whole[k] if want[p] else 12345.0
                    assert got[k].hex() == expected.hex(), (fname, p, k)
                    checked += 1
            broken = dict(state, q=list(state["q"]))
            if trial % 2 and hinges:
                broken["q"][rng.choice(hinges)] = math.inf
            elif model.joints[0].is_free_3d:
                broken["q"][3:7] = [0.0] * 4
            else:
                continue
            _, whole_err = _call_c(lib, fname, params, broken, len(whole))
            _, some_err = _call_some(lib, fname, params, broken, [0] * len(by_part), len(whole))
            assert some_err == whole_err, fname
    assert checked > 1000
