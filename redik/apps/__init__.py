"""Applications built on the solvers.

Timed paths (:mod:`~redik.apps.trajectory`), headless simulation (:mod:`~redik.apps.sim`),
rendering and plots (:mod:`~redik.apps.render`, :mod:`~redik.apps.plot`,
:mod:`~redik.apps.selfmotion_plot`), workspace analysis (:mod:`~redik.apps.workspace`), spec
scripts (:mod:`~redik.apps.specs`), regression scenes (:mod:`~redik.apps.regress`), the demo,
the benchmarks (:mod:`~redik.apps.bench`) and the ``redik`` command line
(:mod:`~redik.apps.cli`).
"""

from redik.core.lazy import lazy_submodules

__getattr__ = lazy_submodules(__name__)
