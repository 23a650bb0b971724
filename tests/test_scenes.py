"""The bundled scenes: they load, match the published tables, and match the scene library."""

from __future__ import annotations

import json
import math
from pathlib import Path

import mujoco
import numpy as np
import pytest

import redik
from redik.models import dh
from redik.models.builder import read_dh
from redik.models.scene_library import SCENES, write_scenes

ROOT = Path(__file__).resolve().parent.parent
SCENE_DIR = ROOT / "scenes"
SCENE_FILES = sorted(SCENE_DIR.glob("*.xml"))
TABLES = json.loads((Path(__file__).parent / "data" / "kinematic-tables.json").read_text())
SAMPLES = 60

# PUMA 560 as published (Paul, Shimano and Mayer 1981): standard DH in inches.
PUMA_INCH = 0.0254
PUMA_ROWS = [
    (0.0, 0.0, -math.pi / 2),
    (17.000 * PUMA_INCH, 0.0, 0.0),
    (0.75 * PUMA_INCH, 4.937 * PUMA_INCH, math.pi / 2),
    (0.0, 17.000 * PUMA_INCH, -math.pi / 2),
    (0.0, 0.0, math.pi / 2),
    (0.0, 0.0, 0.0),
]
PUMA_RANGES_DEG = [(-160, 160), (-225, 45), (-45, 225), (-170, 170), (-135, 135), (-170, 170)]
IIWA_RANGES_DEG = [(-170, 170), (-120, 120), (-170, 170), (-120, 120), (-170, 170), (-120, 120)]
IIWA_RANGES_DEG.append((-175, 175))


def published(name: str) -> tuple[list, str, dict | None, np.ndarray]:
    """(rows, convention, tool, ranges) of a robot from the published data."""
    if name == "puma560":
        return PUMA_ROWS, "standard", None, np.radians(PUMA_RANGES_DEG)
    entry = TABLES[name]
    convention = {"sdh": "standard", "mdh": "modified"}[entry["convention"]]
    return entry["rows"], convention, entry.get("tool"), np.array(entry["limits"])


def load(name: str) -> tuple[mujoco.MjModel, mujoco.MjData]:
    model = mujoco.MjModel.from_xml_path(str(SCENE_DIR / f"{name}.xml"))
    return model, mujoco.MjData(model)


def ee_pose(model: mujoco.MjModel, data: mujoco.MjData, q: np.ndarray) -> np.ndarray:
    data.qpos[:] = q
    mujoco.mj_kinematics(model, data)
    site = model.site("ee").id
    T = np.eye(4)
    T[:3, :3] = data.site_xmat[site].reshape(3, 3)
    T[:3, 3] = data.site_xpos[site]
    return T


def jacobian(model: mujoco.MjModel, data: mujoco.MjData, q: np.ndarray) -> np.ndarray:
    data.qpos[:] = q
    mujoco.mj_kinematics(model, data)
    mujoco.mj_comPos(model, data)
    jacp, jacr = np.zeros((3, model.nv)), np.zeros((3, model.nv))
    mujoco.mj_jacSite(model, data, jacp, jacr, model.site("ee").id)
    return np.vstack([jacp, jacr])


def random_q(model: mujoco.MjModel, rng: np.random.Generator, count: int = SAMPLES) -> np.ndarray:
    lower, upper = model.jnt_range.T
    return rng.uniform(lower, upper, (count, model.nq))


def test_every_library_scene_is_committed():
    assert sorted(path.stem for path in SCENE_FILES) == sorted(SCENES)


def test_committed_files_are_what_the_library_writes(tmp_path):
    written = write_scenes(tmp_path)
    assert sorted(path.name for path in written) == sorted(
        [path.name for path in SCENE_FILES] + ["README.md"]
    )
    for path in written:
        committed = SCENE_DIR / path.name
        assert committed.read_bytes() == path.read_bytes(), (
            f"{committed} drifted from redik.models.scene_library: run "
            "python -m redik.models.scene_library"
        )


@pytest.mark.parametrize("name", sorted(SCENES))
def test_scene_loads_with_ee_home_and_limits(name):
    model, _ = load(name)
    scene = SCENES[name]
    assert model.site("ee").id >= 0
    assert model.nq == model.nv == model.nu == scene.dof
    assert np.all(model.jnt_limited)
    home = model.key("home").qpos
    lower, upper = model.jnt_range.T
    assert np.all((lower <= home) & (home <= upper)), f"home {home} outside {model.jnt_range}"
    np.testing.assert_array_equal(home, scene.home)
    np.testing.assert_array_equal(model.key("home").ctrl, scene.home)
    np.testing.assert_array_equal(model.actuator_ctrlrange, model.jnt_range)
    # Renders: capsule links, and every moving body has geometry and mass (zero-length links
    # of spherical wrists get their joint sphere).
    assert np.sum(model.geom_type == mujoco.mjtGeom.mjGEOM_CAPSULE) >= 2
    assert np.all(model.body_geomnum[1:] >= 1) and np.all(model.body_mass[1:] > 0)
    for key, value in scene.parameters.items():
        assert model.numeric(key).data.tolist() == [value]


@pytest.mark.parametrize("name", sorted(SCENES))
def test_home_is_not_singular(name):
    model, data = load(name)
    J = jacobian(model, data, model.key("home").qpos)
    task_rows = {"planar_2r": [0, 1], "planar_3r": [0, 1, 5], "rrp_polar": [0, 1, 2]}
    task_rows["hexapod_leg"] = [0, 1, 2]
    singular_values = np.linalg.svd(J[task_rows.get(name, slice(None))], compute_uv=False)
    assert singular_values.min() > 0.03 * singular_values.max()


@pytest.mark.parametrize("name", ["panda", "iiwa14", "ur5e", "puma560"])
def test_joint_ranges_match_published_tables(name):
    model, _ = load(name)
    *_, ranges = published(name)
    # iiwa14 and puma560 ranges are published in whole degrees; the JSON rounds to 1e-4 rad.
    np.testing.assert_allclose(model.jnt_range, ranges, atol=1e-4)
    if name == "iiwa14":
        np.testing.assert_allclose(model.jnt_range, np.radians(IIWA_RANGES_DEG), atol=1e-12)


@pytest.mark.parametrize("name", ["panda", "iiwa14", "ur5e", "puma560"])
def test_fk_matches_published_table(name, rng):
    model, data = load(name)
    rows, convention, tool, _ = published(name)
    worst = max(
        np.max(np.abs(ee_pose(model, data, q) - dh.forward(rows, q, convention, tool)))
        for q in random_q(model, rng)
    )
    assert worst <= 1e-9


def test_panda_home_is_the_usual_ready_pose():
    # Franka's "ready" posture puts the flange ≈ 0.307 m forward, 0.59 m up, pointing down.
    model, data = load("panda")
    T = ee_pose(model, data, model.key("home").qpos)
    np.testing.assert_allclose(T[:3, 3], [0.307, 0.0, 0.59], atol=2e-3)
    np.testing.assert_allclose(T[:3, 2], [0.0, 0.0, -1.0], atol=2e-3)


def test_planar_arms_match_trigonometry(rng):
    for name, lengths in (("planar_2r", (1.0, 1.0)), ("planar_3r", (1.0, 1.0, 1.0))):
        model, data = load(name)
        for q in random_q(model, rng):
            angles = np.cumsum(q)
            T = ee_pose(model, data, q)
            expected = [lengths @ np.cos(angles), lengths @ np.sin(angles), 0.0]
            np.testing.assert_allclose(T[:3, 3], expected, atol=1e-12)
            heading = math.atan2(T[1, 0], T[0, 0])
            assert abs(math.remainder(heading - angles[-1], math.tau)) < 1e-12


def test_rrp_polar_matches_polar_coordinates(rng):
    model, data = load("rrp_polar")
    d1 = model.numeric("d1").data[0]
    for yaw, elevation, extension in random_q(model, rng):
        p = ee_pose(model, data, np.array([yaw, elevation, extension]))[:3, 3]
        horizontal = extension * math.cos(elevation)
        expected = [
            horizontal * math.cos(yaw),
            horizontal * math.sin(yaw),
            d1 + extension * math.sin(elevation),
        ]
        np.testing.assert_allclose(p, expected, atol=1e-12)


def test_hexapod_leg_matches_leg_geometry(rng):
    model, data = load("hexapod_leg")
    coxa, femur, tibia, z_offset = (
        model.numeric(key).data[0] for key in ("coxa", "femur", "tibia", "z_offset")
    )
    for q1, q2, q3 in random_q(model, rng):
        p = ee_pose(model, data, np.array([q1, q2, q3]))[:3, 3]
        radial = coxa + femur * math.cos(q2) + tibia * math.cos(q2 + q3)
        height = z_offset + femur * math.sin(q2) + tibia * math.sin(q2 + q3)
        expected = [radial * math.cos(q1), radial * math.sin(q1), height]
        np.testing.assert_allclose(p, expected, atol=1e-12)


def test_stanford_arm_matches_spong_table(rng):
    """Spong §3.3 Stanford arm (d2 shoulder offset, prismatic d3, tool length d6)."""
    model, data = load("stanford_arm")
    d2, d6 = model.numeric("d2").data[0], model.numeric("d6").data[0]
    rows = [
        (0, 0, -math.pi / 2),
        (0, d2, math.pi / 2),
        (0, 0, 0, 0, "prismatic"),
        (0, 0, -math.pi / 2),
        (0, 0, math.pi / 2),
        (0, d6, 0),
    ]
    assert model.jnt_type[2] == mujoco.mjtJoint.mjJNT_SLIDE
    for q in random_q(model, rng):
        T = ee_pose(model, data, q)
        np.testing.assert_allclose(T, dh.forward(rows, q), atol=1e-9)
        # Spong's closed form for the wrist centre o_c = o_6 − d6 z_6:
        c1, s1, c2, s2 = math.cos(q[0]), math.sin(q[0]), math.cos(q[1]), math.sin(q[1])
        centre = [c1 * s2 * q[2] - s1 * d2, s1 * s2 * q[2] + c1 * d2, c2 * q[2]]
        np.testing.assert_allclose(T[:3, 3] - d6 * T[:3, 2], centre, atol=1e-12)


@pytest.mark.parametrize("name", sorted(SCENES))
def test_stored_table_matches_the_library_and_the_file(name, rng):
    model, data = load(name)
    scene = SCENES[name]
    rows, convention, tool = read_dh(model)
    assert rows == scene.rows and convention == scene.convention
    for q in random_q(model, rng, 20):
        expected = dh.forward(rows, q, convention, tool)
        np.testing.assert_allclose(ee_pose(model, data, q), expected, atol=1e-9)


def test_dexter8r_is_redundant_and_generic(rng):
    """Redundancy 2 for 6-D tasks: rank 6 at generic q, and no two axes always collinear."""
    model, data = load("dexter8r")
    assert model.nq == 8
    qs = random_q(model, rng, 200)
    ranks = [np.linalg.matrix_rank(jacobian(model, data, q), tol=1e-8) for q in qs]
    assert min(ranks) == 6
    # Joint axes as lines (point, direction) in the world; two axes are "aligned" at q when
    # they are collinear. Every pair must be non-collinear at some sampled q.
    separation = np.zeros((8, 8))
    for q in qs[:20]:
        data.qpos[:] = q
        mujoco.mj_kinematics(model, data)
        points, axes = data.xanchor.copy(), data.xaxis.copy()
        for i in range(8):
            for j in range(i + 1, 8):
                angle = np.linalg.norm(np.cross(axes[i], axes[j]))
                offset = np.linalg.norm(np.cross(points[j] - points[i], axes[i]))
                separation[i, j] = max(separation[i, j], angle + offset)
    upper = np.triu_indices(8, 1)
    assert separation[upper].min() > 1e-3


@pytest.mark.parametrize("name", [None, 5, b"panda", ["panda"], "", "   "])
def test_load_refuses_what_is_not_a_name_or_path_saying_what_is_accepted(name):
    with pytest.raises(redik.InvalidInput, match=r"bundled scene name \(one of \[.*'panda'"):
        redik.load(name)


@pytest.mark.parametrize("name", ["x" * 5000, "a\0b", "no_such_robot", "missing/robot"])
def test_load_of_an_unknown_name_is_a_model_error_listing_the_scenes(name):
    with pytest.raises(redik.ModelError, match=r"bundled scenes: \[.*'panda'.*MJCF/URDF"):
        redik.load(name)
