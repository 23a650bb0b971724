r"""Collision avoidance as a limit: a velocity damper on the distance between geom pairs.

For a pair of geoms at signed distance :math:`d` (``mj_geomDistance``; negative when they
penetrate) with nearest points :math:`p_1, p_2` and unit normal :math:`n` from geom 1 to
geom 2 (flipped when they penetrate, so that :math:`d` grows along :math:`n`), a step
:math:`Δq` changes the distance to first order by

.. math::

    Δd = n^\top \bigl(J_{p_2} - J_{p_1}\bigr) Δq ,

with :math:`J_p` the translational Jacobian of the point :math:`p` fixed to its geom's body
(``mj_jac``). The limit keeps every pair closer than the detection distance
:math:`d_i` from approaching faster than a fraction :math:`ξ` of its remaining margin above
the minimum distance :math:`d_s` (the velocity damper of Faverjon & Tournassoud, ICRA
1987; Kanoun, Lamiraux & Wieber, IEEE T-RO 2011, §IV-B; mink's
``CollisionAvoidanceLimit``):

.. math::

    -n^\top \bigl(J_{p_2} - J_{p_1}\bigr) Δq \;\le\; ξ\, (d - d_s) \qquad (d < d_i).

Iterated, the margin :math:`d - d_s` can shrink at most geometrically, so the pair never
comes closer than :math:`d_s` (to first order); a pair already inside the margin gets a
positive lower bound on :math:`Δd` and is pushed back out at the same rate (mink holds it
still instead). Pairs farther than :math:`d_i` give no row; a cheap bounding-sphere test
(``geom_rbound``, MuJoCo's broad phase) skips most of them before ``mj_geomDistance``.
Distances are computed on the robot's own ``MjData`` after the problem's forward
kinematics; only the robot's moved joints get columns (:mod:`redik.kinematics.robot`).

By default the rows are hard: a :class:`redik.Problem` imposes them while solving every
priority level, so no task (a posture, a second hand) can buy its objective with a
collision. With ``priority=k`` the tasks ranked above ``k`` may (a hand asked into the
obstacle gets there) and the rest of the arm keeps clear as far as they allow
(:mod:`redik.limits.limit`).

**Long steps.** The rows are first order and exist only for pairs closer than
:math:`d_i`, so one long step (an iterative solve far from its target) could carry a
geom through another. :meth:`CollisionAvoidanceLimit.admits` therefore checks the true
distances of a trial configuration, and :func:`redik.solve_problem` halves the step until
no pair ends closer than :math:`d_s` (or, for a pair already inside the margin, closer
than it was): every iterate the driver returns keeps the margin. ``Problem.step`` returns
the damped step only, as mink does; at a control rate the steps are short.
"""

from __future__ import annotations

import fnmatch
import itertools
from collections.abc import Collection, Sequence
from typing import Any

import mujoco
import numpy as np
from numpy.typing import NDArray

from redik.core.exceptions import InvalidInput, ModelError
from redik.kinematics.robot import Robot
from redik.limits.limit import InequalityLimit

GeomGroup = Sequence[str | int]
"""Geom names, or body names standing for all of the body's geoms; ``fnmatch`` patterns
(``"left_*"``) match geom and body names; an integer is a geom id (a URDF's collision geoms
have no names)."""


class CollisionAvoidanceLimit(InequalityLimit):
    """Keep geom pairs at least ``minimum_distance`` apart.

    Args:
        geom_pairs: Pairs ``(group_a, group_b)`` of geom groups (geom or body names,
            patterns such as ``"left_*"``, or geom ids); every geom of ``group_a`` is kept away from
            every geom of ``group_b`` (a group paired with itself: self-collision within
            it); pairs MuJoCo would not collide (``contype``/``conaffinity``, welded, parent
            and child, ``<exclude>``) are dropped. None: every pair of geoms that MuJoCo may
            collide — by the same filters — of which at least one is moved by the robot
            (self-collision and obstacles from the model's geoms), less the pairs already
            closer than ``minimum_distance`` at the robot's ``home`` (overlapping collision
            shapes of neighbouring links, which a URDF often has: the "collide by default"
            pairs MoveIt's setup assistant disables).
        minimum_distance: ``d_s`` (m), the distance to keep; ≥ 0.
        detection_distance: ``d_i`` (m), the distance under which a pair is constrained;
            > ``minimum_distance``.
        gain: ``ξ ∈ (0, 1]``, the fraction of the margin a step may close.
        priority: None (default): hard at every priority level; ``k``: ranked just above
            the tasks of priority ``k``, which those above may override (the semantics and
            math are in :mod:`redik.limits.limit`).

    Attributes:
        pairs: The geom id pairs checked, once bound.
        floor: Per pair, the distance :meth:`admits` holds it to: ``minimum_distance``, or
            the pair's own distance at the last linearisation when that was smaller (a pair
            already inside the margin may not come closer still).
    """

    def __init__(
        self,
        geom_pairs: Sequence[tuple[GeomGroup, GeomGroup]] | None = None,
        minimum_distance: float = 0.005,
        detection_distance: float = 0.05,
        gain: float = 0.5,
        *,
        priority: int | None = None,
    ):
        minimum_distance = _as_number(minimum_distance, "minimum_distance")
        detection_distance = _as_number(detection_distance, "detection_distance")
        gain = _as_number(gain, "gain")
        if not (np.isfinite(minimum_distance) and minimum_distance >= 0.0):
            raise InvalidInput(f"minimum_distance must be finite and >= 0, got {minimum_distance}")
        if not (np.isfinite(detection_distance) and detection_distance > minimum_distance):
            raise InvalidInput(
                f"detection_distance must be finite and > minimum_distance "
                f"({minimum_distance}), got {detection_distance}"
            )
        if not 0.0 < gain <= 1.0:
            raise InvalidInput(f"gain must be in (0, 1], got {gain}")
        if geom_pairs is not None:
            if isinstance(geom_pairs, str) or not isinstance(geom_pairs, Collection):
                raise InvalidInput(
                    f"geom_pairs must be a list of pairs (group_a, group_b), got {geom_pairs!r}"
                )
            for index, pair in enumerate(geom_pairs):
                if isinstance(pair, str) or not isinstance(pair, Sequence) or len(pair) != 2:
                    raise InvalidInput(
                        f"geom_pairs[{index}] must be a pair of groups, got {pair!r}"
                    )
        self.geom_pairs = None if geom_pairs is None else list(geom_pairs)
        self.minimum_distance = minimum_distance
        self.detection_distance = detection_distance
        self.gain = gain
        self._set_priority(priority)
        self.pairs = np.empty((0, 2), dtype=int)
        self.floor = np.empty(0)

    def bind(self, robot: Robot, tolerance: float = 0.0) -> CollisionAvoidanceLimit:
        """Prepare for ``robot`` (the base class's contract); returns self."""
        model = robot.model
        mover = _moving_ancestor(robot)
        if self.geom_pairs is None:
            a, b = np.triu_indices(model.ngeom, 1)
            pairs = _collidable_pairs(model, mover, a, b)
            pairs = _apart_at_home(robot, pairs, self.minimum_distance)
        else:
            pairs = []
            for index, pair in enumerate(self.geom_pairs):
                group_a = _geom_ids(robot, pair[0], f"geom_pairs[{index}][0]")
                group_b = _geom_ids(robot, pair[1], f"geom_pairs[{index}][1]")
                a, b = np.array(list(itertools.product(group_a, group_b))).T
                pairs += _collidable_pairs(model, mover, a, b)
            pairs = sorted(set(pairs))
            if not pairs:
                raise ModelError(
                    f"geom_pairs {list(self.geom_pairs)!r} leave no pair to check on "
                    f"{robot!r}: every pair is on bodies no moved joint separates, on welded or "
                    "parent and child bodies, or fails MuJoCo's contype/conaffinity test"
                )
        self.pairs = np.array(pairs, dtype=int).reshape(-1, 2)
        rbound = model.geom_rbound
        self._bounded = (rbound[self.pairs[:, 0]] > 0.0) & (rbound[self.pairs[:, 1]] > 0.0)
        self._radii = rbound[self.pairs[:, 0]] + rbound[self.pairs[:, 1]]
        # Per-step scratch: the rows of every pair that may become active, written in place.
        body = model.geom_bodyid
        self._pair_list = [(int(a), int(b), int(body[a]), int(body[b])) for a, b in self.pairs]
        self._fromto = np.zeros(6)
        self._normal = np.zeros(3)
        self.floor = np.full(len(self.pairs), self.minimum_distance)
        self._jac1 = np.zeros((3, model.nv))
        self._jac2 = np.zeros((3, model.nv))
        self._row = np.zeros(model.nv)
        self._G = np.zeros((len(self.pairs), robot.dof))
        self._h = np.zeros(len(self.pairs))
        super().bind(robot, tolerance)
        return self

    def _candidates(self, data: mujoco.MjData, distmax: float) -> NDArray[np.intp]:
        """Indices of the pairs whose bounding spheres are closer than ``distmax``."""
        a, b = self.pairs[:, 0], self.pairs[:, 1]
        gap = np.linalg.norm(data.geom_xpos[a] - data.geom_xpos[b], axis=1) - self._radii
        return np.flatnonzero(~self._bounded | (gap < distmax))

    def distances(self, distmax: float = 1.0) -> NDArray[np.float64]:
        """Signed distance of every pair at the robot's current state.

        Capped at ``distmax``; call ``robot.state.update(q)`` (or ``fk``) first.
        """
        robot = self._require_robot()
        data = robot.state.data
        out = np.full(len(self.pairs), distmax)
        for i in self._candidates(data, distmax):
            a, b, _, _ = self._pair_list[i]
            out[i] = mujoco.mj_geomDistance(robot.model, data, a, b, distmax, self._fromto)
        return out

    def minimum_distance_at(self, q: NDArray[np.float64]) -> tuple[float, tuple[str, str] | None]:
        """``(d, (geom_a, geom_b))``: the closest pair at ``q`` (``d`` capped at 1 m)."""
        robot = self._require_robot()
        robot.state.update(robot.check_q(q))
        if len(self.pairs) == 0:
            return 1.0, None
        distances = self.distances()
        i = int(np.argmin(distances))
        a, b = self.pairs[i]
        return float(distances[i]), (_geom_name(robot.model, a), _geom_name(robot.model, b))

    def inequalities(
        self, state: Any, dt: float | None
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]] | None:
        """``(G, h)`` at the current state, or None when inactive."""
        robot = self._require_robot()
        model, data = robot.model, robot.state.data
        fromto, normal, jac1, jac2, row = (
            self._fromto,
            self._normal,
            self._jac1,
            self._jac2,
            self._row,
        )
        G, h, columns = self._G, self._h, robot.dof_indices
        detection, minimum = self.detection_distance, self.minimum_distance
        self.floor.fill(minimum)
        count = 0
        for i in self._candidates(data, detection):
            a, b, body_a, body_b = self._pair_list[i]
            d = mujoco.mj_geomDistance(model, data, a, b, detection, fromto)
            if d >= detection:
                continue
            self.floor[i] = min(minimum, d)
            np.subtract(fromto[3:], fromto[:3], out=normal)
            if mujoco.mju_normalize3(normal) < 1e-12:  # touching: separate the geom centres
                np.subtract(data.geom_xpos[b], data.geom_xpos[a], out=normal)
                if mujoco.mju_normalize3(normal) < 1e-12:
                    continue
            elif d < 0.0:
                np.negative(normal, out=normal)  # penetrating: the nearest points cross over
            mujoco.mj_jac(model, data, jac1, None, fromto[:3], body_a)
            mujoco.mj_jac(model, data, jac2, None, fromto[3:], body_b)
            jac1 -= jac2
            np.dot(normal, jac1, out=row)  # -nᵀ(J₂ − J₁) over the model's nv columns
            np.take(row, columns, out=G[count])
            h[count] = self.gain * (d - minimum)
            count += 1
        if count == 0:
            return None
        return G[:count].copy(), h[:count].copy()

    def admits(self) -> bool:
        """Whether no pair is closer than ``minimum_distance`` at the current state.

        No pair closer than ``minimum_distance`` at the current state, unless it was already closer
        at the last linearisation and has not come closer still.

        A pair that was inside by no more than the tolerance (the slack an earlier step was
        allowed) is held to ``minimum_distance`` again, not to its own distance: else the
        slack compounds, a micrometre per iteration, while a lower level slides the arm
        along the constraint.
        """
        robot = self._require_robot()
        model, data = robot.model, robot.state.data
        tolerance = 1e-6  # 1 µm: what a distance query resolves on meshes
        minimum = self.minimum_distance
        for i in self._candidates(data, minimum):
            a, b, _, _ = self._pair_list[i]
            d = mujoco.mj_geomDistance(model, data, a, b, minimum, self._fromto)
            floor = self.floor[i] if self.floor[i] < minimum - tolerance else minimum
            if d < floor - tolerance:
                return False
        return True


def _as_number(value: Any, name: str) -> float:
    try:
        return float(value)
    except (TypeError, ValueError):
        raise InvalidInput(f"{name} must be a number, got {value!r}") from None


def _geom_name(model: mujoco.MjModel, geom: int) -> str:
    """The geom's name, else ``"<body>#<id>"`` (URDF collision geoms have no name)."""
    name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, geom)
    if name:
        return str(name)
    body = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, model.geom_bodyid[geom])
    return f"{body or 'world'}#{geom}"


def _moving_ancestor(robot: Robot) -> NDArray[np.intp]:
    """Per body.

    The nearest body (itself or an ancestor) with a joint of the robot, 0 if none. Two bodies with
    the same one move as one rigid body under the robot's joints.
    """
    model = robot.model
    joint_body = set(int(model.jnt_bodyid[j]) for j in robot.joint_ids)
    mover = np.zeros(model.nbody, dtype=int)
    for body in range(1, model.nbody):  # parents come before children in MuJoCo
        mover[body] = body if body in joint_body else mover[model.body_parentid[body]]
    return mover


def _apart_at_home(
    robot: Robot, pairs: list[tuple[int, int]], distance: float
) -> list[tuple[int, int]]:
    """The pairs at least ``distance`` apart at ``robot.home`` (held joints as held)."""
    data = mujoco.MjData(robot.model)
    data.qpos[:] = robot.full_qpos(robot.home)
    mujoco.mj_kinematics(robot.model, data)
    fromto = np.zeros(6)
    return [
        (a, b)
        for a, b in pairs
        if mujoco.mj_geomDistance(robot.model, data, a, b, distance + 1e-6, fromto) >= distance
    ]


def _collidable_pairs(
    model: mujoco.MjModel,
    mover: NDArray[np.intp],
    a: NDArray[np.intp],
    b: NDArray[np.intp],
) -> list[tuple[int, int]]:
    """The geom pairs the robot can move relative to each other and MuJoCo lets collide.

    The pairs ``(min, max)`` of geoms ``a[i]``, ``b[i]`` that the robot's joints can move relative
    to each other (different moving ancestors) and that MuJoCo's own filters let collide
    (``mj_collision``'s broad phase): contype/conaffinity, not the same weld, not a parent and child
    weld unless the parent is the world (or ``filterparent`` is disabled), not an ``<exclude>`` body
    pair. mink applies the first three, and drops the world's children too.
    """
    body = model.geom_bodyid
    body_a, body_b = body[a], body[b]
    keep = mover[body_a] != mover[body_b]
    contype, conaffinity = model.geom_contype, model.geom_conaffinity
    keep &= ((contype[a] & conaffinity[b]) | (contype[b] & conaffinity[a])) != 0
    weld = model.body_weldid
    weld_a, weld_b = weld[body_a], weld[body_b]
    keep &= weld_a != weld_b
    if not model.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_FILTERPARENT:
        parent_a, parent_b = weld[model.body_parentid[weld_a]], weld[model.body_parentid[weld_b]]
        keep &= ~(((parent_a == weld_b) | (parent_b == weld_a)) & (weld_a != 0) & (weld_b != 0))
    if model.nexclude:
        signature = (np.minimum(body_a, body_b) << 16) + np.maximum(body_a, body_b)
        keep &= ~np.isin(signature, model.exclude_signature)
    low, high = np.minimum(a, b)[keep], np.maximum(a, b)[keep]
    return list(zip(low.tolist(), high.tolist(), strict=True))


def _geom_ids(robot: Robot, group: GeomGroup, where: str) -> list[int]:
    """Geom ids of a group of geom or body names, patterns or geom ids."""
    if isinstance(group, str | int | np.integer):
        group = [group]
    if not isinstance(group, Sequence) or not group:
        raise InvalidInput(f"{where}: a geom group is a non-empty list of names, got {group!r}")
    ids: list[int] = []
    for name in group:
        ids.extend(_named_geoms(robot, name, where))
    return ids


def _named_geoms(robot: Robot, name: str | int, where: str) -> list[int]:
    """Geom ids of one entry of a group: a geom id, a pattern, a geom name or a body name."""
    model = robot.model
    if isinstance(name, int | np.integer) and not isinstance(name, bool):
        if not 0 <= name < model.ngeom:
            raise ModelError(f"{where}: no geom {name} in {robot.name!r} ({model.ngeom} geoms)")
        return [int(name)]
    if not isinstance(name, str):
        raise InvalidInput(f"{where}: a geom group holds names or geom ids, got {name!r}")
    if any(char in name for char in "*?["):
        matched = [
            g
            for g in range(model.ngeom)
            if fnmatch.fnmatchcase(
                mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, g) or "", name
            )
            or fnmatch.fnmatchcase(
                mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, model.geom_bodyid[g]) or "",
                name,
            )
        ]
        if not matched:
            raise ModelError(f"{where}: no geom or body matches {name!r} in {robot.name!r}")
        return matched
    geom = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, name)
    if geom >= 0:
        return [geom]
    body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, name)
    if body < 0:
        raise ModelError(f"{where}: no geom or body named {name!r} in model {robot.name!r}")
    body_geoms = np.flatnonzero(model.geom_bodyid == body).tolist()
    if not body_geoms:
        raise ModelError(f"{where}: body {name!r} has no geom")
    return body_geoms
