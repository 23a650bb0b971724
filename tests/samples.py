"""Random rotations and poses for the tests of the group math, from a seeded generator."""

from __future__ import annotations

import numpy as np

from redik import lie


def random_rotation(rng: np.random.Generator) -> np.ndarray:
    """A rotation uniform on SO(3): a normalised Gaussian quaternion."""
    quat = rng.normal(size=4)
    return lie.matrix_from_quat(quat / np.linalg.norm(quat))


def random_pose(rng: np.random.Generator) -> np.ndarray:
    """A uniform rotation with a translation uniform in [−2, 2]³."""
    return lie.make_pose(random_rotation(rng), rng.uniform(-2, 2, 3))
