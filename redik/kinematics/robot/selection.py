"""Which joints of a MuJoCo model a robot moves: the chain to a frame, or names and patterns.

A chain moves the hinge and slide joints on the path from the world to one body
(:func:`chain_joints`); a whole-model robot moves the joints its ``joints=`` argument names,
as names or ``fnmatch`` patterns (:func:`selected_joints`). Both leave out the joints named in
``fixed=``. A pattern that matches nothing is an error, never a silent no-op: a typo would
otherwise move, or hold, nothing.
"""

from __future__ import annotations

import fnmatch
from collections.abc import Sequence

import mujoco

from redik.core.exceptions import InvalidInput, ModelError

FREE, BALL, SLIDE, HINGE = (
    int(mujoco.mjtJoint.mjJNT_FREE),
    int(mujoco.mjtJoint.mjJNT_BALL),
    int(mujoco.mjtJoint.mjJNT_SLIDE),
    int(mujoco.mjtJoint.mjJNT_HINGE),
)
CHAIN_JOINT_TYPES = (HINGE, SLIDE)
"""The joint types a serial chain moves."""

JOINT_TYPE_NAMES = {FREE: "free", BALL: "ball", SLIDE: "slide", HINGE: "hinge"}


def joint_name(model: mujoco.MjModel, joint: int) -> str:
    """The joint's name, or ``joint<id>`` for an unnamed one."""
    return mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, joint) or f"joint{joint}"


def literal(name: str) -> str:
    """An ``fnmatch`` pattern matching exactly ``name`` (``*``, ``?``, ``[`` escaped)."""
    return "".join(f"[{char}]" if char in "*?[" else char for char in name)


def match_joints(
    model: mujoco.MjModel, patterns: Sequence[str], argument: str, robot_name: str
) -> list[int]:
    """Ids of the joints whose name equals or ``fnmatch``-es one of ``patterns``.

    Raises:
        InvalidInput: ``patterns`` is not a name, a pattern or a list of them.
        ModelError: a pattern matches no joint (a typo would otherwise move, or fix,
            nothing).
    """
    if isinstance(patterns, str):
        patterns = [patterns]
    if not isinstance(patterns, (list, tuple, set, frozenset)):
        raise InvalidInput(
            f"{argument} must be 'all', a joint name or pattern, or a list of them; got "
            f"{patterns!r}"
        )
    names = [joint_name(model, j) for j in range(model.njnt)]
    selected: list[int] = []
    for pattern in patterns:
        if not isinstance(pattern, str):
            raise InvalidInput(f"{argument} holds joint names or patterns, got {pattern!r}")
        hits = [j for j, name in enumerate(names) if fnmatch.fnmatchcase(name, pattern)]
        if not hits:
            raise ModelError(
                f"{argument}: no joint of model {robot_name!r} matches {pattern!r}; joints: {names}"
            )
        selected.extend(hits)
    return sorted(set(selected))


def selected_joints(
    model: mujoco.MjModel,
    joints: str | Sequence[str],
    fixed: Sequence[str] | None,
    fixed_ids: set[int],
    robot_name: str,
) -> list[int]:
    """Ids of the joints a whole-model robot moves, in model order.

    ``joints`` (``"all"``, or names and patterns) minus ``fixed`` (whose ids
    :func:`match_joints` gave as ``fixed_ids``).

    Raises:
        InvalidInput: a joint is named (not matched by a pattern) in both arguments.
        ModelError: a pattern matches nothing, or no joint is left to move.
    """
    selected = (
        range(model.njnt)
        if isinstance(joints, str) and joints == "all"
        else match_joints(model, [joints] if isinstance(joints, str) else joints, "joints",
                          robot_name)
    )  # fmt: skip
    named_both = sorted(_exact_names(joints) & _exact_names(fixed))
    if named_both:
        raise InvalidInput(
            f"joints {named_both} are named both in joints= (to move) and in fixed= "
            "(to hold); name each in one of them"
        )
    joint_ids = sorted(set(selected) - fixed_ids)
    if not joint_ids:
        raise ModelError(
            f"no joint left to move in model {robot_name!r} (joints={joints!r}, fixed={fixed!r})"
        )
    return joint_ids


def chain_joints(model: mujoco.MjModel, body: int, fixed: set[int], robot_name: str) -> list[int]:
    """Hinge and slide joints on the path from the world to ``body``, root first.

    Except the ``fixed`` ones (ids).

    A free joint on the path is the floating base: it stays where ``qpos`` puts it. A ball
    joint cannot be part of a serial chain of hinges and slides; it must be fixed
    explicitly (or the robot built with ``joints=``), never silently frozen.

    Raises:
        ModelError: an unfixed ball joint lies on the path.
    """
    joints: list[int] = []
    while body > 0:
        start, count = model.body_jntadr[body], model.body_jntnum[body]
        body_joints = []
        for j in range(start, start + count):
            if j in fixed:
                continue
            joint_type = int(model.jnt_type[j])
            if joint_type == BALL:
                raise ModelError(
                    f"ball joint {joint_name(model, j)!r} lies on the chain to body "
                    f"{mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, body)!r} of model "
                    f"{robot_name!r}: a serial chain moves hinges and slides only. Build a "
                    f"whole-model robot (joints='all') to move it, or pass "
                    f"fixed=[{joint_name(model, j)!r}] to hold it"
                )
            if joint_type in CHAIN_JOINT_TYPES:
                body_joints.append(j)
        joints[:0] = body_joints
        body = int(model.body_parentid[body])
    return joints


def _exact_names(patterns: str | Sequence[str] | None) -> set[str]:
    """The entries of a joints= or fixed= argument that are names, not patterns."""
    if patterns is None or patterns == "all":
        return set()
    if isinstance(patterns, str):
        patterns = [patterns]
    return {p for p in patterns if isinstance(p, str) and not any(c in p for c in "*?[")}
