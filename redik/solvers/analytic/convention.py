r"""Angle conventions: a course's or a servo's joint angles from the solvers' DH angles.

Each closed-form solver works in its DH joint variables ``q`` (stated in its module
docstring). A lecture, a datasheet or a servo horn often measures the same joints from
another zero or in the other sense; both are affine per joint:

.. math:: a_i = s_i\, q_i + c_i, \qquad q_i = s_i\, (a_i - c_i), \qquad s_i = ±1,

so a student's numbers and the solver's are one exact map apart, in both directions, for
solutions, limits and the members of a singular family alike. The hexapod leg's lecture
angles (:data:`redik.solvers.analytic.hexapod.LECTURE`) are an instance; build another for
another lecture.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from redik.core.exceptions import InvalidInput
from redik.core.validate import real_array
from redik.solvers.analytic import _checks
from redik.solvers.analytic.results import IKSolutions, JointSolution, SolutionFamily


@dataclass(frozen=True)
class AngleConvention:
    """``a = sign · q + offset`` per joint (see the module docstring).

    Attributes:
        name: The convention's name, as the solvers' ``convention=`` accepts it.
        symbols: The name of each angle in that convention, e.g. ``("α", "β", "γ")``.
        signs: ``s_i``, each +1 or −1.
        offsets: ``c_i`` (rad, or m for a prismatic joint).
        description: What each angle measures, for a docstring or a message.
    """

    name: str
    symbols: tuple[str, ...]
    signs: tuple[float, ...]
    offsets: tuple[float, ...]
    description: str = ""

    def __post_init__(self) -> None:
        n = len(self.symbols)
        if len(self.signs) != n or len(self.offsets) != n:
            raise InvalidInput(
                f"an angle convention needs one sign and one offset per joint ({n}), got "
                f"{len(self.signs)} and {len(self.offsets)}"
            )
        if any(sign not in (1, -1) for sign in self.signs):
            raise InvalidInput(f"signs must be +1 or -1, got {self.signs}")
        if not np.all(np.isfinite(real_array(self.offsets, "offsets"))):
            raise InvalidInput(f"offsets must be finite, got {self.offsets}")

    @property
    def n_joints(self) -> int:
        """The number of joints."""
        return len(self.symbols)

    def from_joints(self, q: np.ndarray) -> np.ndarray:
        """The convention's angles ``a = s q + c`` of DH joint values ``q`` (…, n)."""
        q = self._checked(q, "q")
        return np.asarray(self.signs) * q + np.asarray(self.offsets)

    def to_joints(self, angles: np.ndarray) -> np.ndarray:
        """The DH joint values ``q = s (a − c)`` of the convention's ``angles`` (…, n)."""
        angles = self._checked(angles, "angles")
        return np.asarray(self.signs) * (angles - np.asarray(self.offsets))

    def limits_to_joints(
        self, limits: tuple[np.ndarray, np.ndarray] | None
    ) -> tuple[np.ndarray, np.ndarray] | None:
        """Limits given in the convention, as DH joint limits.

        ``(lower, upper)`` given in the convention, as DH joint limits (a flipped sign
        swaps the bounds).
        """
        if limits is None:
            return None
        if len(limits) != 2:
            raise InvalidInput(f"limits must be a pair (lower, upper), got {limits!r}")
        lower, upper = (self.to_joints(np.asarray(bound, dtype=float)) for bound in limits)
        return np.minimum(lower, upper), np.maximum(lower, upper)

    def map_solutions(self, solutions: IKSolutions) -> IKSolutions:
        """Every solution (and family member) of a DH-angle result in this convention."""
        mapped = []
        for solution in solutions:
            family = solution.family
            if family is not None:
                family = dataclasses.replace(family, generator=self._mapped_generator(family))
            mapped.append(
                JointSolution(
                    self.from_joints(solution.q), solution.label, solution.singular, family
                )
            )
        return IKSolutions(
            tuple(mapped),
            solutions.n_joints,
            solutions.reachable,
            solutions.reason,
            solutions.preferred,
        )

    def _mapped_generator(self, family: SolutionFamily) -> Callable[..., np.ndarray]:
        """``at(*t)`` with the free joints' values ``t`` in this convention too."""
        signs, offsets = self.signs, self.offsets

        def generator(*t: float) -> np.ndarray:
            dh = [signs[i] * (value - offsets[i]) for i, value in zip(family.free, t, strict=True)]
            return self.from_joints(family.generator(*dh))

        return generator

    def _checked(self, values: np.ndarray, name: str) -> np.ndarray:
        array = real_array(values, name)
        if array.shape[-1:] != (self.n_joints,):
            raise InvalidInput(
                f"{name} must end in {self.n_joints} values ({', '.join(self.symbols)}) for "
                f"the {self.name!r} convention, got shape {array.shape}"
            )
        if np.isnan(array).any():  # ±inf stays: an open bound of limits_to_joints
            raise InvalidInput(f"{name} holds NaN: {np.array2string(array)}")
        return array


def solve_in(
    convention: str,
    conventions: dict[str, AngleConvention | None],
    solver: str,
    limits: tuple[object, object] | None,
    n_joints: int,
    solve: Callable[[tuple[np.ndarray, np.ndarray] | None], IKSolutions],
) -> IKSolutions:
    """Solve in the DH angles and map the result into a convention.

    ``solve(joint_limits)`` in the convention named ``convention`` among a solver's (None:
    its DH angles): resolve it, check the ``limits`` (given in it) and convert them to DH joint
    limits, solve, and map the solutions back into it.
    """
    if convention not in conventions:
        raise InvalidInput(
            f"{solver} convention must be one of {sorted(conventions)}, got {convention!r}"
        )
    mapping = conventions[convention]
    checked_limits = _checks.limits(limits, n_joints)
    if mapping is None:
        return solve(checked_limits)
    return mapping.map_solutions(solve(mapping.limits_to_joints(checked_limits)))
