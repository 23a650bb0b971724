"""``redik batch``: targets in, solutions out, errors reported as exit code 2; a run killed
mid-batch resumes from its checkpoint."""

from __future__ import annotations

import io
import subprocess
import sys
import time

import numpy as np
import pytest

import redik
import redik.models.registry
from redik.apps.cli import main
from redik.solvers.batch.checkpoint import finished_chunks


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


@pytest.mark.slow
def test_a_killed_batch_resumes_from_its_checkpoint_without_solving_its_chunks_again(tmp_path):
    checkpoint, resumed = tmp_path / "checkpoint", tmp_path / "resumed.npz"
    batch = ["batch", "panda", "--random", "160000", "--seed", "3", "--chunk-size", "8000",
             "--engine", "local", "--quiet"]  # fmt: skip
    command = [
        sys.executable, "-m", "redik", *batch, "--workers", "1", "--checkpoint", str(checkpoint)
    ]  # fmt: skip
    first = subprocess.Popen([*command, "--out", str(resumed)], stderr=subprocess.PIPE)
    deadline = time.monotonic() + 300
    while finished_chunks(checkpoint) < 3:  # several chunks done, more in flight
        assert first.poll() is None, first.communicate()[1].decode()
        assert time.monotonic() < deadline
        time.sleep(0.02)
    first.kill()  # SIGKILL: no handler runs, a write may be cut short
    first.wait()
    before = {file.name: file.stat() for file in checkpoint.glob("chunk-*.npz")}
    assert 3 <= len(before) < 20 and not resumed.exists()

    done = subprocess.run(
        [*command, "--out", str(resumed)], capture_output=True, text=True, timeout=600
    )
    assert done.returncode == 0, done.stderr
    assert f"{len(before)} finished chunks are read, not solved" in done.stdout
    after = {file.name: file.stat() for file in checkpoint.glob("chunk-*.npz")}
    assert len(after) == 20
    rewritten = [
        name
        for name, stat in before.items()
        if (after[name].st_ino, after[name].st_mtime_ns) != (stat.st_ino, stat.st_mtime_ns)
    ]
    assert rewritten == []  # each chunk done before the kill was read back, not solved again

    whole = tmp_path / "whole.npz"
    assert main([*batch, "--out", str(whole)]) == 0  # the same batch, uninterrupted, all cores
    with np.load(resumed) as got, np.load(whole) as expected:
        assert sorted(got.files) == sorted(expected.files)
        for name in expected.files:
            np.testing.assert_array_equal(got[name], expected[name], err_msg=name)
