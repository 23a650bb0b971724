r"""The self-motion manifold of a pose: every joint configuration that reaches it.

An arm with ``n`` joints reaches a pose (6 constraints) at generic points with a manifold
of dimension ``d = n − 6`` of configurations (∞^(n−6)): a set of closed curves for a 7R
arm (Burdick 1989, *On the inverse kinematics of redundant manipulators*), a surface for
an 8R arm, isolated points for a 6R arm. Joint limits cut curves into arcs and surfaces
into patches. :func:`explore_self_motion` samples that set:

1. **Seeds.** Inverse kinematics from many random starts (:func:`redik.solve_pose`) gives
   points on every component whose basin of attraction one start falls into; each is
   projected onto the pose to full precision by the corrector below.
2. **Corrector.** Gauss–Newton on the pose error with the minimum-norm step, which is
   orthogonal to ``ker J`` so a corrected prediction does not slide along the manifold
   (:mod:`redik.solvers.redundancy.corrector`: one point at a time, or a whole covering frontier at
   once with :mod:`redik.solvers.batch`'s vectorised kinematics).
3. **Tracing, d = 1** (pseudo-arclength continuation; Allgower & Georg, *Introduction to
   Numerical Continuation Methods*, ch. 2): predictor ``q + h t`` along the unit null
   vector ``t`` of ``J_b`` (its sign kept continuous, ``t_k · t_{k−1} > 0``), corrector back
   onto the pose, step ``h`` adapted so consecutive samples are at most ``spacing`` apart
   and the tangent turns by less than 45°. A branch ends when it returns within ``spacing``
   of its seed heading the same way (a closed loop), or at a joint limit: the last sample
   is then placed *on* the limit by correcting with the offending joint frozen there, and
   the other direction is traced from the seed.
4. **Covering, d = 2**: breadth-first continuation over the tangent plane (in the spirit of
   Henderson's multiple-parameter continuation, 2002), like the curves on the torus of hinge
   angles with the limits ignored, so that one seed anywhere on a surface reaches every
   patch the limits cut from it. Each generation of the frontier predicts points ``h`` away
   in six directions 60° apart of ``ker J``; the predictions not within ``0.75 h`` of a node
   are corrected together, and kept as nodes unless the corrector jumped or a node (or an
   earlier prediction of the same generation) already lies within ``0.75 h``. KD-trees on
   the torus stop re-covering. ``h = 0.7 · spacing`` inside and near the limits, up to
   0.6 rad far outside them (never more than 0.9 × the limit violation, so no patch inside
   the limits fits between coarse nodes). The nodes inside the limits are kept as samples,
   with a point placed *on* the limit between each inside node and its nearest outside
   neighbour; the samples fall into patches (components) joined by neighbours at most
   ``spacing`` apart.
5. **Components.** A seed farther than one step from every node traced or covered so far
   (on the torus) starts new components; one closer is already covered.

Distances are Euclidean in joint space (rad and m), angles of periodic hinges (a range of
2π or more: unlimited ones, a UR5e's ±2π; :mod:`redik.core.conventions`) compared modulo
2π. Such a hinge has several in-range angles for one point of the torus; the manifold is
sampled at one of them (:meth:`Corrector.shift_into_limits
<redik.solvers.redundancy.corrector.Corrector.shift_into_limits>`), not at every turn.
Frames and twists follow :mod:`redik.core.conventions`.

The package: :mod:`.result` (:class:`SelfMotion`), :mod:`.explore` (seeds, components,
:func:`explore_self_motion`), :mod:`.tracing` (curves), :mod:`.covering` (surfaces),
:mod:`.index` (joint-space metric and nearest-sample index).
"""

from redik.solvers.redundancy.selfmotion.explore import (
    DEFAULT_SPACING,
    MAX_DIMENSION,
    explore_self_motion,
)
from redik.solvers.redundancy.selfmotion.result import SelfMotion

__all__ = ["DEFAULT_SPACING", "MAX_DIMENSION", "SelfMotion", "explore_self_motion"]
