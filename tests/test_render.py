"""Headless rendering (redik.apps.render): frames, PNG, GIF and MP4."""

from __future__ import annotations

import os

import numpy as np
import pytest

os.environ.setdefault("MUJOCO_GL", "egl")

import imageio.v2 as imageio
import imageio.v3 as iio

import redik
from redik.apps.render import render_frames, save_gif, save_mp4, save_png, save_pngs


@pytest.fixture(scope="module")
def panda() -> redik.Robot:
    return redik.load("panda")


def test_frames_show_the_arm_and_follow_the_configuration(panda):
    q_bent = panda.home.copy()
    q_bent[0] += 1.0
    frames = render_frames(panda, [panda.home, q_bent], width=160, height=120)
    assert len(frames) == 2
    for frame in frames:
        assert frame.shape == (120, 160, 3) and frame.dtype == np.uint8
        assert frame.std() > 10  # not a blank image
    # The framing camera is the same for both (it frames every configuration), so moving
    # joint 1 moves pixels.
    assert np.mean(np.any(frames[0] != frames[1], axis=2)) > 0.01


def test_target_axes_are_drawn(panda):
    T = panda.fk(panda.home)
    plain = render_frames(panda, [panda.home], 160, 120)[0]
    marked = render_frames(panda, [panda.home], 160, 120, target=T)[0]
    changed = np.any(plain != marked, axis=2)
    assert 20 < changed.sum() < 0.2 * changed.size  # a few arrows, not a different picture


def test_named_and_dict_cameras(panda):
    view = {"lookat": [0, 0, 0.4], "distance": 2.0, "azimuth": 90, "elevation": -20}
    assert render_frames(panda, [panda.home], 64, 48, camera=view)[0].shape == (48, 64, 3)
    with pytest.raises(redik.InvalidInput, match="no camera 'nowhere'"):
        render_frames(panda, [panda.home], 64, 48, camera="nowhere")


def test_png_gif_and_mp4_round_trip(panda, tmp_path):
    qs = [panda.home + np.eye(7)[0] * a for a in np.linspace(0, 0.5, 4)]
    frames = render_frames(panda, qs, width=96, height=72)
    png = save_png(tmp_path / "one.png", frames[0])
    assert np.array_equal(iio.imread(png)[..., :3], frames[0])
    assert len(save_pngs(tmp_path / "frames", frames)) == 4
    gif = iio.imread(save_gif(tmp_path / "motion.gif", frames, fps=10), index=None)
    assert gif.shape[0] == 4 and gif.shape[1:3] == (72, 96)
    mp4 = save_mp4(tmp_path / "motion.mp4", frames, fps=10)
    with imageio.get_reader(mp4) as reader:  # decoded by imageio-ffmpeg
        decoded = [frame for frame in reader]
    assert len(decoded) == 4 and decoded[0].shape == (72, 96, 3)


def test_on_frame_reports_each_frame(panda):
    calls = []
    render_frames(panda, [panda.home] * 3, width=32, height=24, on_frame=lambda *a: calls.append(a))
    assert calls == [(0, 3), (1, 3), (2, 3)]
    with pytest.raises(redik.InvalidInput, match="on_frame"):
        render_frames(panda, [panda.home], width=32, height=24, on_frame=len(calls))
