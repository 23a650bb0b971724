"""What the 6-joint closed-form solvers (PUMA, Stanford, UR) share: slot labels, the kernel
output, and the assembly of one target's solutions with their singularities.

A kernel solves B targets at once into S = 8 slots ordered shoulder × elbow × wrist
(slot = 4·shoulder + 2·elbow + wrist); the scalar solvers run it with B = 1 and keep the valid,
distinct slots.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from redik.analytic._solution import (
    IKSolutions,
    JointSolution,
    SolutionFamily,
    finalize,
)
from redik.analytic.wrist import WRIST_LABELS

SHOULDER_LABELS = ("left", "right")
#: Slot labels of an arm without an elbow choice (the Stanford arm): shoulder × wrist.
SHOULDER_WRIST_LABELS = tuple(f"{s}-{w}" for s in SHOULDER_LABELS for w in WRIST_LABELS)
ELBOW_LABELS = ("up", "down")
ARM_LABELS = tuple(
    f"{shoulder}-{elbow}-{wrist}"
    for shoulder in SHOULDER_LABELS
    for elbow in ELBOW_LABELS
    for wrist in WRIST_LABELS
)


def broadcast_flags(flags: dict[str, np.ndarray], shape: tuple[int, ...]) -> dict[str, np.ndarray]:
    """Broadcast per-target/per-branch flags, whose axes are a prefix of ``shape`` (B, …),
    to ``shape`` and flatten the branch axes into slots (B, S)."""
    return {
        kind: np.broadcast_to(
            flag.reshape(flag.shape + (1,) * (len(shape) - flag.ndim)), shape
        ).reshape(shape[0], -1)
        for kind, flag in flags.items()
    }


#: Singularity kinds a kernel reports, in the order their families take precedence.
SINGULARITY_KINDS = ("base_axis", "elbow_free", "shoulder_boundary", "elbow_boundary", "wrist")


@dataclass(frozen=True)
class ArmBranches:
    """Kernel output for B targets and S slots.

    Attributes:
        q: (B, S, n) joint vectors (finite but meaningless where not valid).
        valid: (B, S) whether the slot solves its target.
        flags: Singularity kind → (B, S) bool, for the kinds the arm can have.
            ``base_axis``: θ1 arbitrary; ``elbow_free``: θ2 arbitrary (wrist at the shoulder);
            ``shoulder_boundary``: left and right coincide; ``elbow_boundary``: up and down
            coincide (arm stretched or folded); ``wrist``: the wrist is singular.
        shoulder_ok: (B,) the first sub-problem (θ1) is solvable.
        plane_radius: (B,) distance the elbow sub-problem has to span (for the reason).
    """

    q: np.ndarray
    valid: np.ndarray
    flags: dict[str, np.ndarray]
    shoulder_ok: np.ndarray
    plane_radius: np.ndarray

    @property
    def singular(self) -> np.ndarray:
        """(B, S) whether the slot is at any singularity."""
        return np.logical_or.reduce(list(self.flags.values()))


#: ``describe(q, slot)`` → (text, family or None) for one singularity kind.
Describer = Callable[[np.ndarray, int], tuple[str, SolutionFamily | None]]


def arm_solutions(
    branches: ArmBranches,
    labels: tuple[str, ...],
    describers: dict[str, Describer],
    revolute: np.ndarray,
    limits: tuple[np.ndarray, np.ndarray] | None,
) -> IKSolutions:
    """The distinct solutions of target 0 of ``branches``, with their singularities.

    ``labels`` names the slots, wrist branch last (odd slots are "flip"). At a wrist
    singularity the flip slot belongs to the same family as the noflip slot and is left out;
    coincident slots (shoulder or elbow boundary) are merged by ``finalize``.
    """
    candidates = []
    n_joints = branches.q.shape[-1]
    for slot in range(branches.q.shape[1]):
        if not branches.valid[0, slot]:
            continue
        q = branches.q[0, slot]
        if branches.flags["wrist"][0, slot] and slot % 2 == 1:
            continue
        texts, family = [], None
        for kind in SINGULARITY_KINDS:
            if kind in branches.flags and branches.flags[kind][0, slot]:
                text, kind_family = describers[kind](q, slot)
                texts.append(text)
                family = family or kind_family
        candidates.append(JointSolution(q, labels[slot], "; ".join(texts), family))
    return finalize(candidates, n_joints, revolute, limits)


def free_joint(
    text: str, joint: int, member: Callable[[float], np.ndarray]
) -> tuple[str, SolutionFamily]:
    """A singularity's text and the family in which ``joint`` is free (``member(t) -> q``)."""
    return text, SolutionFamily((joint,), text, member)


def rotate_z_transpose(theta: np.ndarray, R: np.ndarray) -> np.ndarray:
    """:math:`R_z(θ)^T R` for θ of shape (...) and R broadcastable to (..., 3, 3)."""
    c, s = np.cos(theta), np.sin(theta)
    return np.stack(
        [
            c[..., None] * R[..., 0, :] + s[..., None] * R[..., 1, :],
            c[..., None] * R[..., 1, :] - s[..., None] * R[..., 0, :],
            np.broadcast_to(R[..., 2, :], (*theta.shape, 3)),
        ],
        axis=-2,
    )


def rotate_y_transpose(theta: np.ndarray, M: np.ndarray) -> np.ndarray:
    """:math:`R_y(θ)^T M` for θ of shape (...) and M broadcastable to (..., 3, 3)."""
    c, s = np.cos(theta)[..., None], np.sin(theta)[..., None]
    middle = np.broadcast_to(M[..., 1, :], (*theta.shape, 3))
    return np.stack(
        [c * M[..., 0, :] - s * M[..., 2, :], middle, s * M[..., 0, :] + c * M[..., 2, :]],
        axis=-2,
    )
