"""Compiled closed forms of the 6-joint classes of :mod:`redik.solvers.analytic.geometry`.

One module per family of classes: :mod:`.spherical` (a spherical wrist after two intersecting
axes, two parallel axes, a general shoulder, or a sliding third joint), :mod:`.parallel`
(three parallel axes, with or without a wrist point); :mod:`.wrist` solves the spherical wrist
they share and :mod:`.slots` holds the slot conventions. Each class has one compiled entry
(:func:`.spherical.solve_spherical` and so on) that runs its kernel and
:func:`redik.solvers.analytic.finish.finish`, compiled on first use only.
"""
