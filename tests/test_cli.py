"""The command line: discovery, `redik info`, and errors reported without tracebacks."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

import redik
from redik.apps.cli import main


def test_info_lists_scenes(capsys):
    assert main(["info", "--list"]) == 0
    out = capsys.readouterr().out
    for name in redik.list_scenes():
        assert name in out


@pytest.mark.parametrize("scene", ["panda", "ur5e", "planar_2r"])
def test_info_describes_a_scene(capsys, scene):
    if scene not in redik.list_scenes():
        pytest.fail(f"bundled scene {scene!r} is missing")
    assert main(["info", scene]) == 0
    out = capsys.readouterr().out
    robot = redik.load(scene)
    for joint in robot.joint_names:
        assert joint in out
    assert "end-effector pose at home" in out
    line = next(line for line in out.splitlines() if line.startswith("position [m]:"))
    printed = np.array(line.split("[")[-1].rstrip("]").split(), dtype=float)
    np.testing.assert_allclose(printed, robot.fk(robot.home)[:3, 3], atol=1e-6)


def test_unknown_scene_is_a_clean_error(capsys):
    assert main(["info", "no_such_robot"]) == 2
    err = capsys.readouterr().err
    assert "no bundled scene named 'no_such_robot'" in err


def test_console_script_entry_point():
    completed = subprocess.run(
        [sys.executable, "-m", "redik", "--help"], capture_output=True, text=True, timeout=60
    )
    assert completed.returncode == 0
    for command in ("info", "bench"):
        assert command in completed.stdout


class _Terminal:
    """A stand-in for an interactive stderr: records what is written, says it is a tty."""

    def __init__(self):
        self.text = []

    def write(self, text: str) -> int:
        self.text.append(text)
        return len(text)

    def flush(self) -> None:
        pass

    def isatty(self) -> bool:
        return True

    def __str__(self) -> str:
        return "".join(self.text)


EXPLORE = ["explore", "panda", "--pose", "0.4", "0.1", "0.5", "0", "1", "0", "0", "--starts", "8"]
EXPLORE_OUTPUT = ["--frames", "3", "--size", "64", "48", "--no-mp4"]


def test_explore_draws_a_progress_bar_on_a_terminal(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("MUJOCO_GL", "egl")
    terminal = _Terminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    assert main([*EXPLORE, *EXPLORE_OUTPUT, "--out", str(tmp_path)]) == 0
    drawn = str(terminal)
    for stage in ("plotting", "rendering", "writing GIF"):
        assert stage in drawn, drawn
    assert "wrote" in capsys.readouterr().out


def test_explore_is_quiet_with_quiet_or_without_a_terminal(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("MUJOCO_GL", "egl")
    terminal = _Terminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    assert main([*EXPLORE, *EXPLORE_OUTPUT, "--out", str(tmp_path / "a"), "--quiet"]) == 0
    assert str(terminal) == ""
    monkeypatch.undo()
    monkeypatch.setenv("MUJOCO_GL", "egl")
    assert main([*EXPLORE, *EXPLORE_OUTPUT, "--out", str(tmp_path / "b")]) == 0
    assert capsys.readouterr().err == ""  # pytest's captured stderr is not a tty
