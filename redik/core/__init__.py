"""The foundation every other layer stands on.

* :mod:`~redik.core.exceptions` — errors and warnings;
* :mod:`~redik.core.conventions` — the conventions written once: frames, twist order, units,
  quaternion order;
* :mod:`~redik.core.result` — the result record and the :class:`~redik.core.result.Status`
  of every solver;
* :mod:`~redik.core.validate` — checks of arguments at the public boundary;
* :mod:`~redik.core.rotation_policy` — the one tolerance for rotations and poses;
* :mod:`~redik.core.lazy` — the import of a package's modules on first use.

Nothing here imports another part of redik.
"""

from redik.core.lazy import lazy_submodules

__getattr__ = lazy_submodules(__name__)
