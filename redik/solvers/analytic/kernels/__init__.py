"""Compiled closed forms of the 6-joint classes of :mod:`redik.solvers.analytic.geometry`.

One module per family of classes: :mod:`.spherical` (a spherical wrist after two intersecting
axes, two parallel axes, a general shoulder, or a sliding third joint), :mod:`.parallel`
(three parallel axes, with or without a wrist point); :mod:`.wrist` solves the spherical wrist
they share and :mod:`.slots` holds the slot conventions. Each class has one compiled entry
(:func:`.spherical.solve_spherical` and so on) that runs its kernel and
:func:`redik.solvers.analytic.finish.finish`, compiled on first use only.
"""

# Each class's ``solve_<class>`` and ``batch_<class>`` are written out rather than made by one
# driver that takes the kernel and its label rule: numba keys its on-disk cache of a closure
# (or of a function taking a kernel as an argument) on the captured dispatchers' per-process
# ids, so such a driver is compiled again in every process, and a driver that selects the
# kernel by a ``numba.literally`` class code pays the literal dispatch, which costs more than the
# closed form itself, on each call.
