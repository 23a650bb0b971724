"""``redik batch``: targets in, solutions out, errors reported as exit code 2."""

from __future__ import annotations

import numpy as np

import redik
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
