"""The foundation every other layer stands on.

* :mod:`~redik.core.exceptions` — errors and warnings;
* :mod:`~redik.core.conventions` — the conventions written once: frames, twist order, units,
  quaternion order;
* :mod:`~redik.core.result` — the result record and the :class:`~redik.core.result.Status`
  of every solver;
* :mod:`~redik.core.validate` — checks of arguments at the public boundary;
* :mod:`~redik.core.rotation_policy` — the one tolerance for rotations and poses;
* :mod:`~redik.core.lazy` — the import of a package's modules on first use;
* :mod:`~redik.core.kernel_cache` — numba's disk cache of the kernels, stamped by what they
  import (registered here, before any module of redik defines a kernel).

Nothing here imports another part of redik.
"""

from redik.core.kernel_cache import register
from redik.core.lazy import lazy_submodules

register()
__getattr__ = lazy_submodules(__name__)
