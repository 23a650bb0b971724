"""The command line: discovery, `redik info`, third-party models and the model flags every
command that loads one takes, and errors reported without tracebacks, in the CLI's words."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import redik
from redik.apps.cli import main
from redik.models import registry


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


@pytest.mark.slow
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


def _example_robot_data() -> Path:
    """example-robot-data's package folder (``…/share/example-robot-data``), or skip."""
    try:
        return registry.example_robot_data_dir().resolve().parent
    except redik.ModelError:
        pytest.skip("example-robot-data is not installed")


def _printed_position(out: str) -> np.ndarray:
    line = next(line for line in out.splitlines() if line.startswith("position [m]:"))
    return np.array(line.split("[")[-1].rstrip("]").split(), dtype=float)


def test_info_loads_a_third_party_urdf_kinematics_only_with_a_floating_base(capsys):
    _example_robot_data()
    ur5 = ["info", "example-robot-data:ur5", "--ee", "tool0", "--no-meshes"]
    assert main(ur5) == 0
    out = capsys.readouterr().out
    robot = redik.load("example-robot-data:ur5", ee="tool0", meshes=False)
    assert robot.model.nmesh == 0
    for joint in robot.joint_names:
        assert joint in out
    assert "held joints" not in out
    np.testing.assert_allclose(_printed_position(out), robot.fk(robot.home)[:3, 3], atol=1e-6)
    assert main([*ur5, "--floating-base"]) == 0
    floating = capsys.readouterr().out
    assert "held joints (not moved): floating_base (free)" in floating
    np.testing.assert_allclose(_printed_position(floating), _printed_position(out), atol=1e-12)


def test_package_path_finds_the_meshes_of_a_copied_urdf(tmp_path, capsys):
    package = _example_robot_data()
    copy = tmp_path / "ur5_robot.urdf"  # away from its package: package:// meshes go unfound
    shutil.copy(registry.example_robot_data("ur5"), copy)
    info = ["info", str(copy), "--ee", "tool0"]
    assert main(info) == 2
    err = capsys.readouterr().err
    assert "package://example-robot-data/robots/ur_description/meshes" in err and "not found" in err
    # The remedies are named as the flags that apply them, not as Python keywords.
    assert "--no-meshes" in err and "--package-path DIR" in err
    assert "meshes=False" not in err and "package_paths" not in err
    assert main([*info, "--no-meshes"]) == 0
    capsys.readouterr()
    empty = tmp_path / "empty"
    empty.mkdir()
    for folder in (package, package.parent):  # the package itself, or a folder holding it
        assert main([*info, "--package-path", str(empty), "--package-path", str(folder)]) == 0
        assert "ur5_robot: 6 joints" in capsys.readouterr().out


def test_explore_loads_a_third_party_model_with_the_load_flags(tmp_path, capsys):
    _example_robot_data()
    command = [
        "explore", "example-robot-data:panda", "--ee", "panda_hand", "--no-meshes",
        "--floating-base", "--fixed", "panda_finger_joint*", "--starts", "8", "--frames", "0",
        "--out", str(tmp_path),
    ]  # fmt: skip
    assert main(command) == 0
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["dimension"] == 1 and summary["max_position_error"] < 1e-6
    assert "wrote" in capsys.readouterr().out


PLANAR = """
<mujoco model="planar">
  <worldbody>
    <body name="base">{free}
      <body name="link1">
        <joint name="j1" axis="0 0 1"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02"/>
        <body name="link2" pos="0.3 0 0">
          <joint name="j2" axis="0 0 1"/>
          <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02"/>
          <site name="tip" pos="0.3 0 0"/>
          <body name="marker" pos="0.1 0 0"><geom size="0.01"/></body>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def _planar(tmp_path: Path, free: bool = False) -> str:
    path = tmp_path / ("free.xml" if free else "planar.xml")
    path.write_text(PLANAR.format(free="<freejoint name='root'/>" if free else ""))
    return str(path)


def test_info_prints_the_frames_a_user_would_pick(tmp_path, capsys):
    assert main(["info", _planar(tmp_path), "--ee", "tip"]) == 0
    out = capsys.readouterr().out
    assert "  sites:  tip" in out
    assert "  leaf bodies: marker" in out  # the tip of the tree; link2 holds a child
    assert "other bodies: base, link1, link2" in out


@pytest.mark.parametrize("command", ["info", "batch", "explore"])
def test_every_command_that_loads_a_model_takes_the_model_flags(command):
    from redik.apps.cli import build_parser

    argv = [command, "panda", "--ee", "ee", "--fixed", "joint7", "--no-meshes",
            "--floating-base", "--package-path", "."]  # fmt: skip
    if command == "batch":
        argv += ["--random", "1", "--out", "x.npz"]
    args = build_parser().parse_args(argv)
    assert (args.ee, args.fixed, args.meshes, args.floating_base) == ("ee", ["joint7"], False, True)
    assert args.package_paths == [Path(".")]


def test_fixed_holds_a_joint_in_info_and_batch(tmp_path, capsys):
    assert main(["info", "panda", "--fixed", "joint7"]) == 0
    out = capsys.readouterr().out
    assert "panda: 6 joints" in out and "held joints (not moved): joint7 (hinge)" in out
    solutions = tmp_path / "solutions.npz"
    argv = ["batch", "panda", "--fixed", "joint7", "--random", "5", "--out", str(solutions)]
    assert main([*argv, "--engine", "local", "--quiet"]) == 0
    with np.load(solutions) as data:
        assert data["q"].shape == (5, 6)


def test_errors_name_the_flag_not_the_keyword(capsys):
    assert main(["info", "panda", "--fixed", "no_such_joint"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("redik info: error: --fixed: no joint of model 'panda' matches")


def test_floating_base_warns_when_it_changes_nothing(tmp_path, capsys):
    # A chain does not move the free joint the flag adds.
    assert main(["info", _planar(tmp_path), "--ee", "tip", "--floating-base"]) == 0
    captured = capsys.readouterr()
    assert "held joints (not moved): floating_base (free)" in captured.out
    assert "warning: --floating-base changes nothing here: the chain" in captured.err
    # A model whose root is free already gets no second free joint.
    assert main(["info", _planar(tmp_path, free=True), "--ee", "tip", "--floating-base"]) == 0
    captured = capsys.readouterr()
    assert "already has a free joint ('root')" in captured.err
    assert "floating_base" not in captured.out
    # Without the flag, nothing to warn about.
    assert main(["info", _planar(tmp_path, free=True), "--ee", "tip"]) == 0
    assert capsys.readouterr().err == ""


WHOLE = """
<mujoco model="whole">
  <compiler angle="radian"/>
  <worldbody>
    <body name="torso" pos="0 0 1">
      <freejoint name="root"/>
      <geom size="0.1"/>
      <body name="arm" pos="0.1 0 0">
        <joint name="shoulder" type="ball"/>
        <geom size="0.05"/>
        <body name="forearm" pos="0.3 0 0">
          <joint name="elbow" axis="0 1 0" range="-2 0.5"/>
          <geom size="0.05"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def test_info_describes_a_whole_model_robot_joint_by_joint(capsys):
    import mujoco

    from redik.apps.cli.info import describe

    robot = redik.Robot(mujoco.MjModel.from_xml_string(WHOLE), joints="all")
    describe(robot)
    out = capsys.readouterr().out
    assert out.startswith("whole: 3 joints (10 DoF), whole model (no end-effector")
    rows = {line.split()[0]: line.split()[1:] for line in out.splitlines()[2:5]}
    assert rows["root"][0] == "free" and "(0.0000 0.0000 1.0000 1.0000" in " ".join(rows["root"])
    assert rows["shoulder"] == ["ball", "(1.0000", "0.0000", "0.0000", "0.0000)"]
    assert rows["elbow"] == ["revolute", "-2.0000", "0.5000", "0.0000", "rad"]
    assert "leaf bodies: forearm" in out and "end-effector pose" not in out


def test_a_model_without_an_end_effector_is_described_whole_and_needs_ee_to_solve(tmp_path, capsys):
    planar = _planar(tmp_path)  # no site called 'ee'
    assert main(["info", planar]) == 0
    out = capsys.readouterr().out
    assert out.startswith("planar: 2 joints, whole model (no end-effector: pick one with --ee)")
    assert "  sites:  tip" in out and "end-effector pose" not in out
    batch = ["batch", planar, "--random", "2", "--out", str(tmp_path / "o.npz")]
    explore = ["explore", planar, "--frames", "0", "--out", str(tmp_path / "e")]
    for command in (batch, explore):
        assert main(command) == 2
        err = capsys.readouterr().err
        assert "names no end-effector (no site 'ee'): pick one with --ee FRAME" in err
        assert err.rstrip().endswith("the frames its joints move: tip, marker")
