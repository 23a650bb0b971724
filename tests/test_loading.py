"""Loading real model files: third-party URDFs against pybullet's FK, meshes, frames, errors."""

from __future__ import annotations

import warnings
import xml.etree.ElementTree as ElementTree
from pathlib import Path

import mujoco
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import redik
from redik.models import loading
from redik.models import registry as models

pybullet = pytest.importorskip("pybullet")
pytest.importorskip("pybullet_data")
try:
    models.example_robot_data_dir()
except redik.ModelError:
    pytest.skip("example-robot-data is not installed", allow_module_level=True)

# (finder, name, floating base, frames to check: fixed URDF links that fusing would remove)
THIRD_PARTY = {
    "panda": (models.example_robot_data, "panda", False, ["panda_hand", "panda_hand_tcp"]),
    "ur5": (models.example_robot_data, "ur5", False, ["tool0", "ee_link"]),
    "talos": (
        models.example_robot_data,
        "talos",
        True,
        ["gripper_left_base_link", "wrist_right_ft_tool_link", "left_sole_link"],
    ),
    "baxter": (models.example_robot_data, "baxter", False, ["left_gripper", "right_gripper"]),
    "pr2": (
        models.example_robot_data,
        "pr2",
        False,
        ["r_gripper_tool_frame", "l_gripper_tool_frame"],
    ),
    "kuka_iiwa": (models.pybullet_data, "kuka_iiwa", False, ["lbr_iiwa_link_7"]),
    "franka_panda": (models.pybullet_data, "franka_panda", False, ["panda_grasptarget"]),
}


def _load_model(path: Path, **options) -> mujoco.MjModel:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", redik.ModelWarning)  # baxter's .dae collision meshes
        return loading.load_model(path, **options)


def _load_robot(path: Path, ee: str, **options) -> redik.Robot:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", redik.ModelWarning)
        return redik.load(path, ee=ee, **options)


# --------------------------------------------------------------------------------------
# Two independent references: the URDF's own kinematics in double precision, and pybullet

# pybullet returns link poses rounded to single precision (its quaternions are off unit length
# by ~5e-8; measured |T_mujoco - T_pybullet| <= 5.2e-7 over 20 random q on these seven
# models), so it cannot check 1e-9. The URDF reference below carries the 1e-9 check; pybullet,
# at its own precision, checks that reference's reading of the URDF.
PYBULLET_TOL = 2e-6
EXACT_TOL = 1e-9


class UrdfReference:
    """Forward kinematics read straight off a URDF file (URDF spec, https://wiki.ros.org/urdf).

    Link frame of a child: ``T_child = T_parent · T(xyz) · R(rpy) · M(q)`` with
    ``R(rpy) = Rz(yaw) Ry(pitch) Rx(roll)`` and ``M(q)`` a rotation by ``q`` about ``axis``
    (revolute, continuous), a translation by ``q · axis`` (prismatic) or the identity (fixed).
    """

    def __init__(self, urdf: Path):
        root = ElementTree.parse(urdf).getroot()
        self.children: dict[str, list[ElementTree.Element]] = {}
        children = set()
        for joint in root.iter("joint"):
            if joint.find("parent") is None:
                continue  # a <joint> inside <transmission>
            parent = joint.find("parent").get("link")
            self.children.setdefault(parent, []).append(joint)
            children.add(joint.find("child").get("link"))
        links = [link.get("name") for link in root.iter("link")]
        (self.root,) = [link for link in links if link not in children]

    def link_poses(self, q: dict[str, float], base: np.ndarray | None = None):
        poses = {self.root: np.eye(4) if base is None else base}
        stack = [self.root]
        while stack:
            parent = stack.pop()
            for joint in self.children.get(parent, ()):
                origin = joint.find("origin")
                xyz = _floats(origin, "xyz") if origin is not None else np.zeros(3)
                rpy = _floats(origin, "rpy") if origin is not None else np.zeros(3)
                motion = np.eye(4)
                if joint.get("type") in ("revolute", "continuous", "prismatic"):
                    axis = _floats(joint.find("axis"), "xyz", "1 0 0")
                    axis = q.get(joint.get("name"), 0.0) * axis / np.linalg.norm(axis)
                    if joint.get("type") == "prismatic":
                        motion[:3, 3] = axis
                    else:
                        motion[:3, :3] = Rotation.from_rotvec(axis).as_matrix()
                fixed = np.eye(4)
                fixed[:3, :3] = Rotation.from_euler("xyz", rpy).as_matrix()
                fixed[:3, 3] = xyz
                child = joint.find("child").get("link")
                poses[child] = poses[parent] @ fixed @ motion
                stack.append(child)
        return poses


def _floats(element, attribute: str, default: str = "0 0 0") -> np.ndarray:
    text = default if element is None else element.get(attribute, default)
    return np.array([float(x) for x in text.split()])


class PyBulletReference:
    """A URDF in a pybullet DIRECT session, without its meshes (kinematics only)."""

    def __init__(self, urdf: Path, tmp_path: Path, floating_base: bool = False):
        tree = ElementTree.parse(urdf)
        for link in tree.getroot().iter("link"):
            for child in [c for c in link if c.tag in ("visual", "collision")]:
                link.remove(child)
        stripped = tmp_path / f"{urdf.stem}_kinematics.urdf"
        tree.write(stripped)
        self.client = pybullet.connect(pybullet.DIRECT)
        self.body = pybullet.loadURDF(
            str(stripped), useFixedBase=not floating_base, physicsClientId=self.client
        )
        self.joints: dict[str, int] = {}
        self.links: dict[str, int] = {}
        for index in range(pybullet.getNumJoints(self.body, physicsClientId=self.client)):
            info = pybullet.getJointInfo(self.body, index, physicsClientId=self.client)
            self.links[info[12].decode()] = index
            if info[2] in (pybullet.JOINT_REVOLUTE, pybullet.JOINT_PRISMATIC):
                self.joints[info[1].decode()] = index

    def close(self) -> None:
        pybullet.disconnect(self.client)

    def set(self, values: dict[str, float], base: np.ndarray | None = None) -> None:
        for name, value in values.items():
            pybullet.resetJointState(
                self.body, self.joints[name], value, physicsClientId=self.client
            )
        if base is not None:
            # pybullet places the base by its inertial frame: T_inertial = T_link · T_local.
            dynamics = pybullet.getDynamicsInfo(self.body, -1, physicsClientId=self.client)
            T = base @ _pose(dynamics[3], dynamics[4])
            pybullet.resetBasePositionAndOrientation(
                self.body, T[:3, 3], _xyzw(T[:3, :3]), physicsClientId=self.client
            )

    def link_pose(self, link: str) -> np.ndarray:
        """The URDF link frame (worldLinkFrame*, not the inertial frame) in the world."""
        state = pybullet.getLinkState(
            self.body, self.links[link], computeForwardKinematics=True, physicsClientId=self.client
        )
        return _pose(state[4], state[5])


def _pose(position, quat_xyzw) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3] = np.reshape(pybullet.getMatrixFromQuaternion(quat_xyzw), (3, 3))
    T[:3, 3] = position
    return T


def _xyzw(R: np.ndarray) -> list[float]:
    quat = np.empty(4)
    mujoco.mju_mat2Quat(quat, R.reshape(-1))
    return [quat[1], quat[2], quat[3], quat[0]]


def _random_joint_values(model: mujoco.MjModel, names, rng) -> dict[str, float]:
    values = {}
    for name in names:
        joint = model.joint(name)
        if model.jnt_limited[joint.id]:
            low, high = model.jnt_range[joint.id]
        else:
            low, high = -np.pi, np.pi
        values[name] = float(rng.uniform(low, high))
    return values


def _body_pose(data: mujoco.MjData, body: int) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3] = data.xmat[body].reshape(3, 3)
    T[:3, 3] = data.xpos[body]
    return T


def _assert_link_poses(model, data, expected: dict, root: str, bullet) -> None:
    """Every body named in ``expected`` sits at its URDF pose (1e-9) and, but for the root
    (pybullet's base, not a link), at pybullet's (its precision)."""
    for link, T in expected.items():
        actual = _body_pose(data, model.body(link).id)
        np.testing.assert_allclose(actual, T, rtol=0, atol=EXACT_TOL, err_msg=link)
        if link != root:
            np.testing.assert_allclose(
                actual, bullet.link_pose(link), rtol=0, atol=PYBULLET_TOL, err_msg=link
            )


# --------------------------------------------------------------------------------------
# Third-party models


@pytest.mark.parametrize("key", sorted(THIRD_PARTY))
def test_third_party_urdf_loads_with_and_without_meshes(key):
    finder, name, floating, frames = THIRD_PARTY[key]
    path = finder(name)
    for meshes in (False, True):
        model = _load_model(path, meshes=meshes, floating_base=floating)
        if not meshes:
            assert model.nmesh == 0
        for frame in frames:
            assert mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, frame) >= 0, frame
        assert model.nq == model.njnt + 6 * floating  # the free joint holds 7 values
    # Meshes change geometry, never kinematics: every body sits at the same place.
    with_meshes = _load_model(path, meshes=True, floating_base=floating)
    without = _load_model(path, meshes=False, floating_base=floating)
    assert with_meshes.nbody == without.nbody
    q = np.random.default_rng(0).uniform(-1.0, 1.0, without.nq)
    poses = []
    for model in (with_meshes, without):
        data = mujoco.MjData(model)
        data.qpos[:] = q
        mujoco.mj_kinematics(model, data)
        poses.append(data.xpos.copy())
    np.testing.assert_allclose(poses[0], poses[1], atol=1e-12)


def test_meshes_are_loaded_when_asked():
    model = _load_model(models.example_robot_data("panda"), meshes=True)
    assert model.nmesh == 9  # panda's collision STLs, found through package://
    model = _load_model(models.pybullet_data("franka_panda"), meshes=True)
    assert model.nmesh > 0  # package://meshes/… relative to the URDF's own folder


@pytest.mark.parametrize("key", sorted(THIRD_PARTY))
def test_third_party_fk_matches_independent_fk(key, tmp_path):
    """Every link frame, and redik's FK of each chosen frame, equal the URDF's own FK (1e-9)
    and pybullet's (to its single precision) at random joint values."""
    finder, name, _, frames = THIRD_PARTY[key]
    path = finder(name)
    rng = np.random.default_rng(7)
    model = _load_model(path, meshes=False)
    urdf = UrdfReference(path)
    bullet = PyBulletReference(path, tmp_path)
    try:
        data = mujoco.MjData(model)
        for _ in range(3):
            values = _random_joint_values(model, bullet.joints, rng)
            for joint, value in values.items():
                data.qpos[model.jnt_qposadr[model.joint(joint).id]] = value
            mujoco.mj_kinematics(model, data)
            bullet.set(values)
            expected = urdf.link_poses(values)
            assert set(expected) == set(bullet.links) | {urdf.root}
            _assert_link_poses(model, data, expected, urdf.root, bullet)
        for frame in frames:
            robot = _load_robot(path, ee=frame, meshes=False)
            for _ in range(3):
                q = robot.random_q(rng)
                values = dict(zip(robot.joint_names, q, strict=True))
                bullet.set(values)
                T = robot.fk(q)
                np.testing.assert_allclose(
                    T, urdf.link_poses(values)[frame], rtol=0, atol=EXACT_TOL, err_msg=frame
                )
                np.testing.assert_allclose(
                    T, bullet.link_pose(frame), rtol=0, atol=PYBULLET_TOL, err_msg=frame
                )
    finally:
        bullet.close()


def test_floating_base_matches_independent_fk(tmp_path):
    """Talos with a free root: every link follows a random base pose as in the references."""
    path = models.example_robot_data("talos")
    model = _load_model(path, meshes=False, floating_base=True)
    free = model.joint(loading.FLOATING_BASE_JOINT)
    assert model.jnt_type[free.id] == mujoco.mjtJoint.mjJNT_FREE
    assert model.body(model.jnt_bodyid[free.id]).name == "base_link"
    urdf = UrdfReference(path)
    bullet = PyBulletReference(path, tmp_path, floating_base=True)
    rng = np.random.default_rng(3)
    try:
        data = mujoco.MjData(model)
        for _ in range(3):
            values = _random_joint_values(model, bullet.joints, rng)
            for joint, value in values.items():
                data.qpos[model.jnt_qposadr[model.joint(joint).id]] = value
            quat = rng.normal(size=4)
            quat /= np.linalg.norm(quat)
            position = rng.uniform(-1.0, 1.0, 3)
            adr = model.jnt_qposadr[free.id]
            data.qpos[adr : adr + 7] = [*position, *quat]
            mujoco.mj_kinematics(model, data)
            base = np.eye(4)
            base[:3, :3] = Rotation.from_quat(quat, scalar_first=True).as_matrix()
            base[:3, 3] = position
            bullet.set(values, base=base)
            _assert_link_poses(model, data, urdf.link_poses(values, base), urdf.root, bullet)
    finally:
        bullet.close()


def test_floating_base_robot_keeps_its_chain():
    path = models.example_robot_data("talos")
    fixed = _load_robot(path, ee="gripper_left_base_link", meshes=False)
    floating = _load_robot(path, ee="gripper_left_base_link", meshes=False, floating_base=True)
    assert floating.joint_names == fixed.joint_names
    q = fixed.random_q(1)
    np.testing.assert_allclose(floating.fk(q), fixed.fk(q), atol=1e-12)


def test_visual_geometry_is_kept_on_request_and_never_collides():
    path = models.pybullet_data("kuka_iiwa")
    collision = _load_model(path)
    both = _load_model(path, visual=True)
    assert both.nmesh == collision.nmesh + 8  # link_0 … link_7: an .obj each
    visual = both.geom_group == 1
    assert visual.sum() == 8 and collision.ngeom == both.ngeom - 8
    assert not np.any(both.geom_contype[visual]) and not np.any(both.geom_conaffinity[visual])
    assert np.all(both.geom_contype[~visual] == 1)
    # example-robot-data's visual meshes are COLLADA: dropped with a warning, collision kept.
    with pytest.warns(redik.ModelWarning, match=r"link0\.dae"):
        panda = loading.load_model(models.example_robot_data("panda"), visual=True)
    assert panda.nmesh == 9


def test_fixed_links_are_fused_only_on_request():
    path = models.example_robot_data("ur5")
    fused = _load_model(path, meshes=False, keep_fixed_links=False)
    assert mujoco.mj_name2id(fused, mujoco.mjtObj.mjOBJ_BODY, "tool0") < 0
    kept = _load_model(path, meshes=False)
    assert mujoco.mj_name2id(kept, mujoco.mjtObj.mjOBJ_BODY, "tool0") >= 0
    assert kept.nq == fused.nq


def test_continuous_joints_are_unlimited_hinges():
    path = models.example_robot_data("pr2")
    continuous = [
        joint.get("name")
        for joint in ElementTree.parse(path).getroot().iter("joint")
        if joint.get("type") == "continuous"
    ]
    assert "r_forearm_roll_joint" in continuous
    model = _load_model(path, meshes=False)
    for name in continuous:
        joint = model.joint(name)
        assert model.jnt_type[joint.id] == mujoco.mjtJoint.mjJNT_HINGE
        assert not model.jnt_limited[joint.id], name
    robot = _load_robot(path, ee="r_gripper_tool_frame", meshes=False)
    roll = robot.joint_names.index("r_forearm_roll_joint")
    assert robot.lower[roll] == -np.inf and robot.upper[roll] == np.inf


def test_indefinite_inertia_is_repaired_with_a_warning():
    with pytest.warns(redik.ModelWarning, match="base_antenna_left_link"):
        model = loading.load_model(models.example_robot_data("tiago_dual"), meshes=False)
    assert np.all(model.body_inertia[1:] > 0)


def test_every_listed_model_loads_whole_with_the_frames_a_user_would_pick(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # MuJoCo logs asr_twodof's empty joint ranges to MUJOCO_LOG.TXT
    for table, finder in (
        (models.EXAMPLE_ROBOT_DATA, models.example_robot_data),
        (models.PYBULLET_DATA, models.pybullet_data),
    ):
        for name, entry in table.items():
            path = finder(name)
            assert path.is_file()
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", redik.ModelWarning)
                robot = redik.load(path, meshes=False, floating_base=entry.floating_base)
            assert robot.model.nbody > 1, name
            assert not robot.is_chain and robot.ee is None, name  # no frame named by default
            frames = robot.suggested_frames()
            assert frames, name
            J = robot.jacobian(robot.home, frames[-1])
            assert J.shape == (6, robot.dof) and np.isfinite(J).all(), name


def test_finders_accept_stems_and_relative_paths():
    assert models.example_robot_data("ur5_joint_limited_robot").name == (
        "ur5_joint_limited_robot.urdf"
    )
    assert models.pybullet_data("kuka_iiwa/model_free_base.urdf").is_file()
    assert redik.models.scene_path("example-robot-data:ur5") == models.example_robot_data("ur5")
    robot = redik.load("pybullet_data:kuka_iiwa", ee="lbr_iiwa_link_7", meshes=False)
    assert robot.dof == 7


def test_finders_name_close_matches():
    with pytest.raises(redik.ModelError, match="did you mean 'ur5'"):
        models.example_robot_data("ur6")
    with pytest.raises(redik.ModelError, match="kuka_iiwa"):
        models.pybullet_data("kuka")


def test_missing_packages_say_which_extra_to_install(monkeypatch):
    import importlib.metadata
    import sys

    def not_installed(name):
        raise importlib.metadata.PackageNotFoundError(name)

    monkeypatch.setattr(importlib.metadata, "distribution", not_installed)
    monkeypatch.setattr(sys, "path", [])
    monkeypatch.setattr(sys, "prefix", "/nonexistent")
    monkeypatch.delenv("AMENT_PREFIX_PATH", raising=False)
    with pytest.raises(redik.ModelError, match=r"redik\[models\]"):
        models.example_robot_data("ur5")
    monkeypatch.setitem(sys.modules, "pybullet_data", None)
    with pytest.raises(redik.ModelError, match=r"redik\[models\]"):
        models.pybullet_data("kuka_iiwa")


# --------------------------------------------------------------------------------------
# Mesh paths, on small files written here

_URDF = """<robot name="tiny">
  <link name="base"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0"
    iyz="0"/></inertial>{collision}</link>
  <link name="arm"/>
  <link name="tool"/>
  <joint name="j1" type="continuous"><parent link="base"/><child link="arm"/>
    <origin xyz="0 0 0.5" rpy="0.1 0.2 0.3"/><axis xyz="0 0 1"/></joint>
  <joint name="flange" type="fixed"><parent link="arm"/><child link="tool"/>
    <origin xyz="0.3 0 0" rpy="0 1.5707963267948966 0"/></joint>
</robot>"""


def _collision(filename: str) -> str:
    return f'<collision><geometry><mesh filename="{filename}"/></geometry></collision>'


def _write_stl(path: Path) -> None:
    """A binary STL of a unit tetrahedron."""
    vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float32)
    faces = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("wb") as stream:
        stream.write(b"\0" * 80 + np.uint32(len(faces)).tobytes())
        for face in faces:
            stream.write(np.zeros(3, np.float32).tobytes())
            for vertex in face:
                stream.write(vertices[vertex].tobytes())
            stream.write(b"\0\0")


def _package(tmp_path: Path) -> Path:
    """A ROS-style workspace ``ws/tiny_description/{meshes/tet.stl, urdf/tiny.urdf}``."""
    _write_stl(tmp_path / "ws" / "tiny_description" / "meshes" / "tet.stl")
    urdf = tmp_path / "ws" / "tiny_description" / "urdf" / "tiny.urdf"
    urdf.parent.mkdir(parents=True)
    return urdf


def test_package_uri_resolves_from_the_file_tree(tmp_path):
    urdf = _package(tmp_path)
    urdf.write_text(_URDF.format(collision=_collision("package://tiny_description/meshes/tet.stl")))
    model = loading.load_model(urdf)
    assert model.nmesh == 1
    robot = redik.load(urdf, ee="tool")
    assert robot.joint_names == ("j1",) and robot.lower[0] == -np.inf


def test_package_uri_resolves_from_package_paths_and_ros_package_path(tmp_path, monkeypatch):
    _package(tmp_path)
    elsewhere = tmp_path / "elsewhere" / "tiny.urdf"
    elsewhere.parent.mkdir()
    elsewhere.write_text(
        _URDF.format(collision=_collision("package://tiny_description/meshes/tet.stl"))
    )
    with pytest.raises(redik.ModelError) as error:
        loading.load_model(elsewhere)
    message = str(error.value)
    assert "package://tiny_description/meshes/tet.stl" in message and "'base'" in message
    assert str(elsewhere.parent) in message and "meshes=False" in message
    assert "package_paths" in message
    assert loading.load_model(elsewhere, package_paths=[tmp_path / "ws"]).nmesh == 1
    # The package folder itself works as a search folder too.
    package = tmp_path / "ws" / "tiny_description"
    assert loading.load_model(elsewhere, package_paths=package).nmesh == 1
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(tmp_path / "ws"))
    assert loading.load_model(elsewhere).nmesh == 1
    monkeypatch.delenv("ROS_PACKAGE_PATH")
    # A catkin/colcon workspace: packages (folders with a package.xml) nested below src/.
    nested = tmp_path / "catkin" / "src" / "robots" / "tiny_description"
    nested.parent.mkdir(parents=True)
    package.rename(nested)
    with pytest.raises(redik.ModelError):
        loading.load_model(elsewhere, package_paths=[tmp_path / "catkin" / "src"])
    (nested / "package.xml").write_text("<package><name>tiny_description</name></package>")
    assert loading.load_model(elsewhere, package_paths=[tmp_path / "catkin" / "src"]).nmesh == 1
    # A package is named by its package.xml, whatever its folder is called (a git checkout).
    renamed = nested.parent / "tiny_robot-main"
    nested.rename(renamed)
    assert loading.load_model(elsewhere, package_paths=[tmp_path / "catkin" / "src"]).nmesh == 1
    assert loading.load_model(elsewhere, meshes=False).nmesh == 0


def test_relative_and_file_uri_mesh_paths(tmp_path, monkeypatch):
    urdf = _package(tmp_path)
    urdf.write_text(_URDF.format(collision=_collision("../meshes/tet.stl")))
    monkeypatch.chdir(tmp_path)  # relative to the file, not to the working directory
    assert loading.load_model(urdf).nmesh == 1
    mesh = tmp_path / "ws" / "tiny_description" / "meshes" / "tet.stl"
    urdf.write_text(_URDF.format(collision=_collision(f"file://{mesh}")))
    assert loading.load_model(urdf).nmesh == 1
    urdf.write_text(_URDF.format(collision=_collision("../meshes/missing.stl")))
    with pytest.raises(redik.ModelError, match=r"missing\.stl"):
        loading.load_model(urdf)


def test_mujoco_extension_meshdir_and_strippath_are_honoured(tmp_path):
    urdf = _package(tmp_path)
    extension = '<mujoco><compiler meshdir="../meshes" strippath="true"/></mujoco>'
    # MuJoCo strips the folders while parsing; the file name is then looked up in meshdir.
    for filename in ("cad/export/tet.stl", "/opt/ros/elsewhere/tet.stl"):
        text = _URDF.format(collision=_collision(filename))
        urdf.write_text(text.replace('<robot name="tiny">', f'<robot name="tiny">{extension}'))
        assert loading.load_model(urdf).nmesh == 1


def test_urdf_string_resolves_relative_to_directory(tmp_path):
    _package(tmp_path)
    xml = _URDF.format(collision=_collision("meshes/tet.stl"))
    robot = redik.Robot.from_xml_string(
        xml, ee="tool", directory=tmp_path / "ws" / "tiny_description"
    )
    assert robot.model.nmesh == 1
    with pytest.raises(redik.ModelError, match=r"meshes/tet\.stl"):
        redik.Robot.from_xml_string(xml, ee="tool", directory=tmp_path)
    assert redik.Robot.from_xml_string(xml, ee="tool", meshes=False).model.nmesh == 0


def test_undecodable_mesh_is_dropped_with_a_warning(tmp_path):
    urdf = _package(tmp_path)
    (tmp_path / "ws" / "tiny_description" / "meshes" / "tet.dae").write_text("<COLLADA/>")
    urdf.write_text(_URDF.format(collision=_collision("../meshes/tet.dae")))
    with pytest.warns(redik.ModelWarning, match=r"tet\.dae \(\['base'\]\)"):
        model = loading.load_model(urdf)
    assert model.nmesh == 0 and model.ngeom == 0


def test_fixed_link_is_a_frame_at_its_urdf_pose():
    robot = redik.Robot.from_xml_string(_URDF.format(collision=""), ee="tool", meshes=False)
    q = np.array([0.7])
    # T_tool = T(origin_j1) · Rz(q) · T(flange), rpy = Rz(yaw) Ry(pitch) Rx(roll) (URDF).

    def transform(xyz, rotation):
        T = np.eye(4)
        T[:3, :3] = rotation.as_matrix()
        T[:3, 3] = xyz
        return T

    expected = (
        transform([0, 0, 0.5], Rotation.from_euler("xyz", [0.1, 0.2, 0.3]))
        @ transform([0, 0, 0], Rotation.from_euler("z", 0.7))
        @ transform([0.3, 0, 0], Rotation.from_euler("y", np.pi / 2))
    )
    np.testing.assert_allclose(robot.fk(q), expected, atol=1e-12)


# --------------------------------------------------------------------------------------
# Frames and options


def test_unknown_frame_lists_close_matches_and_frames():
    path = models.example_robot_data("panda")
    with pytest.raises(redik.UnknownFrame) as error:
        _load_robot(path, ee="panda_hnd", meshes=False)
    message = str(error.value)
    assert "did you mean 'panda_hand'" in message
    assert "bodies: [" in message and "'panda_link7'" in message and "sites: [" in message


def test_unknown_frame_suggests_names_containing_it():
    with pytest.raises(redik.UnknownFrame, match="did you mean 'ee_link'"):
        _load_robot(models.example_robot_data("ur5"), ee="ee", meshes=False)


@pytest.mark.parametrize("key", sorted(THIRD_PARTY))
def test_a_third_party_model_loads_whole_and_a_frame_task_names_its_frame(key):
    finder, name, floating, frames = THIRD_PARTY[key]
    robot = _load_robot(finder(name), ee=None, meshes=False, floating_base=floating)
    assert robot.ee is None and not robot.is_chain
    assert set(frames) & set(robot.suggested_frames())  # the flanges and hands it would pick
    frame = frames[0]
    q_goal = robot.clip(robot.home + 0.05)
    task = redik.FrameTask(frame, target=robot.fk(q_goal, frame))
    problem = redik.Problem(robot, [task, redik.PostureTask(robot.home, cost=1e-3)])
    q = robot.home.copy()
    error = redik.lie.position_distance(robot.fk(q, frame), task.target)
    for _ in range(20):
        q = robot.integrate(q, problem.step(q))
    assert redik.lie.position_distance(robot.fk(q, frame), task.target) < 0.1 * error


def test_without_a_frame_a_chain_lists_the_sites_and_leaf_bodies():
    robot = _load_robot(models.example_robot_data("ur5"), ee=None, meshes=False)
    for needs_a_chain in (
        robot.chain,
        lambda: robot.frame(None),
        lambda: redik.solve_pose(robot, np.eye(4)),
        lambda: redik.solve_batch(robot, np.eye(4)[None]),
        lambda: redik.explore_self_motion(robot, np.eye(4)),
    ):
        with pytest.raises(redik.UnknownFrame) as error:
            needs_a_chain()
        message = str(error.value)
        assert "names no end-effector" in message and "did you mean" not in message
        assert "'tool0'" in message and "leaf bodies [" in message
    chain = robot.chain("tool0")
    assert chain.is_chain and chain.dof == 6 and chain.ee.name == "tool0"
    result = redik.solve_pose(robot, chain.fk(chain.random_q(1)), frame="tool0", seed=0)
    assert result.success


def test_unknown_frame_lists_every_kind_and_points_out_a_geom():
    xml = """<mujoco><worldbody><body name="link"><joint name="j" axis="0 0 1"/>
      <geom name="finger" size="0.1"/><site name="ee"/></body></worldbody></mujoco>"""
    model = redik.Robot.from_xml_string(xml).model
    message = str(loading.unknown_frame(model, "fingr", "arm"))
    assert message.startswith("no site or body or geom named 'fingr' in arm")
    assert "did you mean 'finger'" in message and "geoms: ['finger']" in message
    message = str(loading.unknown_frame(model, "body:finger", "arm", kinds=("site", "body")))
    assert "'finger' is a geom, which is not a frame here" in message
    assert "geoms:" not in message and "bodies: ['world', 'link']" in message
    sites = "".join(f'<site name="s{i}"/>' for i in range(105))
    crowded = redik.Robot.from_xml_string(xml.replace('<site name="ee"/>', sites), ee="s0")
    assert "] and 5 more" in str(loading.unknown_frame(crowded.model, "nothing", "arm"))


def test_mjcf_keeps_keyframes_sites_includes_and_relative_assets(tmp_path):
    _write_stl(tmp_path / "assets" / "tet.stl")
    (tmp_path / "parts").mkdir()
    (tmp_path / "parts" / "arm.xml").write_text(
        """<mujoco><body name="base" pos="1 2 3" euler="0 0 90">
          <body name="link"><joint name="j" axis="0 0 1" range="-60 60"/>
          <geom type="mesh" mesh="tet"/><site name="ee" pos="1 0 0"/></body></body></mujoco>"""
    )
    (tmp_path / "arm.xml").write_text(
        """<mujoco model="arm"><compiler meshdir="assets"/>
      <asset><mesh file="tet.stl"/></asset>
      <worldbody><include file="parts/arm.xml"/></worldbody>
      <keyframe><key name="home" qpos="0.5" qvel="0.25"/><key name="rest"/></keyframe>
    </mujoco>"""
    )
    robot = redik.load(tmp_path / "arm.xml")
    assert robot.model.nmesh == 1 and robot.home[0] == 0.5 and robot.ee.kind == "site"
    assert redik.load(tmp_path / "arm.xml", meshes=False).model.nmesh == 0
    # A free root: each keyframe gains the root's initial pose first and keeps its own values.
    floating = redik.load(tmp_path / "arm.xml", floating_base=True)
    model = floating.model
    assert model.nq == 8 and model.jnt_type[0] == mujoco.mjtJoint.mjJNT_FREE
    half = np.sqrt(0.5)
    np.testing.assert_allclose(model.key_qpos[0], [1, 2, 3, half, 0, 0, half, 0.5], atol=1e-15)
    np.testing.assert_allclose(model.key_qvel[0], [0, 0, 0, 0, 0, 0, 0.25])
    np.testing.assert_allclose(model.key_qpos[1], model.qpos0)  # a key without qpos: qpos0
    assert floating.home[0] == 0.5
    np.testing.assert_allclose(floating.fk(floating.home), robot.fk(robot.home), atol=1e-15)


def test_bad_options_and_files(tmp_path):
    path = models.example_robot_data("ur5")
    xacro = tmp_path / "arm.urdf"
    xacro.write_text(
        '<robot name="a"><link name="b"/><link name="c"/><joint name="j" type="fixed">'
        '<parent link="b"/><child link="c"/><origin xyz="$(arg x) 0 0"/></joint></robot>'
    )
    with pytest.raises(redik.ModelError, match="xacro file"):
        loading.load_spec(xacro)
    with pytest.raises(redik.InvalidInput, match="meshes must be True or False"):
        loading.load_spec(path, meshes="no")
    with pytest.raises(redik.InvalidInput, match="XML string"):
        loading.load_spec_from_string(b"<mujoco/>")
    with pytest.raises(redik.ModelError, match="not SDF"):
        loading.load_spec(models.pybullet_data("kuka_iiwa/model.sdf"))
    with pytest.raises(redik.ModelError, match="not found"):
        loading.load_spec("/nonexistent/robot.urdf")
    # A path of the wrong type is an InvalidInput naming the argument, not a raw TypeError.
    for call, match in [
        (lambda: loading.load_spec(None), "source"),
        (lambda: loading.load_spec(path, package_paths=5), "package_paths"),
        (lambda: loading.load_spec(path, package_paths=[tmp_path, None]), r"package_paths\[1\]"),
        (lambda: loading.load_spec_from_string("<mujoco/>", directory=3), "directory"),
        (lambda: loading.search_folders(5), "package_paths"),
        (lambda: redik.load(None), "scene name"),
    ]:
        with pytest.raises(redik.InvalidInput, match=match):
            call()
    xml = """<mujoco><worldbody><body name="a"/><body name="b"/></worldbody></mujoco>"""
    with pytest.raises(redik.ModelError, match="exactly one body"):
        loading.load_spec_from_string(xml, floating_base=True)


def test_load_spec_returns_an_editable_spec():
    spec = loading.load_spec(models.example_robot_data("ur5"), meshes=False)
    assert isinstance(spec, mujoco.MjSpec)
    spec.body("tool0").add_site(name="tcp", pos=[0, 0, 0.1])
    model = loading.compile_spec(spec)
    robot = redik.Robot(model, ee="tcp")
    T_tool = robot.fk(robot.home, "tool0")
    np.testing.assert_allclose(robot.fk(robot.home)[:3, 3], T_tool[:3, 3] + 0.1 * T_tool[:3, 2])
