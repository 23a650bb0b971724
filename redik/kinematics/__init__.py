"""The kinematics layer: a robot's FK and Jacobians, in forms tested equal to each other.

* :mod:`~redik.kinematics.robot` — :class:`~redik.kinematics.robot.Robot`, MuJoCo's FK and
  Jacobians (``mj_kinematics``, ``mj_jacSite``): the reference every other form is tested
  against. Jacobians in the ``"space"`` and ``"body"`` references come from the ``"world"``
  one by :func:`redik.lie.world_jacobian_to`; ``Robot.periodic`` marks the joints taken
  modulo 2π (:func:`redik.lie.periodic_coordinates`).
* :mod:`~redik.kinematics.chain` — :class:`~redik.kinematics.chain.Chain`, the serial chain
  folded into constant transforms, for the fast paths below.
* :mod:`~redik.kinematics.batched` — FK and Jacobians of a chain over a batch, in numpy
  (``tests/test_batch_kinematics.py``: equal to MuJoCo's).
* :mod:`~redik.kinematics.compiled` — FK, world Jacobian and pose error of one target,
  compiled (``tests/test_batch_kernel.py``: equal to MuJoCo's and to
  :func:`redik.lie.rotation_log`).

A DH table's own FK, :func:`redik.models.dh.forward`, is the reference the MJCF built from the
table is tested against (``tests/test_model_builder.py``). Frames, twists and units follow
:mod:`redik.core.conventions`. The layer sits below the solvers (docs/architecture.md) so that
every solver can use it; it computes kinematics only.
"""

from redik.core.lazy import lazy_submodules

__getattr__ = lazy_submodules(__name__)
