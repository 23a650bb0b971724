"""Headless pictures of a robot: MuJoCo renders of configurations, saved as PNG, GIF or MP4.

Rendering is offscreen through an OpenGL context chosen by the ``MUJOCO_GL`` environment
variable (``egl`` or ``osmesa`` without a display; ``glfw`` with one). When it is unset
and there is no display, EGL is used. The renderer sets ``q`` on the robot's chain (every
other joint at its home value, :meth:`Robot.full_qpos`), runs the kinematics and draws
the model's geoms, with an optional target frame drawn as three RGB axes.

Typical use::

    frames = render_frames(robot, qs, width=480, height=360, target=T)
    save_gif("motion.gif", frames, fps=20)
"""

from __future__ import annotations

import contextlib
import os
import sys
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeAlias

import mujoco
import numpy as np

from redik.core.exceptions import InvalidInput

if TYPE_CHECKING:
    from redik.kinematics.robot import Robot

Camera: TypeAlias = str | int | mujoco.MjvCamera | dict[str, Any] | None
"""A camera: a model camera's name or id, an ``MjvCamera``, a dict of free-camera settings
(``lookat``, ``distance``, ``azimuth``, ``elevation``), or None to frame the robot."""


def _gl_backend() -> str:
    backend = os.environ.get("MUJOCO_GL", "").lower().strip()
    if backend:
        return backend
    headless = sys.platform.startswith("linux") and not (
        os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")
    )
    return "egl" if headless else "glfw"


def _gl_context(width: int, height: int):
    backend = _gl_backend()
    if backend == "egl":
        from mujoco.egl import GLContext
    elif backend == "osmesa":
        from mujoco.osmesa import GLContext
    elif backend in ("glfw", "glx", "1", "on", "true", "enable", "enabled"):
        from mujoco.glfw import GLContext
    else:
        raise InvalidInput(f"MUJOCO_GL={backend!r} cannot render; use 'egl', 'osmesa' or 'glfw'")
    return GLContext(width, height)


@contextlib.contextmanager
def _offscreen(model: mujoco.MjModel, width: int, height: int) -> Iterator[mujoco.MjrContext]:
    """An OpenGL context and a MuJoCo render context with an offscreen buffer ≥ width × height."""
    context = _gl_context(width, height)
    context.make_current()
    global_ = model.vis.global_
    saved = (global_.offwidth, global_.offheight)
    global_.offwidth, global_.offheight = max(width, saved[0]), max(height, saved[1])
    try:
        render_context = mujoco.MjrContext(model, mujoco.mjtFontScale.mjFONTSCALE_150)
        mujoco.mjr_setBuffer(mujoco.mjtFramebuffer.mjFB_OFFSCREEN, render_context)
        yield render_context
    finally:
        global_.offwidth, global_.offheight = saved
        with contextlib.suppress(Exception):
            render_context.free()
        context.free()


def framing_camera(robot: Robot, qs: Sequence[np.ndarray], margin: float = 1.3) -> dict:
    """Free-camera settings that keep every body of the chain in view over ``qs``.

    Looks at the centre of the bodies' bounding box from a distance proportional to its
    size, 135° around and 25° above the horizon.
    """
    data = mujoco.MjData(robot.model)
    points = []
    for q in qs:
        data.qpos[:] = robot.full_qpos(q)
        mujoco.mj_kinematics(robot.model, data)
        points.append(data.xpos[1:].copy())
        points.append(data.site_xpos.copy())
    cloud = np.concatenate(points)
    low, high = cloud.min(axis=0), cloud.max(axis=0)
    radius = max(0.5 * float(np.linalg.norm(high - low)), 0.2)
    return {
        "lookat": 0.5 * (low + high),
        "distance": margin * radius / np.tan(np.radians(robot.model.vis.global_.fovy / 2)),
        "azimuth": 135.0,
        "elevation": -25.0,
    }


def _camera(robot: Robot, camera: Camera, qs: Sequence[np.ndarray]) -> mujoco.MjvCamera:
    if isinstance(camera, mujoco.MjvCamera):
        return camera
    view = mujoco.MjvCamera()
    if camera is None or isinstance(camera, dict):
        settings = framing_camera(robot, qs) if camera is None else camera
        view.type = mujoco.mjtCamera.mjCAMERA_FREE
        view.lookat[:] = settings.get("lookat", (0.0, 0.0, 0.5))
        view.distance = float(settings.get("distance", 2.0))
        view.azimuth = float(settings.get("azimuth", 135.0))
        view.elevation = float(settings.get("elevation", -25.0))
        return view
    camera_id = (
        camera
        if isinstance(camera, int)
        else mujoco.mj_name2id(robot.model, mujoco.mjtObj.mjOBJ_CAMERA, camera)
    )
    if not 0 <= camera_id < robot.model.ncam:
        raise InvalidInput(f"no camera {camera!r} in model {robot.name!r}")
    view.type = mujoco.mjtCamera.mjCAMERA_FIXED
    view.fixedcamid = camera_id
    return view


def _add_frame_axes(scene: mujoco.MjvScene, T: np.ndarray, length: float) -> None:
    """Three arrows (x red, y green, z blue) for the pose ``T``."""
    for axis in range(3):
        if scene.ngeom >= scene.maxgeom:
            return
        geom = scene.geoms[scene.ngeom]
        rgba = np.array([0.0, 0.0, 0.0, 1.0], dtype=np.float32)
        rgba[axis] = 0.9
        mujoco.mjv_initGeom(
            geom, mujoco.mjtGeom.mjGEOM_ARROW, np.zeros(3), np.zeros(3), np.zeros(9), rgba
        )
        mujoco.mjv_connector(
            geom, mujoco.mjtGeom.mjGEOM_ARROW, 0.008, T[:3, 3], T[:3, 3] + length * T[:3, axis]
        )
        scene.ngeom += 1


def render_frames(
    robot: Robot,
    qs: Sequence[np.ndarray] | np.ndarray,
    width: int = 640,
    height: int = 480,
    camera: Camera = None,
    target: np.ndarray | None = None,
    on_frame: Callable[[int, int], None] | None = None,
) -> list[np.ndarray]:
    """Render ``robot`` at each configuration of ``qs``: a list of height × width × 3 uint8.

    Args:
        robot: The robot (its model is drawn; its own ``data`` is left untouched).
        qs: Configurations (k × n) of the chain; other joints at their home values.
        width: Image width in pixels.
        height: Image height in pixels.
        camera: See :data:`Camera`; None frames every configuration (:func:`framing_camera`).
        target: A pose (4 × 4) drawn as RGB axes, e.g. the end-effector target.
        on_frame: Called as ``on_frame(k, total)`` after each frame (e.g. a progress bar).

    Returns:
        One ``height × width × 3`` uint8 image per configuration.

    Raises:
        InvalidInput: a configuration of the wrong length or not finite, a size that is not
            positive, an ``on_frame`` that is not callable.
    """
    qs = [robot.check_q(q, "qs[i]") for q in np.atleast_2d(np.asarray(qs, dtype=float))]
    view = _camera(robot, camera, qs)
    states = [robot.full_qpos(q) for q in qs]
    return _render(robot, states, width, height, view, target, on_frame)


def render_states(
    robot: Robot,
    qpos: Sequence[np.ndarray] | np.ndarray,
    width: int = 640,
    height: int = 480,
    camera: Camera = None,
    target: np.ndarray | None = None,
    on_frame: Callable[[int, int], None] | None = None,
) -> list[np.ndarray]:
    """Render full model states (k × nq ``qpos``, e.g. ``SimulationResult.qpos``).

    The other arguments and the result are those of :func:`render_frames`.

    Raises:
        InvalidInput: ``qpos`` is not a finite ``k × nq`` array; as :func:`render_frames`.
    """
    qpos = np.atleast_2d(np.asarray(qpos, dtype=float))
    if qpos.shape[1] != robot.model.nq or not np.all(np.isfinite(qpos)):
        raise InvalidInput(f"qpos must be finite, k × {robot.model.nq}; got shape {qpos.shape}")
    chain = [state[robot.qpos_indices] for state in qpos]
    view = _camera(robot, camera, chain)
    return _render(robot, list(qpos), width, height, view, target, on_frame)


def _render(
    robot: Robot,
    states: list[np.ndarray],
    width: int,
    height: int,
    view: mujoco.MjvCamera,
    target: np.ndarray | None,
    on_frame: Callable[[int, int], None] | None = None,
) -> list[np.ndarray]:
    if width <= 0 or height <= 0:
        raise InvalidInput(f"width and height must be positive, got {width} × {height}")
    if on_frame is not None and not callable(on_frame):  # else a TypeError after frame 0
        raise InvalidInput(f"on_frame must be callable or None, got {on_frame!r}")
    data = mujoco.MjData(robot.model)
    scene = mujoco.MjvScene(robot.model, maxgeom=max(1000, 2 * robot.model.ngeom + 10))
    option = mujoco.MjvOption()
    viewport = mujoco.MjrRect(0, 0, width, height)
    axis_length = 0.1 * max(robot.model.stat.extent, 0.5)
    frames = []
    with _offscreen(robot.model, width, height) as render_context:
        for state in states:
            data.qpos[:] = state
            mujoco.mj_forward(robot.model, data)
            mujoco.mjv_updateScene(
                robot.model, data, option, None, view, mujoco.mjtCatBit.mjCAT_ALL, scene
            )
            if target is not None:
                _add_frame_axes(scene, np.asarray(target, dtype=float), axis_length)
            mujoco.mjr_render(viewport, scene, render_context)
            pixels = np.empty((height, width, 3), dtype=np.uint8)
            mujoco.mjr_readPixels(pixels, None, viewport, render_context)
            frames.append(np.flipud(pixels).copy())  # OpenGL rows run bottom-up
            if on_frame is not None:
                on_frame(len(frames) - 1, len(states))
    return frames


def save_png(path: str | Path, image: np.ndarray) -> Path:
    """Write one image as PNG."""
    import imageio.v3 as iio

    path = Path(path)
    iio.imwrite(path, np.asarray(image), extension=".png")
    return path


def save_pngs(
    directory: str | Path, frames: Sequence[np.ndarray], stem: str = "frame"
) -> list[Path]:
    """Write frames as ``directory/stem_0000.png``, … (the directory is created)."""
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    return [save_png(directory / f"{stem}_{k:04d}.png", frame) for k, frame in enumerate(frames)]


def save_gif(path: str | Path, frames: Sequence[np.ndarray], fps: float = 20.0) -> Path:
    """Write frames as an animated GIF that loops forever."""
    import imageio.v3 as iio

    if not frames:
        raise InvalidInput("save_gif needs at least one frame")
    path = Path(path)
    iio.imwrite(path, np.stack(frames), extension=".gif", duration=1000.0 / fps, loop=0)
    return path


def save_mp4(path: str | Path, frames: Sequence[np.ndarray], fps: float = 20.0) -> Path:
    """Write frames as an H.264 MP4 (needs ``imageio-ffmpeg``; sizes rounded to even pixels)."""
    import imageio.v2 as imageio

    if not frames:
        raise InvalidInput("save_mp4 needs at least one frame")
    path = Path(path)
    height, width = (frames[0].shape[0] // 2) * 2, (frames[0].shape[1] // 2) * 2
    with imageio.get_writer(path, fps=fps, codec="libx264", macro_block_size=1) as writer:
        for frame in frames:
            # imageio's stubs type Writer.__enter__ as returning the reader/writer base class.
            writer.append_data(np.ascontiguousarray(frame[:height, :width]))  # type: ignore[attr-defined]
    return path


def save_video(path: str | Path, frames: Sequence[np.ndarray], fps: float = 20.0) -> Path:
    """Write frames as ``.mp4``, ``.gif`` or (the last frame) ``.png``, by the path's suffix."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    writers = {".mp4": save_mp4, ".gif": save_gif}
    if path.suffix == ".png":
        return save_png(path, frames[-1])
    if path.suffix not in writers:
        raise InvalidInput(f"video path must end in .mp4, .gif or .png, got {str(path)!r}")
    return writers[path.suffix](path, frames, fps)
