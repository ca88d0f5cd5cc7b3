"""``legdsl replay DIR --mujoco``: a recorded legdsl run played in MuJoCo.

The creature is the MJCF export of its ``.leg`` file (``legdsl.export.mjcf``);
MuJoCo does not simulate anything here: each frame sets ``qpos`` from the run
(coordinates matched by name, as in the tests) and calls ``mj_forward``, so
what is shown is legdsl's motion on MuJoCo's model and renderer.

With a display, MuJoCo's interactive viewer (``mujoco.viewer``) plays the run
in real time, looping. Without one, or with ``-o FILE.mp4``, MuJoCo's
offscreen renderer draws the frames (``MUJOCO_GL=egl`` by default, which works
without a display on Mesa; ``osmesa`` elsewhere) and ffmpeg encodes them; where
no OpenGL context can be had the command says so and why.
"""

from __future__ import annotations

import os
import platform
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from legdsl.export.frames import enough_frames, every_frame, interpolate_q
from legdsl.export.mjcf import mjcf_names, model_to_mjcf
from legdsl.export.motion import drawable, read_run
from legdsl.export.video import FFMPEG_HINT, _write_mp4, ffmpeg_exe
from legdsl.files import atomic_path
from legdsl.ir.model import Model
from legdsl.lang.errors import UsageError
from legdsl.pipeline.optional import not_installed
from legdsl.signals import import_held

# MuJoCo's own list (mujoco/rendering/classic/gl_context.py), by platform
_GL_VALUES = {"Linux": "egl, osmesa, glx", "Windows": "wgl", "Darwin": "cgl"}


# what the offscreen renderer needs, said by each way it fails to start
_OPENGL_ADVICE = (
    "It needs OpenGL without a display: EGL (Mesa's libegl1, MUJOCO_GL=egl) or "
    "OSMesa (libosmesa6, MUJOCO_GL=osmesa); with a display, run without -o to use the viewer"
)


def _mujoco() -> Any:
    os.environ.setdefault("MUJOCO_GL", "egl")  # before mujoco is imported: offscreen on Mesa
    gl = os.environ["MUJOCO_GL"]
    try:
        mujoco = import_held("mujoco")
    except ImportError as e:
        if not not_installed(e, "mujoco"):
            raise
        raise UsageError(
            "replaying in MuJoCo needs the mujoco package: pip install mujoco"
        ) from None
    except RuntimeError as e:  # mujoco's import checks MUJOCO_GL's value
        if "MUJOCO_GL" not in str(e):
            raise
        values = _GL_VALUES.get(platform.system(), "")
        raise UsageError(
            f"MUJOCO_GL={gl} is not a value MuJoCo takes: set it to one of "
            f"{values + ', ' if values else ''}glfw (with a display), or unset it for egl"
        ) from None
    except (AttributeError, OSError) as e:
        # mujoco's import loads the MUJOCO_GL backend's library; PyOpenGL without libOSMesa
        # fails inside its own import ("'NoneType' object has no attribute 'glGetError'")
        raise UsageError(
            f"MuJoCo could not load its OpenGL backend (MUJOCO_GL={gl}): {e}. {_OPENGL_ADVICE}"
        ) from None
    return mujoco


def qpos_map(model: Model, mj: Any) -> np.ndarray:
    """MuJoCo qpos[map[i]] is legdsl q[i], by coordinate name (the free root's joint is
    ``mjcf_names``': 'root')."""
    out = np.full(model.nq, -1)
    free = mjcf_names(model)[1]
    for j in model.joints:
        if j.is_free_3d:
            out[j.q_start : j.q_start + 7] = mj.joint(free).qposadr[0] + np.arange(7)
            continue
        for d in j.dofs:
            out[d.q_index] = mj.joint(d.name).qposadr[0]
    return out


def replay_frames(
    directory: Path, fps: float, source: Path | None = None
) -> tuple[Any, Any, Model, np.ndarray, np.ndarray]:
    """The MuJoCo model and data, the legdsl model, frame times and MuJoCo qpos per frame."""
    mujoco = _mujoco()
    run = drawable(read_run(directory, source, drawn=True))
    # the bare link tree: anchor pads are for MuJoCo's simulation, and one a light body cannot
    # carry refused the replay, saying to export with --no-anchor-pads, which replay has not;
    # a drawing: a mite's inertias under MuJoCo's floor are raised to it, not refused
    mj = mujoco.MjModel.from_xml_string(model_to_mjcf(run.model, pads=False, drawing=True))
    try:
        data = mujoco.MjData(mj)
    except mujoco.FatalError as e:  # "Could not allocate memory": its arena, under ulimit -v
        raise MemoryError(str(e)) from None
    tr = run.trajectory
    # every frame 1/fps after the one before, as the mp4 plays them (the player's frame_times,
    # never denser than the samples, played a run recorded at 10 Hz three times too fast)
    span = float(tr.t[-1] - tr.t[0])
    enough_frames(span, fps, usual=30.0)
    at = tr.t[0] + every_frame(span, fps)
    q = interpolate_q(run.model, tr.t, tr.q, at)
    qpos = np.tile(mj.qpos0, (len(at), 1))
    qpos[:, qpos_map(run.model, mj)] = q
    return mj, data, run.model, at - tr.t[0], qpos


def render_mp4(
    directory: Path,
    out: Path,
    fps: float = 30.0,
    size: tuple[int, int] = (960, 540),
    source: Path | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> int:
    """Render the run with MuJoCo's offscreen renderer to ``out`` (mp4); returns the frame count."""
    if ffmpeg_exe() is None:
        raise UsageError(FFMPEG_HINT)
    mujoco = _mujoco()
    mj, data, model, times, qpos = replay_frames(directory, fps, source)
    width, height = (size[0] // 2) * 2, (size[1] // 2) * 2
    mj.vis.global_.offwidth = max(mj.vis.global_.offwidth, width)
    mj.vis.global_.offheight = max(mj.vis.global_.offheight, height)
    try:
        renderer = mujoco.Renderer(mj, height, width)
    except Exception as err:  # no OpenGL context: say which backend failed and what to try
        from legdsl.sim.recorder import address_space_left

        limited = address_space_left() is not None  # OpenGL fails so with too little room
        raise UsageError(
            f"MuJoCo's offscreen renderer could not start (MUJOCO_GL={os.environ.get('MUJOCO_GL')}): "
            f"{err}. {_OPENGL_ADVICE}"
            + ("; or raise the memory limit (ulimit -v), which OpenGL shares" if limited else "")
        ) from None
    camera = _camera(mujoco, model, mj, data, qpos[0])
    root = _root_body(model)

    def frames() -> Any:
        for f in range(len(times)):
            data.qpos[:] = qpos[f]
            mujoco.mj_forward(mj, data)
            camera.lookat[:2] = data.body(root).xpos[:2]
            renderer.update_scene(data, camera)
            yield renderer.render()

    out.parent.mkdir(parents=True, exist_ok=True)
    try:
        with atomic_path(out) as tmp:  # interrupted, no half of an mp4 under its name
            _write_mp4(
                frames(),
                tmp,
                fps,
                width,
                height,
                lambda i: progress(i + 1, len(times)) if progress else None,
            )
    finally:
        renderer.close()
    return len(times)


def _root_body(model: Model) -> str:
    """The MJCF name of the creature's root body (``world_`` for a body named ``world``)."""
    return mjcf_names(model)[0][model.bodies[0].name]


def _camera(mujoco: Any, model: Model, mj: Any, data: Any, qpos0: np.ndarray) -> Any:
    """A free camera beside the creature (from -y for a planar one), following its root."""
    data.qpos[:] = qpos0
    mujoco.mj_forward(mj, data)
    camera = mujoco.MjvCamera()
    camera.type = mujoco.mjtCamera.mjCAMERA_FREE
    # the bodies and the contacts (the feet: the bare tree's bodies end at the knees, and the
    # biped's 0.83 m were 0.2 m without them)
    extent = float(np.ptp(np.vstack([data.xpos[1:], data.site_xpos]), axis=0).max())
    # half a metre of margin; a creature under 25 cm gets 0.6 of its extent, as the shipped
    # ones (0.8 m) have about (a 5 cm hopper was a speck in a 2.5 m view)
    # one body with its contacts at its origin has no extent: the camera stood inside it
    extent = extent or float(mj.stat.extent)
    size = extent + (0.5 if extent >= 0.25 else 0.6 * extent)
    camera.distance = 4.5 * size
    camera.azimuth = 90.0 if model.planar else 120.0
    camera.elevation = -8.0 if model.planar else -20.0
    camera.lookat[:] = data.body(_root_body(model)).xpos
    camera.lookat[2] = 0.7 * camera.lookat[2]
    return camera


def view(directory: Path, fps: float = 60.0, source: Path | None = None) -> None:
    """Play the run in MuJoCo's interactive viewer, in real time, looping, until it is closed."""
    _mujoco()
    import mujoco.viewer

    mj, data, _, times, qpos = replay_frames(directory, fps, source)
    with mujoco.viewer.launch_passive(mj, data) as viewer:
        start = time.perf_counter()
        while viewer.is_running():
            t = (time.perf_counter() - start) % max(float(times[-1]), 1e-9)
            f = int(np.searchsorted(times, t, side="right") - 1)
            data.qpos[:] = qpos[max(f, 0)]
            mujoco.mj_forward(mj, data)
            viewer.sync()
            time.sleep(1.0 / fps)


def has_display() -> bool:
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))
