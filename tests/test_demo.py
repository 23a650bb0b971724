"""``redik demo`` runs end to end, headless, and writes what it promises.

It runs in a subprocess with ``MUJOCO_GL=egl``: MuJoCo picks its OpenGL back-end when it is
first imported, so the rendering mode cannot be changed inside this test process.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys

import numpy as np
import pytest

import redik
from redik.lie import pose_errors

pytestmark = pytest.mark.slow  # the demo runs as a subprocess

FILES = {"summary.json", "selfmotion.npz", "manifold.png", "solution.png", "selfmotion.gif"}


@pytest.fixture(scope="module")
def demo(tmp_path_factory):
    out = tmp_path_factory.mktemp("demo")
    env = {**os.environ, "MUJOCO_GL": "egl", "PYOPENGL_PLATFORM": "egl", "MPLBACKEND": "Agg"}
    command = [sys.executable, "-m", "redik", "demo", "--out", str(out), "--max-samples", "200"]
    completed = subprocess.run(command, env=env, capture_output=True, text=True, timeout=300)
    assert completed.returncode == 0, completed.stdout[-2000:] + completed.stderr[-4000:]
    return out, completed.stdout, json.loads((out / "summary.json").read_text())


def test_demo_prints_a_short_summary(demo):
    _, printed, _ = demo
    assert "dexter8r" in printed and "converged" in printed and "wrote" in printed
    assert len(printed.splitlines()) < 20


def test_demo_writes_its_files(demo):
    out, _, _ = demo
    assert FILES <= {path.name for path in out.iterdir()}
    assert (out / "solution.png").read_bytes()[:4] == b"\x89PNG"
    assert (out / "manifold.png").read_bytes()[:4] == b"\x89PNG"
    assert (out / "selfmotion.gif").read_bytes()[:3] == b"GIF"


def test_demo_solution_reaches_the_pose_inside_the_limits(demo):
    _, _, summary = demo
    robot = redik.load(summary["scene"])
    q = np.array(summary["qp"]["q"])
    target = np.array(summary["target"])
    position_error, rotation_error = pose_errors(robot.fk(q), target)  # checked by FK
    assert position_error <= 1e-6 and rotation_error <= 1e-5
    assert robot.within_limits(q)
    assert not np.allclose(q, robot.home, atol=0.1)  # the target was away from home


def test_demo_self_motion_keeps_the_pose(demo):
    out, _, summary = demo
    robot = redik.load(summary["scene"])
    target = np.array(summary["target"])
    with np.load(out / "selfmotion.npz") as data:
        samples = data["samples"]
    assert samples.shape[1] == 8 and len(samples) >= 100
    assert summary["self_motion"]["dimension"] == 2
    errors = np.array([pose_errors(robot.fk(q), target) for q in samples[::10]])
    assert errors[:, 0].max() <= 1e-9 and errors[:, 1].max() <= 1e-8
    assert summary["tour_max_end_effector_drift"] <= 1e-6


def test_qp_scores_are_its_own_and_the_manifold_holds_a_sample_near_its_optimum(demo):
    _, _, summary = demo
    robot = redik.load(summary["scene"])
    q_qp = np.array(summary["qp"]["q"])
    comparison = summary["qp_vs_best_sample"]
    assert set(comparison) >= {"joint_limit_margin", "manipulability", "posture_distance"}
    # The QP's scores are of its own q, recomputed here independently.
    posture = comparison["posture_distance"]
    assert posture["qp"] == pytest.approx(float(np.linalg.norm(q_qp - robot.home)), rel=1e-9)
    J = robot.jacobian(q_qp, reference="world")
    manipulability = float(np.sqrt(np.linalg.det(J @ J.T)))
    assert comparison["manipulability"]["qp"] == pytest.approx(manipulability, rel=1e-6)
    # The exploration starts at the QP solution and samples within one spacing of it, and the
    # posture distance is 1-Lipschitz in q: the best sample cannot be worse by more.
    spacing = summary["self_motion"]["spacing"]
    assert posture["best_sample"] <= posture["qp"] + spacing
