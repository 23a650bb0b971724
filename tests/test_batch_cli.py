"""``redik batch``: targets in, solutions out, errors reported as exit code 2."""

from __future__ import annotations

import io
import sys

import numpy as np
import pytest

import redik
import redik.models.registry
from redik.apps.cli import main


def test_random_targets_are_solved_and_written(tmp_path, capsys):
    out = tmp_path / "solutions.npz"
    code = main(["batch", "panda", "--random", "40", "--out", str(out), "--engine", "local"])
    assert code == 0
    assert "strict solves/s" in capsys.readouterr().out
    with np.load(out) as data:
        assert data["q"].shape == (40, 7) and data["T"].shape == (40, 4, 4)
        assert data["success"].mean() >= 0.99
        robot = redik.load("panda")
        i = int(np.flatnonzero(data["success"])[0])
        pos, rot = redik.lie.pose_errors(robot.fk(data["q"][i]), data["T"][i])
        assert pos <= 1e-6 and rot <= 1e-5
        assert list(data["statuses"][data["status"]][data["success"]]) == ["converged"] * int(
            data["success"].sum()
        )


def test_targets_file_with_seeds(tmp_path):
    robot = redik.load("panda")
    q = robot.random_q(0, size=5)
    T = np.stack([robot.fk(qi) for qi in q])
    T[2] = np.nan
    targets, out = tmp_path / "targets.npz", tmp_path / "out.npz"
    np.savez(targets, T=T, q0=q)
    assert (
        main(
            [
                "batch",
                "panda",
                "--targets",
                str(targets),
                "--out",
                str(out),
                "--quiet",
                "--engine",
                "local",
            ]
        )
        == 0
    )
    with np.load(out) as data:
        np.testing.assert_array_equal(data["success"], [True, True, False, True, True])
        assert data["statuses"][data["status"][2]] == "invalid"
        np.testing.assert_array_equal(data["iterations"][[0, 1, 3, 4]], 0)


def test_bad_targets_file_is_an_error(tmp_path, capsys):
    bad = tmp_path / "bad.npz"
    np.savez(bad, poses=np.zeros((2, 4, 4)))
    assert main(["batch", "panda", "--targets", str(bad), "--out", str(tmp_path / "o.npz")]) == 2
    assert "'T'" in capsys.readouterr().err
    assert (
        main(
            [
                "batch",
                "panda",
                "--targets",
                str(tmp_path / "missing.npz"),
                "--out",
                str(tmp_path / "o.npz"),
            ]
        )
        == 2
    )


def test_a_third_party_urdf_is_solved_with_the_load_flags(tmp_path, capsys):
    try:
        redik.models.registry.example_robot_data_dir()
    except redik.ModelError:
        pytest.skip("example-robot-data is not installed")
    out = tmp_path / "ur5.npz"
    command = [
        "batch", "example-robot-data:ur5", "--ee", "tool0", "--no-meshes", "--floating-base",
        "--random", "30", "--out", str(out), "--engine", "local", "--quiet",
    ]  # fmt: skip
    assert main(command) == 0
    assert capsys.readouterr().out.startswith("ur5_robot:")
    robot = redik.load("example-robot-data:ur5", ee="tool0", meshes=False, floating_base=True)
    with np.load(out) as data:
        assert data["q"].shape == (30, 6) and data["success"].mean() >= 0.9
        for q, T, success in zip(data["q"], data["T"], data["success"], strict=True):
            if success:
                pos, rot = redik.lie.pose_errors(robot.fk(q), T)
                assert pos <= 1e-6 and rot <= 1e-5


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_the_progress_bar_is_drawn_on_a_terminal_only(tmp_path, monkeypatch):
    command = ["batch", "panda", "--random", "20", "--out", str(tmp_path / "a.npz")]
    terminal = _Terminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    assert main([*command, "--chunk-size", "10"]) == 0
    assert "batch IK" in terminal.getvalue() and "20/20" in terminal.getvalue()
    quiet = _Terminal()
    monkeypatch.setattr(sys, "stderr", quiet)
    assert main([*command, "--quiet"]) == 0
    assert quiet.getvalue() == ""
    piped = io.StringIO()  # not a terminal: a log stays clean
    monkeypatch.setattr(sys, "stderr", piped)
    assert main(command) == 0
    assert piped.getvalue() == ""
