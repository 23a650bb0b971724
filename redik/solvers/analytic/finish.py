r"""What every compiled closed form does after its kernel: verify, polish, select.

A class entry (:mod:`.kernels`) runs ``begin`` → its kernel → :func:`verify` → its label rule
(:mod:`.labels`) → :func:`select`, in one compiled call that returns a (k, :data:`WIDTH`)
array: the six joint values in the robot's order, then the label code (plus
:data:`SINGULAR_CODE` for a singular row), the slot's status, its free joint, the slot and the
stage at which it failed (columns :data:`Q` … :data:`STAGE`).

- **Verify.** Every slot's forward kinematics (:func:`redik.solvers.analytic.chain.fk_error`)
  must reach the target within the plan's ``verify`` tolerance; a slot within
  :data:`POLISH_RANGE` but above rounding is first polished by Gauss–Newton
  (:func:`redik.solvers.analytic.chain.newton`), which brings a subproblem solved next to a
  singularity (SP4 with ``C ≈ ±r`` gives θ to only √ε) back to rounding.
- **Select.** Each angle is wrapped to (−π, π] and moved by the smallest multiple of 2π that
  brings it into the joint limits (a slot with no such representative is dropped), and a slot
  equal to an earlier one (within ``duplicate``, per joint, angles modulo 2π) is dropped:
  :func:`shift_into` and :func:`same_joints`, the one selection rule of every closed form
  (:func:`select_rows` applies it to the small solvers' results).

The ``plan`` holds everything but the target in one array (one argument keeps a call
cheap): the (19, 3) geometry, the lower and upper limits (in the robot's joint order), then
:data:`REVERSE`, :data:`TOL`, :data:`VERIFY`, :data:`DUPLICATE`, and what a call asks beyond
the solutions: :data:`FIX_JOINT` (a joint a singular family fixes, or −1) at
:data:`FIX_VALUE`, :data:`KEEP_ALL` (every slot, unfiltered) and :data:`LABELLED` (label codes
computed and rows in their order; without, the label column is 0).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from redik.core.rotation_policy import ROTATION_TOLERANCE
from redik.kinematics.compiled import COMPILE, valid_target
from redik.solvers.analytic.chain import fk_error, inverse, is_prismatic, newton, wrap
from redik.solvers.analytic.kernels.slots import EMPTY, SINGULAR

#: Entries of a plan (module docstring).
GEOMETRY_SIZE = 57
LOWER, UPPER = 57, 63
REVERSE, TOL, VERIFY, DUPLICATE = 69, 70, 71, 72
FIX_JOINT, FIX_VALUE, KEEP_ALL, LABELLED = 73, 74, 75, 76
PLAN_SIZE = 77

#: Columns of an entry's result (module docstring).
Q, LABEL, STATUS, FREE, SLOT, STAGE = 0, 6, 7, 8, 9, 10
WIDTH = 11

#: Added to the label code of a singular row, so that a lookup of the code fails there.
SINGULAR_CODE = 64

#: A slot whose FK error lies in (POLISH_ABOVE, POLISH_RANGE] is polished, by at most
#: POLISH_STEPS Gauss–Newton steps, stopping once the error is POLISH_ABOVE or less.
POLISH_ABOVE = 1e-13
POLISH_RANGE = 1e-3
POLISH_STEPS = 4

_TWO_PI = 2.0 * math.pi


@numba.njit(**COMPILE)
def begin(T, plan):
    """Read a plan and check the target.

    ``(valid, target, G, tol, fix_joint, fix_value)``: whether ``T`` is a 4 × 4 finite rigid
    transform to use as it is (:func:`redik.kinematics.compiled.valid_target` at the rotation
    policy's tolerance), the target the chain is solved for (``T⁻¹`` for a chain run
    backwards), the geometry, the subproblems' tolerance and the chain's fixed joint.
    """
    G = plan[:GEOMETRY_SIZE].reshape(19, 3)
    fix_joint, reverse = int(plan[FIX_JOINT]), plan[REVERSE] != 0.0
    if fix_joint >= 0 and reverse:
        fix_joint = 5 - fix_joint
    valid = T.shape[0] == 4 and T.shape[1] == 4 and valid_target(T, ROTATION_TOLERANCE)
    if not valid:
        return False, np.eye(4), G, plan[TOL], fix_joint, plan[FIX_VALUE]
    target = inverse(T) if reverse else T
    return True, target, G, plan[TOL], fix_joint, plan[FIX_VALUE]


@numba.njit(**COMPILE)
def labelled(plan):
    """Whether the call asks for label codes."""
    return plan[LABELLED] != 0.0


@numba.njit(**COMPILE)
def verify(target, G, plan, q, status, free, stage):
    """Verify every slot by forward kinematics, polishing the near ones.

    Empty every slot whose FK misses ``target`` by more than the plan's ``verify``
    tolerance (stage 4), after polishing the slots within reach (module docstring).
    """
    for slot in range(q.shape[0]):
        if status[slot] == EMPTY:
            continue
        error = fk_error(G, q[slot], target)
        if POLISH_ABOVE < error <= POLISH_RANGE:
            error = newton(G, q[slot], target, free[slot], POLISH_STEPS, POLISH_ABOVE)
        if error > plan[VERIFY]:
            status[slot], stage[slot] = EMPTY, 4


@numba.njit(**COMPILE)
def shift_into(value, lower, upper, tol):
    """Move an angle by whole turns into its limits.

    An angle moved by the smallest multiple of 2π into ``[lower, upper]``, and whether
    there is one (a value outside by at most ``tol`` is clipped onto the limit).
    """
    if lower <= value <= upper:
        return value, True
    # The turns k with lower ≤ q + 2πk ≤ upper run from ceil((lower − q)/2π) to
    # floor((upper − q)/2π); the one nearest 0 is the smallest shift.
    turns = min(max(np.ceil((lower - value) / _TWO_PI), 0.0), np.floor((upper - value) / _TWO_PI))
    shifted = value + _TWO_PI * turns
    clipped = min(max(shifted, lower), upper)
    return clipped, abs(clipped - shifted) <= tol


@numba.njit(**COMPILE)
def same_joints(a, b, revolute, tol):
    """Whether two joint vectors agree within ``tol`` per joint, angles modulo 2π."""
    for j in range(a.shape[0]):
        difference = a[j] - b[j]
        if revolute[j]:
            difference = wrap(difference)
        if abs(difference) >= tol:
            return False
    return True


@numba.njit(**COMPILE)
def _place(values, revolute, lower, upper, tol):
    """Wrap and shift a joint vector into the limits in place; whether it fits."""
    for j in range(values.shape[0]):
        if revolute[j]:
            values[j], inside = shift_into(wrap(values[j]), lower[j], upper[j], tol)
        else:
            inside = lower[j] - tol <= values[j] <= upper[j] + tol
            values[j] = min(max(values[j], lower[j]), upper[j])
        if not inside:
            return False
    return True


@numba.njit(**COMPILE)
def select_rows(q, revolute, lower, upper, dedupe, tol):
    """The selection rule on rows of joint values.

    The selection rule on a (k, n) ``q`` in place: each row wrapped and shifted into the
    limits, and, when ``dedupe``, dropped if equal to an earlier kept row. Returns which rows
    are kept.
    """
    keep = np.zeros(q.shape[0], np.bool_)
    for r in range(q.shape[0]):
        if not _place(q[r], revolute, lower, upper, tol):
            continue
        keep[r] = True
        if dedupe:
            for other in range(r):
                if keep[other] and same_joints(q[other], q[r], revolute, tol):
                    keep[r] = False
                    break
    return keep


@numba.njit(**COMPILE)
def _robot_row(plan, q, status, free, stage, codes, slot, out, r):
    """Write one slot as a result row.

    Write slot ``slot`` into row ``r`` of ``out`` in the robot's joint order (the joint
    values only when ``out`` has 6 columns).
    """
    reverse = plan[REVERSE] != 0.0
    for j in range(6):
        out[r, Q + j] = q[slot, 5 - j if reverse else j]
    if out.shape[1] == 6:
        return
    out[r, LABEL] = codes[slot] + (SINGULAR_CODE if status[slot] == SINGULAR else 0)
    out[r, STATUS] = status[slot]
    out[r, FREE] = 5 - free[slot] if reverse and free[slot] >= 0 else free[slot]
    out[r, SLOT] = slot
    out[r, STAGE] = stage[slot]


@numba.njit(**COMPILE)
def _revolute(G, plan):
    """Which robot joints are angles."""
    reverse = plan[REVERSE] != 0.0
    revolute = np.empty(6, np.bool_)
    for j in range(6):
        revolute[j] = not is_prismatic(G, 5 - j if reverse else j)
    return revolute


@numba.njit(**COMPILE)
def select(G, plan, q, status, free, stage, codes):
    """The entry's result rows.

    The entry's result (module docstring): the non-empty slots moved into the limits,
    without duplicates, in label order; with ``keep_all`` every slot in slot order, wrapped
    only (for a family member or the reason of an empty result). Without labels and
    ``keep_all``, the joint values alone: (k, 6).
    """
    keep_all = plan[KEEP_ALL] != 0.0
    out = np.empty((q.shape[0], WIDTH if keep_all or labelled(plan) else 6))
    revolute = _revolute(G, plan)
    lower, upper = plan[LOWER : LOWER + 6], plan[UPPER : UPPER + 6]
    count = 0
    for slot in range(q.shape[0]):
        if status[slot] == EMPTY and not keep_all:
            continue
        _robot_row(plan, q, status, free, stage, codes, slot, out, count)
        values = out[count, Q : Q + 6]
        if keep_all:
            for j in range(6):
                values[j] = wrap(values[j]) if revolute[j] else values[j]
            count += 1
            continue
        if not _place(values, revolute, lower, upper, plan[DUPLICATE]):
            continue
        repeated = False
        for other in range(count):
            if same_joints(out[other, Q : Q + 6], values, revolute, plan[DUPLICATE]):
                repeated = True
                break
        if not repeated:
            count += 1
    if labelled(plan) and not keep_all:
        _sort_by_label(out, count)
    return out[:count]


@numba.njit(**COMPILE)
def _sort_by_label(out, count):
    """Order the first ``count`` rows by label code (insertion sort: at most 16 rows)."""
    for i in range(1, count):
        j = i
        while j > 0 and out[j, LABEL] < out[j - 1, LABEL]:
            for c in range(WIDTH):
                out[j, c], out[j - 1, c] = out[j - 1, c], out[j, c]
            j -= 1


@numba.njit(**COMPILE)
def invalid():
    """The result for a target that is not a rigid transform to use as it is: no columns."""
    return np.empty((0, 0))


@numba.njit(**COMPILE)
def scatter_slots(G, plan, q, status, codes, b, out_q, valid, singular):
    """Write target ``b``'s verified slots into a batch by label code.

    Each slot is moved into the limits as :func:`select` does (dropped if it has no
    representative there); the first slot of a code is kept.
    """
    revolute = _revolute(G, plan)
    lower, upper = plan[LOWER : LOWER + 6], plan[UPPER : UPPER + 6]
    reverse = plan[REVERSE] != 0.0
    values = np.empty(6)
    for slot in range(q.shape[0]):
        code = codes[slot]
        if status[slot] == EMPTY or valid[b, code]:
            continue
        for j in range(6):
            values[j] = q[slot, 5 - j if reverse else j]
        if not _place(values, revolute, lower, upper, plan[DUPLICATE]):
            continue
        out_q[b, code] = values
        valid[b, code] = True
        singular[b, code] = status[slot] == SINGULAR
