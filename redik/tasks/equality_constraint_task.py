r"""Hold a model's ``<equality>`` connect and weld constraints (mink's ``EqualityConstraintTask``).

MuJoCo's equality constraints close kinematic loops: ``connect`` joins two bodies (or sites)
at a point, ``weld`` fixes their relative pose. The task's error is MuJoCo's own constraint
residual (``efc_pos`` of ``mj_instantiateEquality``), computed here from the kinematics
alone, so it needs no constraint pipeline:

- **connect**, bodies :math:`b_1, b_2` with anchors :math:`a_1` (in :math:`b_1`) and
  :math:`a_2` (in :math:`b_2`): :math:`e = p_1 - p_2`, :math:`p_i = x_i + R_i a_i` (for sites,
  the sites' positions), :math:`J = J_{p_1} - J_{p_2}` with :math:`J_p` the world Jacobian
  of a point fixed to its body;
- **weld**, bodies :math:`b_0, b_1`, the position part as for connect (anchors
  ``data[3:6]`` in :math:`b_0`, ``data[0:3]`` in :math:`b_1`), and the orientation part
  :math:`s\,\mathrm{Im}(\bar q_1 q_0 q_{rel})` (for sites :math:`\bar q_{s1} q_{s0}`), with
  :math:`s` the ``torquescale``; its derivative under the world angular velocities
  :math:`ω_0, ω_1` is :math:`\tfrac{s}{2}\mathrm{Im}(\bar q_1 [0, ω_0 - ω_1] q_0 q_{rel})`
  (the quaternion kinematics :math:`\dot q = \tfrac12 [0, ω] q`), linear in
  :math:`ω_0 - ω_1`.

Both vanish exactly when the constraint holds; the rows are in constraint-id order, as in
mink. At priority 0 the driver holds them to its tolerance (:func:`redik.solve_problem`):
a closed chain, two hands holding one object, a foot welded to the floor.
"""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import numpy as np
from numpy.typing import ArrayLike, NDArray

from redik.core.exceptions import InvalidInput
from redik.kinematics.robot import Robot
from redik.tasks.kinematics import KinematicState
from redik.tasks.task import ResidualTask, as_cost

WIDTH = {int(mujoco.mjtEq.mjEQ_CONNECT): 3, int(mujoco.mjtEq.mjEQ_WELD): 6}
"""Rows per constraint, by MuJoCo equality type (the types this task holds)."""


def _equality_ids(model: mujoco.MjModel, equalities: Sequence[int | str] | None) -> list[int]:
    """The constraint ids named (all of the model's when None), sorted, each checked."""
    if equalities is None:
        ids = list(range(model.neq))
    else:
        ids = [_equality_id(model, item) for item in equalities]
        if len(set(ids)) != len(ids):
            raise InvalidInput(f"equalities names a constraint twice: {list(equalities)!r}")
    if not ids:
        raise InvalidInput("EqualityConstraintTask: the model has no equality constraint")
    for i in ids:
        _check_equality(model, i)
    return sorted(ids)


def _equality_id(model: mujoco.MjModel, item: object) -> int:
    if isinstance(item, str):
        index = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_EQUALITY, item)
        if index < 0:
            raise InvalidInput(f"the model has no equality constraint named {item!r}")
        return int(index)
    if (
        isinstance(item, bool)
        or not isinstance(item, int | np.integer)
        or not 0 <= item < model.neq
    ):
        raise InvalidInput(f"an equality constraint id must be in [0, {model.neq}), got {item!r}")
    return int(item)


def _check_equality(model: mujoco.MjModel, i: int) -> None:
    name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_EQUALITY, i) or f"equality {i}"
    kind = int(model.eq_type[i])
    if kind not in WIDTH:
        raise InvalidInput(
            f"{name!r} is a {mujoco.mjtEq(kind).name} constraint; EqualityConstraintTask holds "
            "connect and weld constraints"
        )
    if not model.eq_active0[i]:
        raise InvalidInput(f"{name!r} is not active in the model (eq_active0)")


def _quat_product(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    out = np.empty(4)
    mujoco.mju_mulQuat(out, a, b)
    return out


def _conjugate(q: NDArray[np.float64]) -> NDArray[np.float64]:
    return np.array([q[0], -q[1], -q[2], -q[3]])


class EqualityConstraintTask(ResidualTask):
    """Hold the connect and weld equality constraints of ``model`` (mink's signature).

    Args:
        model: The MuJoCo model whose constraints are held (the bound robot's).
        cost: Scalar, or one cost per constraint named in ``equalities`` (in that order),
            applied to each of its rows.
        equalities: Names or ids of the constraints to hold; None holds every constraint of
            the model (each must be a connect or a weld, active in the model).
        gain: Fraction ``α ∈ [0, 1]`` of the error corrected per step.
        lm_damping: mink's Levenberg–Marquardt scale ``λ ≥ 0``.
        priority: Priority level, 0 highest (mink has none).

    Attributes:
        equalities: The constraint ids held, sorted (the order of the rows).

    Raises:
        InvalidInput: an unknown or repeated constraint, one of another type or inactive, or
            a cost of the wrong shape.
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        cost: ArrayLike = 1.0,
        equalities: Sequence[int | str] | None = None,
        gain: float = 1.0,
        lm_damping: float = 0.0,
        *,
        priority: int = 0,
    ):
        if not isinstance(model, mujoco.MjModel):
            raise InvalidInput(f"model must be a mujoco.MjModel, got {type(model).__name__}")
        given = equalities
        if isinstance(given, str | int | np.integer):
            given = [given]
        self.equalities = _equality_ids(model, given)
        # Where the constraint the caller named k-th sits in the (sorted) rows.
        self._order = (
            list(range(len(self.equalities)))
            if given is None
            else [self.equalities.index(_equality_id(model, item)) for item in given]
        )
        self._widths = [WIDTH[int(model.eq_type[i])] for i in self.equalities]
        self._model = model
        super().__init__(1.0, gain, priority, sum(self._widths), lm_damping=lm_damping)
        self.set_cost(cost)

    def set_cost(self, cost: ArrayLike) -> None:
        """Replace the cost: a scalar, or one value per constraint in ``equalities`` order."""
        per_constraint = as_cost(cost, len(self.equalities), "EqualityConstraintTask cost")
        sorted_costs = np.empty(len(self.equalities))
        sorted_costs[self._order] = per_constraint
        self.cost[:] = np.repeat(sorted_costs, self._widths)
        self.version += 1

    def bind(self, robot: Robot) -> EqualityConstraintTask:
        """Check that ``robot`` is built on the constraints' model."""
        model = robot.model
        if model is not self._model and (
            model.neq != self._model.neq
            or model.nbody != self._model.nbody
            or not np.array_equal(model.eq_type, self._model.eq_type)
        ):
            raise InvalidInput(
                f"EqualityConstraintTask was built on another model than {robot!r}'s"
            )
        super().bind(robot)
        return self

    def residual_into(
        self, state: KinematicState, e: NDArray[np.float64], J: NDArray[np.float64]
    ) -> None:
        """Write MuJoCo's residual of each constraint and its Jacobian (module docstring)."""
        row = 0
        for i, width in zip(self.equalities, self._widths, strict=True):
            self._constraint_into(state, i, e[row : row + width], J[row : row + width])
            row += width

    def _ends(
        self, state: KinematicState, i: int
    ) -> tuple[list[int], list[NDArray[np.float64]], list[NDArray[np.float64]]]:
        """The bodies, world points and orientations (quaternions) of constraint ``i``."""
        model, data = state.model, state.data
        data_i = model.eq_data[i]
        weld = int(model.eq_type[i]) == mujoco.mjtEq.mjEQ_WELD
        objects = (int(model.eq_obj1id[i]), int(model.eq_obj2id[i]))
        if int(model.eq_objtype[i]) == mujoco.mjtObj.mjOBJ_SITE:
            bodies = [int(model.site_bodyid[s]) for s in objects]
            points = [data.site_xpos[s].copy() for s in objects]
            quats = [
                _quat_product(data.xquat[b], model.site_quat[s])
                for b, s in zip(bodies, objects, strict=True)
            ]
            if weld:
                quats[1] = _conjugate(quats[1])
            return bodies, points, quats
        bodies = [max(b, 0) for b in objects]
        anchors = (data_i[3:6], data_i[0:3]) if weld else (data_i[0:3], data_i[3:6])
        points = [
            data.xpos[b] + data.xmat[b].reshape(3, 3) @ a
            for b, a in zip(bodies, anchors, strict=True)
        ]
        quats = [
            _quat_product(data.xquat[bodies[0]], data_i[6:10]),
            _conjugate(data.xquat[bodies[1]]),
        ]
        return bodies, points, quats

    def _constraint_into(
        self, state: KinematicState, i: int, e: NDArray[np.float64], J: NDArray[np.float64]
    ) -> None:
        bodies, points, quats = self._ends(state, i)
        J0 = state.point_jacobian(bodies[0], points[0])
        J1 = state.point_jacobian(bodies[1], points[1])
        e[:3] = points[0] - points[1]
        J[:3] = J0[:3] - J1[:3]
        if e.shape[0] == 3:
            return
        scale = float(state.model.eq_data[i][10])
        q, q1_bar = quats
        e[3:] = scale * _quat_product(q1_bar, q)[1:]
        # Im(q̄₁ [0, w] q) = M w: the columns of M from the unit axes.
        M = np.empty((3, 3))
        for k in range(3):
            axis = np.zeros(4)
            axis[k + 1] = 1.0
            M[:, k] = _quat_product(_quat_product(q1_bar, axis), q)[1:]
        J[3:] = 0.5 * scale * M @ (J0[3:] - J1[3:])
