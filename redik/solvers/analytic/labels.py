r"""Names of the solutions of a 6-joint arm, computed from each solution's own geometry.

A label is an integer code per solution, computed inside the compiled call from the world
axes :math:`ω_i` and points at that solution (each sign in the frame where it takes fewest
rotations: signs of triple products do not change under a rigid motion), and mapped to words
by the class's vocabulary (:data:`VOCABULARIES`). Nothing
depends on how the subproblems happened to order their roots, so the same configuration gets
the same name whichever solver found it.

Arms with a shoulder, an elbow and a wrist point (``spherical_two_intersecting``,
``spherical_two_parallel``, ``three_parallel_two_intersecting``):
``"{left|right}-{up|down}-{noflip|flip}"``, with ``o`` the foot on axis 1 of its common normal
with axis 2 (the shoulder point where they meet) and ``w`` the wrist
point (the wrist centre; for the three-parallel class the point where axes 5 and 6 meet):

- *left*: the lateral offset ``ℓ = ((w − o)·ω₂) ω₂`` lies to the left of the vertical plane
  through axis 1 and ``w``, seen from the base: :math:`ℓ·(ω_1 × (w - o)) > 0`; with no offset
  (ℓ = 0), *left* when the wrist point is in front: :math:`(w - o)·(ω_2 × ω_1) > 0`;
- *up*: the planar two-link made by axis 2 (its point ``s`` nearest axis 1), axis 3 (``e``,
  nearest axis 2) and its end ``x`` (the wrist centre; a point of axis 4 for the
  three-parallel class) turns about ω₂ the way that equals *left*:
  :math:`(((e - s) × (x - s))·ω_2 > 0) = \text{left}`;
- *noflip*: :math:`(ω_4 × ω_6)·ω_5 \ge 0`, the sine of the middle wrist angle (θ5 ∈ [0, π]
  for a ZYZ wrist).

For the PUMA 560 these are Craig's and Paul's words (left/right arm, elbow up/down, wrist
flip); for the UR arms Hawkins' and Andersen's. The Stanford class
(``spherical_two_intersecting_prismatic``): ``"{left|right}-{out|in}-{noflip|flip}"``, *out*
when the wrist centre lies ahead of the shoulder along the slide, :math:`(w - o)·ω_3 > 0`.

An arm solved backwards (a spherical *shoulder*: the class is its tool-to-base chain's) is
labelled by the same rules read on that chain, its tool taken as the base.

The classes without such a shoulder number their arm solutions by increasing first angle of
the chain as solved: ``spherical`` ``"arm{k}-{noflip|flip}"``, ``three_parallel``
``"arm{k}-{up|down}"`` (*up* when the two-link of axes 2, 3, 4 turns positively about their
common direction).
"""

from __future__ import annotations

import numba

from redik.kinematics.compiled import COMPILE
from redik.solvers.analytic.chain import AXES, POINTS, TIP, target_of
from redik.solvers.analytic.kernels.slots import EMPTY
from redik.solvers.analytic.vectors import add, cross, dot, mul, norm, rotate_cs, row, scale, sub

#: Below this (relative to the arm's size) the lateral offset counts as none.
OFFSET_TOL = 1e-9


def _words(*parts: tuple[str, ...]) -> tuple[str, ...]:
    """Every combination, the first part varying slowest (code = binary digits)."""
    names: tuple[str, ...] = ("",)
    for words in parts:
        names = tuple(f"{name}-{word}" if name else word for name in names for word in words)
    return names


_ARMS = tuple(f"arm{k}" for k in range(1, 5))

#: The names of the label codes, per class.
VOCABULARIES = {
    "spherical_two_intersecting": _words(("left", "right"), ("up", "down"), ("noflip", "flip")),
    "spherical_two_parallel": _words(("left", "right"), ("up", "down"), ("noflip", "flip")),
    "three_parallel_two_intersecting": _words(
        ("left", "right"), ("up", "down"), ("noflip", "flip")
    ),
    "spherical_two_intersecting_prismatic": _words(
        ("left", "right"), ("out", "in"), ("noflip", "flip")
    ),
    "spherical": _words(_ARMS, ("noflip", "flip")),
    "three_parallel": _words(_ARMS, ("up", "down")),
}


@numba.njit(**COMPILE)
def _closest(p1, u1, p2, u2):
    """The point of the line ``(p1, u1)`` closest to the line ``(p2, u2)`` (p1 if parallel)."""
    w = sub(p1, p2)
    b = dot(u1, u2)
    denominator = 1.0 - b * b
    if denominator < 1e-24:
        return p1
    return add(p1, scale(u1, (b * dot(u2, w) - dot(u1, w)) / denominator))


@numba.njit(**COMPILE)
def _flip(G, slot):
    r"""Whether the wrist flips.

    1 for a *flip* wrist, 0 for *noflip*: the sign of :math:`(ω_4 × ω_6)·ω_5`, which in the
    frame after joints 1–4 is :math:`(h_4 × \mathrm{rot}(h_5, θ_5) h_6)·h_5`.
    """
    h4, h5, h6 = row(G, AXES + 3), row(G, AXES + 4), row(G, AXES + 5)
    last = rotate_cs(h5, slot[10], slot[16], h6)
    return 0 if dot(cross(h4, last), h5) >= 0.0 else 1


@numba.njit(**COMPILE)
def _shoulder_frame(target, G, wrist_point):
    """What the shoulder rule needs of a target.

    What the shoulder rule needs of a target, in the chain's frame at q = 0:
    ``(o, s, e0, w − a1)``, the feet of the common normals of axes 1–2 on axis 1 (``o``) and
    on axis 2 (``s``), of axes 2–3 on axis 3 at q = 0 (``e0``), and the wrist point (row
    ``wrist_point`` of ``G`` carried to the target) relative to ``a1``.
    """
    z0, z1, z2, p = target_of(target, G)
    a1, a2, a3 = row(G, POINTS), row(G, POINTS + 1), row(G, POINTS + 2)
    h1, h2, h3 = row(G, AXES), row(G, AXES + 1), row(G, AXES + 2)
    w = sub(p, mul(z0, z1, z2, sub(row(G, TIP), row(G, POINTS + wrist_point))))
    o = _closest(a1, h1, a2, h2)
    return o, _closest(a2, h2, a1, h1), _closest(a3, h3, a2, h2), sub(w, a1)


@numba.njit(**COMPILE)
def _left(G, slot, frame, size):
    """Whether the shoulder is on the left.

    Whether the shoulder is on the *left* (module docstring), evaluated in the frame that
    undoes joint 1 (a rotation about axis 1, which keeps ``o``, ω1 and every sign).
    """
    o, _, _, w = frame
    h1, h2 = row(G, AXES), row(G, AXES + 1)
    d = sub(add(row(G, POINTS), rotate_cs(h1, slot[6], -slot[12], w)), o)
    lateral = dot(d, h2)
    if abs(lateral) > OFFSET_TOL * size:
        return lateral * dot(h2, cross(h1, d)) > 0.0
    return dot(d, cross(h2, h1)) > 0.0


@numba.njit(**COMPILE)
def _elbow_end(G, slot, frame, end_on_axis4):
    """The end of the elbow's two-link.

    The two-link's end ``x`` in the frame that undoes joint 1: the wrist point, or the
    point of axis 4 carried by joints 2 and 3.
    """
    h1, h2, h3 = row(G, AXES), row(G, AXES + 1), row(G, AXES + 2)
    a1, a2, a3, a4 = row(G, POINTS), row(G, POINTS + 1), row(G, POINTS + 2), row(G, POINTS + 3)
    if not end_on_axis4:
        return add(a1, rotate_cs(h1, slot[6], -slot[12], frame[3]))
    inner = add(sub(a3, a2), rotate_cs(h3, slot[8], slot[14], sub(a4, a3)))
    return add(a2, rotate_cs(h2, slot[7], slot[13], inner))


@numba.njit(**COMPILE)
def shoulder_elbow_wrist(target, G, q, status, wrist_point, end_on_axis4, codes):
    """Label codes ``4·right + 2·down + flip`` of the non-empty slots (module docstring).

    Every sign is evaluated in the frame that undoes joint 1: axis 2 is then ``(a2, h2)``,
    axis 3 ``(a2 + R2(a3 − a2), R2 h3)``, and the foot ``e`` of the common normal of axes 2
    and 3 is ``a2 + R2(e0 − a2)``.

    Args:
        target: The target the chain is solved for.
        G: The packed chain.
        q: The slot rows (S, 18).
        status: (S,) which slots are empty.
        wrist_point: The row of the wrist point among ``G``'s points (3: the wrist centre;
            4: the point where axes 5 and 6 meet).
        end_on_axis4: Whether the two-link ends on axis 4 (the three-parallel class) rather
            than at the wrist point.
        codes: (S,) written.
    """
    frame = _shoulder_frame(target, G, wrist_point)
    size = size_of(G)
    h2, a2 = row(G, AXES + 1), row(G, POINTS + 1)
    for slot in range(q.shape[0]):
        if status[slot] == EMPTY:
            continue
        left = _left(G, q[slot], frame, size)
        s = frame[1]
        e = add(a2, rotate_cs(h2, q[slot, 7], q[slot, 13], sub(frame[2], a2)))
        x = _elbow_end(G, q[slot], frame, end_on_axis4)
        up = (dot(cross(sub(e, s), sub(x, s)), h2) > 0.0) == left
        codes[slot] = 4 * (0 if left else 1) + 2 * (0 if up else 1) + _flip(G, q[slot])


@numba.njit(**COMPILE)
def shoulder_slide_wrist(target, G, q, status, codes):
    """Label codes of the Stanford class.

    Label codes ``4·right + 2·in + flip`` of the Stanford class (module docstring): *out*
    when :math:`(w - o)·ω_3 > 0`, in the frame that undoes joint 1 :math:`ω_3 = R_2 h_3`.
    """
    frame = _shoulder_frame(target, G, 3)
    size = size_of(G)
    h1, h2, h3 = row(G, AXES), row(G, AXES + 1), row(G, AXES + 2)
    for slot in range(q.shape[0]):
        if status[slot] == EMPTY:
            continue
        left = _left(G, q[slot], frame, size)
        w = add(row(G, POINTS), rotate_cs(h1, q[slot, 6], -q[slot, 12], frame[3]))
        out = dot(sub(w, frame[0]), rotate_cs(h2, q[slot, 7], q[slot, 13], h3)) > 0.0
        codes[slot] = 4 * (0 if left else 1) + 2 * (0 if out else 1) + _flip(G, q[slot])


@numba.njit(**COMPILE)
def arm_and_wrist(G, q, status, codes):
    """Label codes of the SP5 class.

    Label codes ``2·(arm − 1) + flip``: the arm solution's rank (slot pairs, in the
    kernel's order by θ1) and the wrist's flip.
    """
    for slot in range(q.shape[0]):
        if status[slot] != EMPTY:
            codes[slot] = 2 * (slot // 2) + _flip(G, q[slot])


@numba.njit(**COMPILE)
def arm_and_elbow(G, q, status, codes):
    """Label codes of the three-parallel class.

    Label codes ``2·(arm − 1) + down`` of the three-parallel class: the arm solution's rank
    and the turn of the two-link of axes 2, 3, 4 about their direction ``h``,
    :math:`((a_3 - a_2) × ((a_3 - a_2) + R_3 (a_4 - a_3)))·h` in the frame of joint 2.
    """
    h = row(G, AXES + 1)
    a2, a3, a4 = row(G, POINTS + 1), row(G, POINTS + 2), row(G, POINTS + 3)
    link = sub(a3, a2)
    for slot in range(q.shape[0]):
        if status[slot] == EMPTY:
            continue
        end = add(link, rotate_cs(h, q[slot, 8], q[slot, 14], sub(a4, a3)))
        up = dot(cross(link, end), h) > 0.0
        codes[slot] = 2 * (slot // 2) + (0 if up else 1)


@numba.njit(**COMPILE)
def size_of(G):
    """A length of the arm (m).

    A length of the arm (m): the largest distance of a kernel point or the tip from the
    first point.
    """
    first = row(G, POINTS)
    size = 0.0
    for i in range(POINTS + 1, TIP + 1):
        size = max(size, norm(sub(row(G, i), first)))
    return max(size, 1e-300)
