"""The compiled step of a :class:`~redik.qp.Problem` whose stack it supports.

:func:`compiled_plan` decides and builds (:mod:`redik.qp.compiled.plan`, which lists what a
plan supports and how a step runs); the kernels live one concept per module: the objective
and frame Jacobians (:mod:`~redik.qp.compiled.frames`), the box and level 0's minimiser
(:mod:`~redik.qp.compiled.level0`), the box QP (:mod:`~redik.qp.compiled.box_qp`), level 1 in
level 0's null space (:mod:`~redik.qp.compiled.lower_level`), collision rows
(:mod:`~redik.qp.compiled.collision`), DAQP's workspaces (:mod:`~redik.qp.compiled.workspaces`)
and the small dense algebra they share (:mod:`~redik.qp.compiled.linalg`).
"""

from redik.qp.compiled.plan import CompiledPlan, compiled_plan

__all__ = ["CompiledPlan", "compiled_plan"]
