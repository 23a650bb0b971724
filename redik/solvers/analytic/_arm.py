"""What the 6-joint closed-form solvers (PUMA, Stanford, UR) share: slot labels, the kernel
output, and the assembly of one target's solutions with their singularities.

A kernel is written once (:mod:`._numeric`) and solves one target in floats or B targets in
(B,) arrays into S = 8 slots ordered shoulder × elbow × wrist (slot = 4·shoulder + 2·elbow +
wrist); the one-target solvers keep the valid, distinct slots, the batch solvers stack them.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from redik.solvers.analytic._numeric import Numeric, Value
from redik.solvers.analytic._solution import (
    Candidate,
    IKSolutions,
    SolutionFamily,
    finalize,
    wrap_angle,
)
from redik.solvers.analytic.wrist import WRIST_LABELS

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


#: Singularity kinds a kernel reports, in the order their families take precedence.
SINGULARITY_KINDS = ("base_axis", "elbow_free", "shoulder_boundary", "elbow_boundary", "wrist")


class Slot(NamedTuple):
    """One slot of a kernel, for one target (floats, bools) or B targets ((B,) arrays).

    Attributes:
        q: The n joint values (meaningless where not valid).
        valid: Whether the slot solves its target.
        flags: Singularity kind → whether the slot is at it, for the kinds the arm can have.
            ``base_axis``: θ1 arbitrary; ``elbow_free``: θ2 arbitrary (wrist at the shoulder);
            ``shoulder_boundary``: left and right coincide; ``elbow_boundary``: up and down
            coincide (arm stretched or folded); ``wrist``: the wrist is singular.
    """

    q: tuple[Value, ...]
    valid: Value
    flags: dict[str, Value]


@dataclass(frozen=True)
class ArmSlots:
    """Kernel output: S slots, plus what the reason for an unreachable target needs.

    Attributes:
        slots: The S :class:`Slot`, in the arm's label order.
        shoulder_ok: The first sub-problem (θ1) is solvable.
        plane_radius: Distance the elbow sub-problem has to span (for the reason).
    """

    slots: list[Slot]
    shoulder_ok: Value
    plane_radius: Value

    def arrays(self, batch: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(q, valid, singular)`` of a batch kernel: (B, S, n), (B, S), (B, S)."""
        n_slots, n_joints = len(self.slots), len(self.slots[0].q)
        q = np.empty((batch, n_slots, n_joints))
        valid = np.empty((batch, n_slots), bool)
        singular = np.zeros((batch, n_slots), bool)
        for index, slot in enumerate(self.slots):
            for joint, value in enumerate(slot.q):
                q[:, index, joint] = value
            valid[:, index] = slot.valid
            for flag in slot.flags.values():
                singular[:, index] |= flag
        return q, valid, singular


def shoulder(
    x: Value, y: Value, offset: float, tol: float, num: Numeric
) -> tuple[Value, Value, Value, Value]:
    r"""The first sub-problem of an arm whose joints after the first keep a constant lateral
    ``offset`` from the base axis: :math:`X = \pm\sqrt{x^2 + y^2 - \text{offset}^2}`.

    Returns ``(rho, ok, boundary, reach)``: the distance ρ of (x, y) from the base axis,
    whether ρ ≥ |offset| (within ``tol``), whether ρ = |offset| (left and right coincide)
    and :math:`|X|` (0 on that boundary).
    """
    rho = num.hypot(x, y)
    ok = rho >= abs(offset) - tol
    boundary = abs(rho - abs(offset)) <= tol
    reach = num.where(
        boundary, 0.0, num.sqrt(num.maximum((rho - abs(offset)) * (rho + abs(offset)), 0.0))
    )
    return rho, ok, boundary, reach


def wrist_columns(
    M: Any, c1: Value, s1: Value, c: Value, s: Value
) -> tuple[Value, Value, Value, Value, Value, Value]:
    """Columns 0 and 2 of :math:`R_y(θ)^T R_z(θ_1)^T R` (the rotation left to a spherical
    wrist after :math:`R_z(θ_1) R_y(θ)`), from the pose entries ``M[i][j]`` and the cosines
    and sines: ``(r00, r10, r20, r02, r12, r22)``, the arguments of
    :func:`redik.solvers.analytic.wrist.zyz_pair`."""
    a00, a10 = c1 * M[0][0] + s1 * M[1][0], c1 * M[1][0] - s1 * M[0][0]
    a02, a12 = c1 * M[0][2] + s1 * M[1][2], c1 * M[1][2] - s1 * M[0][2]
    return (
        c * a00 - s * M[2][0],
        a10,
        s * a00 + c * M[2][0],
        c * a02 - s * M[2][2],
        a12,
        s * a02 + c * M[2][2],
    )


#: ``describe(q, slot)`` → (text, family or None) for one singularity kind.
Describer = Callable[[np.ndarray, int], tuple[str, SolutionFamily | None]]


def arm_solutions(
    arm: ArmSlots,
    labels: tuple[str, ...],
    describers: dict[str, Describer],
    revolute: np.ndarray,
    limits: tuple[np.ndarray, np.ndarray] | None,
) -> IKSolutions:
    """The distinct solutions of a one-target (:data:`._numeric.SCALAR`) kernel output, with
    their singularities.

    ``labels`` names the slots, wrist branch last (odd slots are "flip"). At a wrist
    singularity the flip slot belongs to the same family as the noflip slot and is left out;
    coincident slots (shoulder or elbow boundary) are merged by ``finalize``.
    """
    candidates = []
    for index, (q, valid, flags) in enumerate(arm.slots):
        if not valid or (flags["wrist"] and index % 2 == 1):
            continue
        texts, family = [], None
        for kind in SINGULARITY_KINDS:
            if flags.get(kind, False):
                text, kind_family = describers[kind](wrapped(q, revolute), index)
                texts.append(text)
                family = family or kind_family
        candidates.append(Candidate(q, labels[index], "; ".join(texts), family))
    return finalize(candidates, len(arm.slots[0].q), revolute, limits)


def wrapped(q: tuple[float, ...], revolute: np.ndarray) -> np.ndarray:
    """A kernel's joint values as an array with the angles wrapped to (−π, π]."""
    array = np.array(q, dtype=float)
    return np.where(revolute, wrap_angle(array), array)


def free_joint(
    text: str, joint: int, member: Callable[[float], np.ndarray]
) -> tuple[str, SolutionFamily]:
    """A singularity's text and the family in which ``joint`` is free (``member(t) -> q``)."""
    return text, SolutionFamily((joint,), text, member)
